"""A wall's table (the compiled wall protocol): a wall position given as a clipped piecewise
polynomial in diffusion time, which the engine evaluates in compiled code (numba) instead of
calling the position back in Python.

A :class:`WallTable` is ``p(tau) = s * g(poly(clip(tau, t_lo, t_hi)))`` [Pa] with ``poly`` the
piecewise polynomial of coefficients ``c`` (shape ``(k, m)``, highest order first, as scipy's
``PPoly``) on the strictly increasing breakpoints ``x`` [Pa^2], ``g = sqrt(max(., 0))`` when
``root`` (else the identity) and ``s = -1`` when ``negate``. A moving wall built with
``Wall.absorbing(position, table=...)`` keeps its position callable (the plain path, used
whenever the compiled code does not run); where numba is imported in the process and the
option ``compiled`` is on, the engine evaluates the table itself: the wall's positions
(:meth:`WallTable.values`) and the window-edge kinks (:func:`edge_roots`: the sign changes of
the wall's gap to the window's edge and their Illinois steps in one compiled call, the
operations of :mod:`._cn_kinks` in the same order, so the same roots bit for bit).

:func:`table_values` does the clip, the interval search, the local polynomial, the clip at 0,
the square root and the sign in one pass, with the operations of the numpy path in the same
order (``np.minimum(np.maximum(t, t_lo), t_hi)``; scipy's ``find_interval_ascending`` and
``evaluate_poly1``; ``np.sqrt(np.maximum(v, 0.0))``; the negation): the numbers of
``PPoly.__call__`` bit for bit (``tests/engine/test_wall_table.py``).

Plugins declare that their walls carry tables with ``FastPaths(wall_tables=True)``
(:mod:`xpersson.plugins`); ``xpersson.testing.check_plugin`` checks the tables against the
position callables. Units: tau in Pa^2, positions in Pa.
"""

from __future__ import annotations

import math
import sys
import types
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .. import numba_cache
from ..options import compiled_enabled

__all__ = ["WallTable", "edge_roots", "kernels", "table_track", "table_values"]

Array = NDArray[np.float64]

_STATE: dict[str, Any] = {}  # "fns": the compiled kernels (None: no numba)


