"""Read-only broadcast views of the engine's batch results, without ``np.broadcast_to``'s
argument handling (about 8 us a call; a few calls per solve), the positions of no upper wall
(:func:`no_wall`), per-load counts, and deferred batch fields (:class:`LazyField`)."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["NO_WALL", "LazyField", "broadcast_view", "no_wall", "per_load"]


def broadcast_view(value: Any, shape: tuple[int, ...]) -> NDArray[Any]:
    """``np.broadcast_to(value, shape)``: read-only, no copy. A 0-d or C-contiguous value whose
    shape ends ``shape`` is viewed with zero strides on the new leading axes, a C-contiguous
    one of ``shape``'s rank with zero strides on its length-1 axes; anything else goes to
    ``np.broadcast_to``."""
    arr = np.asarray(value)
    lead = len(shape) - arr.ndim
    if lead == 1 and shape[0] == 1 and arr.shape == shape[1:]:  # (one load: an added axis)
        out = arr[None]
        out.flags.writeable = False
        return out
    if lead >= 0 and tuple(shape[lead:]) == arr.shape and arr.flags.c_contiguous:
        out = np.ndarray(shape, arr.dtype, buffer=arr, strides=(0,) * lead + arr.strides)
        out.flags.writeable = False
        return out
    if (
        lead == 0
        and arr.flags.c_contiguous
        and arr.size
        and all(n == m or n == 1 for n, m in zip(arr.shape, shape, strict=True))
    ):  # (a column of loads over the outputs: its length-1 axes with zero strides)
        strides = tuple(
            0 if n != m else s for n, m, s in zip(arr.shape, shape, arr.strides, strict=True)
        )
        out = np.ndarray(shape, arr.dtype, buffer=arr, strides=strides)
        out.flags.writeable = False
        return out
    return np.broadcast_to(arr, shape)


NO_WALL = np.asarray(np.inf)  # the upper wall's position without one [Pa] (read-only)
NO_WALL.setflags(write=False)
_INF_ROW = np.full(1024, np.inf)  # its positions at up to 1024 outputs (read-only)
_INF_ROW.setflags(write=False)


def no_wall(shape: tuple[int, ...]) -> NDArray[np.float64]:
    """The positions [Pa] of no upper wall (+inf) shaped ``shape`` (loads, outputs),
    read-only: a view of one row for one load (~3 us less than a broadcast view)."""
    if len(shape) == 2 and shape[0] == 1 and shape[1] <= _INF_ROW.size:
        return _INF_ROW[None, : shape[1]]
    return broadcast_view(NO_WALL, shape)


def per_load(value: int | NDArray[Any], n: int) -> NDArray[np.int64]:
    """A count per load [1] (``(n,)`` int64, read-only) of one count or one per load."""
    if type(value) is int:  # (one count for the batch: ~1 us less than a broadcast view)
        out = np.empty(n, dtype=np.int64)
        out.fill(value)
        out.flags.writeable = False
        return out
    return broadcast_view(np.asarray(value, dtype=np.int64), (n,))


class LazyField:
    """A batch field computed on first access (e.g. the wall positions of a moving wall that
    the exact path dropped: reported when asked for, not inverted for every solve)."""

    __slots__ = ("_fn",)

    def __init__(self, fn) -> None:
        self._fn = fn

    def __call__(self):
        return self._fn()
