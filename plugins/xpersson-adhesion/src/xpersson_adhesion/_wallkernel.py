"""Optional compiled evaluation of the detachment wall (numba): ``-sqrt(max(poly(t), 0))`` of
the clipped table in one loop, the numbers of the numpy path bit for bit.

The engine evaluates the wall a dozen to two dozen times per ``jkr`` solve, at 1 to ~1000 times
each (issue 36: 0.15-0.5 ms per solve through numpy and scipy's ``PPoly`` loop, mostly per-call
overhead and a bisection per time). :func:`wall_values` does the clip, the interval search,
the local polynomial, the clip at 0, the square root and the sign in one pass, with the
operations of the numpy path in the same order:

- the clip ``np.minimum(np.maximum(t, t_lo), t_hi)`` (NaN kept; of two zeros ``maximum``
  gives ``+0`` and ``minimum`` ``-0``, as numpy does);
- the interval scipy's ``find_interval_ascending`` finds (unique: the table's breakpoints
  strictly increase) and scipy's ``evaluate_poly1`` (``res = res + c[k-1-j] * z``,
  ``z *= s``; NaN outside a table that does not extrapolate);
- ``np.sqrt(np.maximum(v, 0.0))`` and the negation.

It runs only where numba is already imported in the process (the engine's compiled march
imports it once marching pays for it: a few small solves never import numba for the wall) and
the option ``xpersson.set_options(compiled=...)`` (``XPERSSON_COMPILED``) is on; otherwise the
numpy path runs. Either path gives the same numbers (``tests/test_wallpos_eval.py``).
"""

from __future__ import annotations

import math
import sys
import types
from collections.abc import Callable
from typing import Any

from xpersson import numba_cache
from xpersson.options import compiled_enabled

__all__ = ["build", "kernel", "wall_values"]

_STATE: dict[str, Any] = {}  # "fn": the compiled function once built (None: numba missing)


def kernel() -> Callable[..., None] | None:
    """The compiled :func:`wall_values`, or None: the option is off, or numba is not imported
    in this process (nothing imports it for the wall alone) or missing."""
    if not compiled_enabled():
        return None
    if "fn" in _STATE:
        return _STATE["fn"]  # type: ignore[no-any-return]
    if "numba" not in sys.modules:
        return None
    return _build()


def build() -> bool:
    """Build the compiled evaluation now (imports numba); whether it is available."""
    return compiled_enabled() and _build() is not None


def _build() -> Callable[..., None] | None:
    import numpy as np

    jit = numba_cache.njit(__name__, nogil=True, error_model="numpy")
    if jit is None:  # pragma: no cover - numba is optional
        _STATE["fn"] = None
        return None
    # the loop calls the compiled helpers: the same code, its globals bound to the dispatchers
    scope = {**globals(), **{n: jit(globals()[n]) for n in ("_maximum", "_minimum", "_interval")}}
    fn = jit(types.FunctionType(wall_values.__code__, scope, "wall_values"))
    one = np.ones(1)
    fn(np.zeros((4, 1)), np.array([0.0, 1.0]), 0.0, 1.0, True, one, one, True, True)
    _STATE["fn"] = fn
    return fn  # type: ignore[no-any-return]


def _maximum(a: float, b: float) -> float:
    """``np.maximum(a, b)`` of two floats (NaN propagates; ``+0`` of two zeros)."""
    if a != a:
        return a
    if b != b or b > a:
        return b
    if a > b:
        return a
    return b if math.copysign(1.0, a) < 0.0 else a


def _minimum(a: float, b: float) -> float:
    """``np.minimum(a, b)`` of two floats (NaN propagates; ``-0`` of two zeros)."""
    if a != a:
        return a
    if b != b or b < a:
        return b
    if a < b:
        return a
    return a if math.copysign(1.0, a) < 0.0 else b


def _interval(x: Any, t: float, prev: int, extrapolate: bool) -> int:
    """The interval of ``t`` as scipy's ``find_interval_ascending`` finds it: ``x[i] <= t <
    x[i + 1]`` (the last interval at the table's end; ``-1`` outside it without
    ``extrapolate``, or for NaN). ``x`` strictly increasing, so that the interval is unique:
    found by a few steps on from the previous one (times come mostly in order), then by
    bisection."""
    n = x.shape[0]
    a, b = x[0], x[n - 1]
    if not (a <= t <= b):
        if t < a and extrapolate:
            return 0
        if t > b and extrapolate:
            return n - 2
        return -1
    if t == b:
        return n - 2
    low, high = 0, n - 2
    if 0 <= prev < n - 1 and t >= x[prev]:
        low = prev
        for _ in range(_STEPS):
            if t < x[low + 1]:
                return low
            low += 1
    while low < high:  # x[low] <= t < x[high + 1]
        mid = (low + high + 1) // 2
        if t < x[mid]:
            high = mid - 1
        else:
            low = mid
    return low


_STEPS = 4
"""Intervals stepped on from the previous time's before the bisection."""


def wall_values(
    c: Any,
    x: Any,
    t_lo: float,
    t_hi: float,
    extrapolate: bool,
    tau: Any,
    out: Any,
    root: bool,
    negate: bool,
) -> None:
    """``out[i] = -sqrt(max(poly(clip(tau[i])), 0))`` (``root``, ``negate``; else the parts
    asked) of the piecewise polynomial with coefficients ``c`` [shape (k, m), highest order
    first] on breakpoints ``x`` [m + 1, ascending]: a plain loop, compiled by :func:`kernel`."""
    k = c.shape[0]
    interval = 0
    for ip in range(tau.shape[0]):
        t = _minimum(_maximum(tau[ip], t_lo), t_hi)
        i = _interval(x, t, interval, extrapolate)
        if i < 0:
            v = math.nan
        else:
            interval = i
            s = t - x[i]
            v = 0.0
            z = 1.0
            for kp in range(k):
                v = v + c[k - kp - 1, i] * z
                if kp < k - 1:
                    z *= s
        if root:
            v = math.sqrt(_maximum(v, 0.0))
        out[ip] = -v if negate else v