@dataclass(frozen=True, eq=False)
class WallTable:
    """A wall position as a clipped piecewise polynomial in diffusion time (see the module).

    Parameters
    ----------
    c : ndarray, shape (k, m)
        Coefficients [Pa, or Pa^2 with ``root``, per Pa^(2j)] of the ``m`` pieces, highest order
        first (scipy's ``PPoly.c``), in powers of ``tau - x[i]``.
    x : ndarray, shape (m + 1,)
        Breakpoints [Pa^2], strictly increasing.
    t_lo, t_hi : float
        The clip [Pa^2]: the polynomial is evaluated at ``min(max(tau, t_lo), t_hi)``.
    extrapolate : bool
        Whether a clipped time outside ``[x[0], x[-1]]`` takes the end piece (else NaN).
    root : bool
        Whether the position is ``sqrt(max(poly, 0))`` (``poly`` then in Pa^2).
    negate : bool
        Whether the position is the negative of that (a lower wall below ``p = 0``).
    """

    c: Array
    x: Array
    t_lo: float
    t_hi: float
    extrapolate: bool = False
    root: bool = False
    negate: bool = False

    def __post_init__(self) -> None:
        c = np.array(self.c, dtype=np.float64, order="C")  # (its own copies)
        x = np.array(self.x, dtype=np.float64, order="C")
        if c.ndim != 2 or c.shape[0] < 1 or x.shape != (c.shape[1] + 1,):
            raise ValueError(
                f"c (shape (k, m)) and x (shape (m + 1,)) [Pa^2] of a WallTable must match; got "
                f"c {c.shape}, x {x.shape}"
            )
        if not (np.all(np.isfinite(x)) and np.all(x[1:] > x[:-1])):
            raise ValueError("x [Pa^2] of a WallTable must be finite and strictly increasing")
        if not float(self.t_lo) <= float(self.t_hi):
            raise ValueError(f"t_lo <= t_hi [Pa^2] required; got {self.t_lo!r}, {self.t_hi!r}")
        object.__setattr__(self, "c", c)
        object.__setattr__(self, "x", x)
        object.__setattr__(self, "t_lo", float(self.t_lo))
        object.__setattr__(self, "t_hi", float(self.t_hi))
        for name in ("extrapolate", "root", "negate"):
            object.__setattr__(self, name, bool(getattr(self, name)))

    def args(self) -> tuple:
        """``(c, x, t_lo, t_hi, extrapolate, root, negate)``: the table as the compiled
        kernels take it."""
        return (self.c, self.x, self.t_lo, self.t_hi, self.extrapolate, self.root, self.negate)

    def compiled(self, tau: ArrayLike) -> Array | None:
        """Positions [Pa] at diffusion times ``tau`` [Pa^2] (same shape) by the compiled loop,
        or None where it does not run (:func:`kernels`)."""
        fns = kernels()
        if fns is None:
            return None
        t = np.asarray(tau, dtype=float)
        out = np.empty(t.shape)
        flat = t if t.ndim == 1 and t.flags.c_contiguous else t.ravel()
        fns[0](self.c, self.x, self.t_lo, self.t_hi, self.extrapolate, flat,
               out if t.ndim == 1 else out.reshape(-1), self.root, self.negate)  # fmt: skip
        return out

    def values(self, tau: ArrayLike) -> Array:
        """Positions [Pa] at diffusion times ``tau`` [Pa^2] (same shape): by the compiled loop
        where it runs (:func:`kernels`), else by numpy and scipy's ``PPoly`` (the same
        numbers)."""
        found = self.compiled(tau)
        if found is not None:
            return found
        t = np.asarray(tau, dtype=float)
        from scipy.interpolate import PPoly

        poly = PPoly.construct_fast(self.c, self.x, self.extrapolate)
        v = np.asarray(poly(np.minimum(np.maximum(t, self.t_lo), self.t_hi)), dtype=float)
        if self.root:
            v = np.sqrt(np.maximum(v, 0.0))
        return -v if self.negate else v


def kernels() -> tuple[Callable[..., Any], ...] | None:
    """The compiled ``(table_values, edge_roots, table_track, table_check)``, or None: the option
    ``compiled`` is off, or numba is not imported in this process (a wall alone never imports
    it: the engine's compiled march does, once marching pays for it) or missing."""
    if not compiled_enabled():
        return None
    if "fns" in _STATE:
        return _STATE["fns"]  # type: ignore[no-any-return]
    if "numba" not in sys.modules:
        return None
    return _build()


def build() -> bool:
    """Build the compiled kernels now (imports numba); whether they are available."""
    if not compiled_enabled():
        return False
    return (_STATE["fns"] if "fns" in _STATE else _build()) is not None


def _build() -> tuple[Callable[..., Any], ...] | None:
    jit = numba_cache.njit(__name__, nogil=True, error_model="numpy")
    if jit is None:  # pragma: no cover - numba is optional
        _STATE["fns"] = None
        return None
    from ._cn_edges import wall_query, wall_track

    names = ("_maximum", "_minimum", "_interval", "_sign", "table_values", "_illinois")
    scope = {**globals(), "wall_query": jit(wall_query), "wall_track": jit(wall_track)}
    for n in (*names, "edge_roots", "table_track"):  # each calls the compiled ones before it
        scope[n] = jit(types.FunctionType(globals()[n].__code__, scope, n))
    values, roots = scope["table_values"], scope["edge_roots"]
    c, x, one = np.zeros((4, 1)), np.array([0.0, 1.0]), np.ones(1)
    values(c, x, 0.0, 1.0, True, one, one, True, True)
    roots(c, x, 0.0, 1.0, True, True, True, one, one, -1.0, np.empty(2))
    track = scope["table_track"]
    two, none = np.array([1.0, 2.0]), np.zeros(0)
    track(c, x, 0.0, 1.0, True, True, True, two, one, none, one, two, two.copy(), two.copy())
    scope["table_check"] = jit(types.FunctionType(table_check.__code__, scope, "table_check"))
    _STATE["fns"] = (values, roots, track, scope["table_check"])
    return _STATE["fns"]  # type: ignore[no-any-return]


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
        for _ in range(4):  # steps on from the previous interval before the bisection
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


