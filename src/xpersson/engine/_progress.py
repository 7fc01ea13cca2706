"""Progress of long numerical solves (the moving-wall ``cn`` path), reported as work done.

A solver calls :func:`report` with the work it has just done (node-steps: grid nodes times time
steps times loads); nothing happens unless a caller installed a reporter with
:func:`reporting`. The reporter lives in a :class:`contextvars.ContextVar`, so threads and
sweeps running in parallel never see each other's reporter, and the engine stays free of any
progress-bar library (the pipeline shows a tqdm counter on a terminal).
"""

from __future__ import annotations

import contextlib
import contextvars
from collections.abc import Callable, Iterator

__all__ = ["report", "reported", "reporting"]

_REPORTER: contextvars.ContextVar[Callable[[int], None] | None] = contextvars.ContextVar(
    "xpersson_engine_progress", default=None
)


def report(node_steps: int) -> None:
    """Report ``node_steps`` units of work just done (a no-op without a reporter)."""
    cb = _REPORTER.get()
    if cb is not None and node_steps > 0:
        cb(int(node_steps))


def reported() -> bool:
    """Whether a reporter is installed (a solver may skip its pauses to report otherwise)."""
    return _REPORTER.get() is not None


@contextlib.contextmanager
def reporting(callback: Callable[[int], None]) -> Iterator[None]:
    """Install ``callback(node_steps)`` for the solves run inside the ``with`` block."""
    token = _REPORTER.set(callback)
    try:
        yield
    finally:
        _REPORTER.reset(token)
