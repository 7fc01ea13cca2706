"""Silencing the warnings of a sweep's points without leaving a trace in the process.

A sweep records what happens at each point (``point_status`` and its message), so the points'
warnings (a tolerance not met, a validity note, NumPy's floating-point notes), repeated at
thousands of points, are silenced while the points are solved. Python's warning filters are
process-wide and :class:`warnings.catch_warnings` is not thread-safe (Python 3.11): two
threads entering and leaving it in an interleaved order can leave a filter installed for the
rest of the process. So the sweep code that runs on worker threads never touches the filters;
:func:`silenced` is entered only by the thread that runs the sweep (or by the task on a dask
worker), and nested or concurrent uses share one :class:`warnings.catch_warnings` under a
lock: the first to enter installs it, the last to leave restores the filters exactly as they
were. While a sweep runs, warnings of the user's other threads are silenced too (the filters
are process-wide); they are as before once it returns.
"""

from __future__ import annotations

import threading
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

__all__ = ["silenced"]

_LOCK = threading.Lock()
_STATE: dict[str, Any] = {"depth": 0, "catch": None}


@contextmanager
def silenced() -> Iterator[None]:
    """Ignore every warning while the block runs (thread-safe among its own uses)."""
    with _LOCK:
        if _STATE["depth"] == 0:
            catch = warnings.catch_warnings()
            catch.__enter__()
            warnings.simplefilter("ignore")
            _STATE["catch"] = catch
        _STATE["depth"] += 1
    try:
        yield
    finally:
        with _LOCK:
            _STATE["depth"] -= 1
            if _STATE["depth"] == 0:
                _STATE["catch"].__exit__(None, None, None)
                _STATE["catch"] = None