def table_values(
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
    """``out[i]`` = the table's position at ``tau[i]`` (see :class:`WallTable`): a plain loop,
    compiled by :func:`kernels`."""
    k, last = c.shape[0], x.shape[0] - 2
    interval = 0
    for ip in range(tau.shape[0]):
        t = tau[ip]
        if not t_lo < t < t_hi:  # (strictly inside, the clip gives t: no NaN, no signed zero)
            t = _minimum(_maximum(t, t_lo), t_hi)
        # (the previous interval first: the times come mostly in order, many in one piece)
        inside = interval <= last and x[interval] <= t < x[interval + 1]
        i = interval if inside else _interval(x, t, interval, extrapolate)
        if i < 0:
            v = math.nan
        elif k == 4:  # (cubic pieces, the loop below unrolled: the same operations)
            interval = i
            s = t - x[i]
            v = 0.0 + c[3, i] * 1.0
            z = s
            v = v + c[2, i] * z
            z *= s
            v = v + c[1, i] * z
            z *= s
            v = v + c[0, i] * z
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
            v = math.sqrt(v if v > 0.0 else _maximum(v, 0.0))
        out[ip] = -v if negate else v


def _sign(v: float) -> float:
    """``numpy.sign`` of a float (NaN for NaN)."""
    if v != v:
        return v
    return 1.0 if v > 0 else (-1.0 if v < 0 else 0.0)


def _illinois(tab: Any, p: float, sk: float, a: float, b: float, fa: float, fb: float) -> float:
    """The root in ``[a, b]`` of the gap ``wall(t) - (p + sk sqrt(2 t))`` by the steps of
    :func:`._cn_kinks._illinois` (to ``1e-15 b``), the table ``tab = (c, x, t_lo, t_hi,
    extrapolate, root, negate, scratch-in, scratch-out)``."""
    c, x, lo, hi, ext, root, neg, tin, tout = tab
    xt = 1e-15 * b
    for _ in range(200):
        den = fb - fa
        if den == 0.0:  # (Python's ZeroDivisionError on the float path: no root)
            return math.nan
        cc = b - fb * (b - a) / den
        nudge = min(xt, 0.5 * abs(a - b))
        if abs(cc - b) < nudge:
            cc = b + math.copysign(nudge, a - b)
        tin[0] = cc
        table_values(c, x, lo, hi, ext, tin, tout, root, neg)
        fc = tout[0] - (p + sk * math.sqrt(2.0 * cc))
        flip = _sign(fc) * _sign(fb) < 0  # the root lies between cc and b
        new_a = b if flip else a
        fa = fb if flip else 0.5 * fa
        a, b, fb = new_a, cc, fc
        if fc == 0 or abs(cc - new_a) <= xt or not math.isfinite(fc):
            return cc if math.isfinite(fc) else math.nan
    return math.nan


def edge_roots(
    c: Any,
    x: Any,
    t_lo: float,
    t_hi: float,
    extrapolate: bool,
    root: bool,
    negate: bool,
    cand: Any,
    p0: Any,
    sk: float,
    roots: Any,
) -> int:
    """The times where the table's wall crosses the window edges ``p0[j] + sk sqrt(2 tau)``
    (``sk = -/+ k``) of every load ``j`` between the sample times ``cand`` [Pa^2]: the sign
    changes of the gap at ``cand`` (load by load, in time order), each polished by
    :func:`_illinois`; written to ``roots``, their number returned (NaN roots left out, as
    :func:`._cn_kinks._switch_times_batch` does). ``roots`` must hold ``len(p0) *
    (len(cand) - 1)`` values."""
    n = cand.shape[0]
    pos = np.empty(n)
    table_values(c, x, t_lo, t_hi, extrapolate, cand, pos, root, negate)
    s = np.empty(n)
    for j in range(n):
        s[j] = math.sqrt(2.0 * cand[j])
    tab = (c, x, t_lo, t_hi, extrapolate, root, negate, np.empty(1), np.empty(1))
    found = 0
    for il in range(p0.shape[0]):
        p = p0[il]
        g_prev = pos[0] - (p + sk * s[0])
        for j in range(n - 1):
            g_next = pos[j + 1] - (p + sk * s[j + 1])
            if _sign(g_prev) != _sign(g_next):  # (NaN differs from itself, as numpy's !=)
                a, b = cand[j], cand[j + 1]
                if g_next == 0:
                    r = b
                elif g_prev == 0:
                    r = a
                elif _sign(g_prev) * _sign(g_next) < 0:
                    r = _illinois(tab, p, sk, a, b, g_prev, g_next)
                else:
                    r = math.nan
                if math.isfinite(r):
                    roots[found] = r
                    found += 1
            g_prev = g_next
    return found


def table_check(
    c: Any,
    x: Any,
    t_lo: float,
    t_hi: float,
    extrapolate: bool,
    root: bool,
    negate: bool,
    tau: Any,
    log16: Any,
    p0: Any,
) -> bool:
    """Whether the table's positions (:func:`table_values`) at the sample times of
    :func:`._problem.sample_times` of the output times ``tau`` [Pa^2] (validated: finite,
    >= 0) are all finite and every load ``p0`` [Pa] lies strictly above the position at
    ``tau = 0`` (the checks of :func:`._problem._check_positions` of a lower wall without an
    upper one, the same comparisons; compiled). The sample times are made here, with numpy's
    operations: 0, ``tau``, ``numpy.linspace(0, t_end, 65)`` and ``t_end log16`` (``log16``:
    ``numpy.logspace(-16, 0, 96)``), ``t_end`` the largest of ``tau``; unsorted and with
    repeats (a check of every position and of the one at 0 does not depend on their order)."""
    n, m = tau.shape[0], log16.shape[0]
    t_end = tau[0]
    for v in tau:  # (np.max: no NaN here)
        if v > t_end:
            t_end = v
    t = np.empty(1 + n + 65 + m)
    t[0] = 0.0
    for i in range(n):
        t[1 + i] = tau[i]
    step = t_end / 64.0  # (numpy.linspace's arithmetic, as _grid.linspace0)
    for i in range(64):
        v = (i / 64.0) * t_end if step == 0 else i * step
        if not 0.0 < step < math.inf:
            v = v + 0.0
        t[1 + n + i] = v
    t[n + 65] = t_end
    for i in range(m):
        t[n + 66 + i] = t_end * log16[i]
    out = np.empty(t.shape[0])
    table_values(c, x, t_lo, t_hi, extrapolate, t, out, root, negate)
    for v in out:
        if not math.isfinite(v):
            return False
    for p in p0:
        if p <= out[0]:
            return False
    return True


def table_track(
    c: Any,
    x: Any,
    t_lo: float,
    t_hi: float,
    extrapolate: bool,
    root: bool,
    negate: bool,
    taus: Any,
    mid: Any,
    bp: Any,
    at_mid: Any,
    at_t: Any,
    vb: Any,
    va: Any,
) -> None:
    """The table's wall along ``taus`` [Pa^2] (:func:`._cn_edges.compiled_track` in one
    call): :func:`._cn_edges.wall_query`'s times, the positions there by
    :func:`table_values`, :func:`._cn_edges.wall_track`'s positions at ``mid`` and ``taus``
    [Pa] and speeds [1/Pa] into ``at_mid``, ``at_t``, ``vb``, ``va`` (``bp``: the wall's
    breakpoints [Pa^2])."""
    n = taus.shape[0]
    hi, lo, q = np.empty(n), np.empty(n), np.empty(4 * n - 1)
    wall_query(taus, mid, bp, hi, lo, q)  # noqa: F821 - bound to the compiled one by _build
    p = np.empty(q.shape[0])
    table_values(c, x, t_lo, t_hi, extrapolate, q, p, root, negate)
    wall_track(p, taus, hi, lo, bp, at_mid, at_t, vb, va)  # noqa: F821 - as wall_query
