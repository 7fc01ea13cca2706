"""Mapped grids on the unit interval (x in [0, 1]) and small array helpers of the time plans."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

__all__ = ["clustered", "decades", "is_in", "linspace0", "sorted_unique"]

Array = NDArray[np.float64]


def clustered(n: int, stretch: float) -> Array:
    """``n + 1`` nodes on [0, 1], clustered at both ends by a smooth tanh map.

    ``stretch = 0`` is uniform; the end spacing is ``sech(stretch)^2`` times the centre spacing.
    A smooth map keeps the 3-point stencils second order in the grid index, so results on nested
    grids (n, 2n, 4n) extrapolate (Richardson).
    """
    xi = np.linspace(0.0, 1.0, n + 1)
    if stretch <= 0:
        return xi
    x = 0.5 * (1.0 + np.tanh(stretch * (2.0 * xi - 1.0)) / np.tanh(stretch))
    x[0], x[-1] = 0.0, 1.0
    return x


def decades(stop: float, n: int) -> Array:
    """``10 ** linspace(0, stop, n)``: ``numpy.logspace(0.0, stop, n)`` bit for bit (its
    ``power`` on the same ``linspace``) without its array set-up (a few microseconds a call
    on the ``cn`` method's per-solve path)."""
    return 10.0 ** linspace0(stop, n)


def linspace0(stop: float, n: int) -> Array:
    """``numpy.linspace(0.0, stop, n)`` bit for bit (its arithmetic on a float ``stop``:
    ``arange(n) * (stop / (n - 1)) + 0.0``, the last value ``stop``) without its ~8 us of
    argument handling."""
    y = np.arange(n, dtype=np.float64)
    div = n - 1
    step = stop / div if div > 0 else math.nan
    if div > 0:
        if step == 0:  # (numpy's handling of denormal steps)
            y /= div
            y *= stop
        else:
            y *= step
    else:
        y *= stop
    if not 0.0 < step < math.inf:  # (+ start 0.0: only -0 changes, and a positive step makes none)
        y += 0.0
    if n > 1:
        y[-1] = stop
    return y


def is_in(t: Array, values: tuple[float, ...] | list[float]) -> Array:
    """``np.isin(t, values)`` for a few ``values`` (without its set-up cost)."""
    out = np.zeros(t.shape, bool)
    for v in values:
        out |= t == v
    return out


def sorted_unique(values: Array) -> Array:
    """The sorted distinct values of a fresh 1-D float array (sorted in place): what
    ``numpy.unique`` returns for finite values, without its dispatch (the ``cn`` time plans
    call it per solve)."""
    values.sort()
    keep = np.empty(values.size, dtype=bool)
    keep[:1] = True
    np.not_equal(values[1:], values[:-1], out=keep[1:])
    return values[keep]
