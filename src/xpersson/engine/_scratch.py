"""Scratch buffers of the ``cn`` march, kept per thread between solves.

The march's block arrays (operators, states) are a few MB; fresh memory of that size costs a
page fault per 4 kB on first touch, which measured ~0.3 ms per grid level of a one-load
``jkr`` solve (more than the copies themselves).  A thread keeps one buffer per name, grown
as needed (at most ~10 MB in all: the block arrays are bounded by ``_moving._BLOCK``); a
march that starts while another one in the same thread holds the pool (a progress reporter
that solves) gets fresh memory.
"""

from __future__ import annotations

import threading
from collections.abc import Iterator
from contextlib import contextmanager

import numpy as np
from numpy.typing import NDArray

__all__ = ["Pool", "pool"]

Array = NDArray[np.float64]

_LOCAL = threading.local()


class Pool:
    """Named float64 buffers: :meth:`empty` returns an uninitialised view of the one named."""

    def __init__(self, keep: bool) -> None:
        self.keep = keep
        self.bufs: dict[str, Array] = {}

    def empty(self, name: str, shape: tuple[int, ...]) -> Array:
        """An uninitialised float64 array of ``shape`` (valid until ``name`` is asked again)."""
        need = int(np.prod(shape))
        buf = self.bufs.get(name)
        if buf is None or buf.size < need:
            buf = np.empty(need)
            if self.keep:
                self.bufs[name] = buf
        return buf[:need].reshape(shape)


@contextmanager
def pool() -> Iterator[Pool]:
    """This thread's pool for the duration of a phase (a fresh one if it is in use)."""
    kept = getattr(_LOCAL, "pool", None)
    if kept is None:
        kept = _LOCAL.pool = Pool(keep=True)
    if getattr(_LOCAL, "busy", False):
        yield Pool(keep=False)
        return
    _LOCAL.busy = True
    try:
        yield kept
    finally:
        _LOCAL.busy = False
