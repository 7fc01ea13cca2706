"""Optional compiled kernels of the gap distribution (numba), within 1e-12 of the numpy path.

Loops over (load, bin, node) tensors that numpy runs as many passes over memory: the sum of
the gap distribution's Gaussians (:func:`gap_rows`), the sub-problem mean gaps of the
detachment bins (:func:`sub_sums`), and the many cubic splines on shared knots of the solved
curve and ``Phi`` (:func:`spline_rhs`, :func:`spline_coefficients`, :func:`spline_values`:
the same operations in the same order as :mod:`._fastnum`, bit for bit).

:func:`~xpersson.physics.gap_pdf` sums, per load, ``w [N(u; u1, h) + N(u; -u1, h)]`` over the
detached-area bins on the output grid of separations (256 points by default): at 1e4 loads and
about 40 bins per load, 1e8 Gaussians, two ``exp`` each, most of ``gap_pdf``'s time. On a
**uniform** grid ``u_j = j du`` both Gaussians of a bin obey a two-term recurrence without
``exp``: with ``b = u/h`` and ``d = du/h``,

.. math::

    g_{j+1} = g_j r_j, \\qquad r_{j+1} = r_j e^{-d^2}, \\qquad
    r_j = e^{-d (b_j - a) - d^2/2},

restarted from exact ``exp`` values every :data:`ANCHOR` columns, in four interleaved chains
of stride 4 after the first four columns (:func:`_block`: independent products, 22 % faster
than one chain; each chain 16 steps long, so the round-off stays ~1e-14 relative). Bins whose
Gaussian is narrow on the grid (``d`` > :data:`D_MAX`) or whose centre lies far out
(``a = u1/h`` > :data:`A_MAX`, where the ``exp`` of a rounded ``b`` is itself conditioned to
``|b - a| b`` ulps) are evaluated directly, on their 39-width band only; so are the columns
far left of a centre, where the exact value underflows. A pair's far tail below 1e-18 of a
lower bound of its load's density is not summed (:mod:`._gauss_tails`: at most ``n_bins``
1e-18 relative, element by element). Measured against the numpy path (36 scenes of
``benchmarks/summary.py``: design, held-out 2026 and 2718; 300 loads): at most 9e-15 of each
load's largest density and 2.1e-13 relative element by element above 1e-250 of it; 1.3e-14 and
4.0e-13 at 1e4 loads (2026 flat H=0.39 4dec; one chain of 16: 5.6e-15, 2.0e-13; 1.1e-14, 3.4e-13).

numba is an optional accelerator (``pip install numba``, the ``fast`` extra), as the engine's
compiled march (:mod:`xpersson.engine._compiled`): without it, or with
``xpersson.set_options(compiled=False)`` (``XPERSSON_COMPILED=off``), the numpy path runs.
Below :data:`MIN_WORK` (pairs x columns) numba is not imported until the numpy calls of the
process add up to :data:`BUILD_AFTER` (rent or buy, as the engine's march: a study of small
analyses pays at most about twice the best of either path); once built, every call takes it
(:func:`gap_rows`'s values then move by round-off, within the 1e-12 above; the other kernels
keep the numpy path's bits). The kernels are also plain Python (tested without numba).

:func:`sub_sums` is ``sum_m kern[e, m] Phi_l(ln tau_c[e, m] + ln A_le^2)`` of
:func:`~xpersson.physics._subgap._sub_mean_gap` (cut-offs shared by every load): the look-up of
:meth:`~xpersson.physics._phi._Phi.at_log_tau_per_load` element by element, in the same
operations, and the sum over the nodes in numpy's pairwise order (:func:`_pairwise`): the same
bits, in one pass without the (loads, edges, nodes) temporaries.

:func:`crossing_newton` is :func:`~._percolation.critical_magnification`'s safeguarded Newton
steps (25-42 steps of ~25 numpy passes each over a few hundred loads: a fixed cost of every
direct call of the leak table), its operations in its order: the same bits. So is
:func:`~._band_sums.series_horner` (``gap_cdf``'s series: the prefix sums, the column counts
and the Horner loop, ~16 numpy passes over (columns, loads) in one). The series' Hermite
recurrence (:func:`~._fasterf.erf_diff_coefficients`) is numpy's: compiled, it saved less
than the timing noise (``benchmarks/ablation.py``).
"""

from __future__ import annotations

import math
import types
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .. import numba_cache
from ..options import compiled_enabled
from ._gauss_tails import tail_floor, tail_stop
from ._pairwise import _pairwise
from ._spline_sums import knot_interval

__all__ = [
    "ANCHOR",
    "A_MAX",
    "BUILD_AFTER",
    "crossing_newton",
    "D_MAX",
    "MIN_WORK",
    "PAIRWISE",
    "row_values",
    "gap_rows",
    "kernel",
    "spline_coefficients",
    "spline_rhs",
    "spline_slopes",
    "spline_values",
    "sub_sums",
    "uniform_from_zero",
]

#: (pair, column) elements below which the numpy path runs until the kernel is built.
MIN_WORK = 2_000_000
#: Elements of numpy calls per process after which the kernels are built: their cost (numba's
#: import and the kernels kept on disk, 0.2 s CPU) at ~8 ns per element on the numpy path
#: (measured 2026-11-30 by ``benchmarks/fresh_process.py``).
BUILD_AFTER = 25_000_000
#: Columns between exact restarts of the recurrence.
ANCHOR = 64
#: Largest centre ``u1/h`` [1] and grid step ``du/h`` [1] of the recurrence; beyond, direct.
A_MAX = 50.0
D_MAX = 0.5
#: Largest number of nodes summed by :func:`sub_sums` (numpy's pairwise sum splits beyond).
PAIRWISE = 128

_STATE: dict[str, Any] = {}


def kernel(work: float, name: str = "gap_rows") -> Callable[..., Any] | None:
    """The compiled kernel ``name`` (:func:`gap_rows` or :func:`sub_sums`), or None: the option
    is off, numba is missing, or ``work`` [elements] is below :data:`MIN_WORK`, the numpy
    path's work of the process so far (this call's included) is below :data:`BUILD_AFTER` and
    the kernels are not built yet."""
    if not compiled_enabled():
        return None
    if work < MIN_WORK and "fns" not in _STATE:
        spent = _STATE.get("numpy", 0.0) + work
        _STATE["numpy"] = spent
        if spent < BUILD_AFTER:
            return None
    if "fns" not in _STATE:
        _STATE["fns"] = _build()
    fns = _STATE["fns"]
    return None if fns is None else fns[name]


def _build() -> dict[str, Callable[..., Any]] | None:
    from . import _band_sums, _phi_sums, _spline_sums, _sub_nodes  # (kernels: own modules)

    mods = (_spline_sums, _band_sums, _phi_sums, _sub_nodes)
    jit = numba_cache.njit(__name__, *(m.__name__ for m in mods), nogil=True, error_model="numpy")
    if jit is None:  # numba is not installed
        return None
    helpers = (_direct, _pairwise, _gtsv_factor, _band_sums._erf, _band_sums._erf_nonneg)
    helpers += (tail_floor, tail_stop, _block, knot_interval)
    scope = {**globals(), **{fn.__name__: jit(fn) for fn in helpers}}
    fns = (
        gap_rows,
        sub_sums,
        spline_rhs,
        spline_slopes,
        spline_coefficients,
        spline_values,
        *(_phi_sums.KERNELS + _sub_nodes.KERNELS),
        row_values,
        crossing_newton,
        _spline_sums.spline_sub_sums,
        _spline_sums.shared_row_values,
        _band_sums.band_sums,
        _band_sums.series_horner,
    )
    return {fn.__name__: jit(types.FunctionType(fn.__code__, scope, fn.__name__)) for fn in fns}


def uniform_from_zero(u: NDArray[np.float64]) -> bool:
    """Whether ``u`` (1-D) is ``0, du, 2 du, ...`` (``np.linspace(0, u_max, n)``) to 1e-12."""
    if u.ndim != 1 or u.size < 2 or u[0] != 0.0 or not u[-1] > 0.0:
        return False
    du = u[-1] / (u.size - 1)
    return bool(np.all(np.abs(u - du * np.arange(u.size)) <= 1e-12 * u[-1]))


def _direct(out: Any, load: int, j0: int, j1: int, row: Any, a: float, w: float) -> None:
    """``out[load, j] += w e^{-(b - a)^2/2} (1 + e^{-2ab})`` on the columns ``[j0, j1)`` (the
    numpy path's arithmetic; exactly 0 below an exponent of -746, the mirror factor exactly 1
    where ``e^{-2ab} < 2^-54``)."""
    for j in range(j0, j1):
        b = row[j]
        d = b - a
        x = -0.5 * (d * d)
        if x <= -746.0:
            continue
        e = math.exp(x)
        y = b * (-2.0 * a)
        if y > -38.0:
            e = e * (math.exp(max(y, -708.0)) + 1.0)
        out[load, j] += e * w


def gap_rows(
    ls: Any, ks: Any, a: Any, w: Any, u_h: Any, out: Any
) -> None:  # pragma: no cover - compiled (its plain-Python form is tested)
    """``out[l] += w_p [N(b; a_p) + N(b; -a_p)]`` (unit Gaussians of ``b = u_h[k_p]``) for every
    pair ``p = (l, k)``: ``u_h`` (n_bin, n_u) is ``u/h_k`` on a uniform grid from 0; ``a >= 0``
    and ``w`` finite."""
    n_u = u_h.shape[1]
    floor = np.full(out.shape, -np.inf)  # the loads' densities' lower bounds (x TAIL), logs
    refs = np.full((out.shape[0], 2, 3), np.nan)
    powers = np.empty(3)
    tail_floor(ls, ks, a, w, u_h, floor, refs)
    for p in range(ls.size):
        load, ap, wp = ls[p], a[p], w[p]
        row = u_h[ks[p]]
        delta = row[1] - row[0]
        lo, hi = 0, n_u  # the band within 39 widths of the centre (exactly 0 beyond)
        if delta > 0.0:
            lo = int(max(0.0, (ap - 39.0) / delta - 1.0))
            hi = int(min(float(n_u), (ap + 39.0) / delta + 2.0))
        hi = tail_stop(row, ap, wp, floor, load, lo, hi, refs)  # less the negligible tail
        if ap > A_MAX or not delta <= D_MAX:  # narrow or far out: its band only, directly
            _direct(out, load, lo, hi, row, ap, wp)
            continue
        step = (row[n_u - 1] - row[0]) / (n_u - 1)  # the grid's step in b
        half = 0.5 * (step * step)
        c, ratio = math.exp(-2.0 * half), math.exp(-2.0 * step * ap)  # r_j+1/r_j, r-/r+
        powers[0], powers[1] = math.exp(-8.0 * half), math.exp(-32.0 * half)  # c^4, c^16
        powers[2] = math.exp(-8.0 * step * ap)  # ratio^4
        j0 = 0
        while j0 < hi:
            j1 = min(j0 + ANCHOR, hi)
            b0 = row[j0]
            dp, dm = b0 - ap, b0 + ap
            xp, xm = -0.5 * (dp * dp), -0.5 * (dm * dm)
            if dp < 0.0 and xp < -700.0:  # far left of the centre: rising from underflow
                _direct(out, load, j0, j1, row, ap, wp)
                j0 = j1
                continue
            if xp <= -746.0:  # right of the centre, both terms 0 from here on
                break
            gm = math.exp(xm) if xm > -746.0 else 0.0
            rp = math.exp(-step * dp - half)
            _block(out, load, j0, j1, math.exp(xp), gm, rp, rp * ratio, c, powers, wp)
            j0 = j1


def _block(
    out: Any, load: int, j0: int, j1: int, g: float, m: float, r: float, s: float, c: float,
    powers: Any, wp: float,
) -> None:  # fmt: skip
    """``out[load, j] += (g_j + m_j) wp`` on ``[j0, j1)`` from ``g, m`` at ``j0`` and their
    ratios ``r, s`` there (``r_j+1 = r_j c``, as ``s``): the first four by the recurrence, then
    four interleaved chains of stride 4 (``g_j+4 = g_j q_j``, ``q_j+4 = q_j c^16``; ``m`` with
    ``q ratio^4``), independent products; ``powers``: ``c^4, c^16, ratio^4``."""
    c4, c16, ratio4 = powers[0], powers[1], powers[2]
    g1, m1 = g * r, m * s
    r1, s1 = r * c, s * c
    g2, m2 = g1 * r1, m1 * s1
    r2, s2 = r1 * c, s1 * c
    g3, m3 = g2 * r2, m2 * s2
    q0 = ((r * r1) * r2) * (r2 * c)
    q1 = q0 * c4
    q2 = q1 * c4
    q3 = q2 * c4
    t0, t1, t2, t3 = q0 * ratio4, q1 * ratio4, q2 * ratio4, q3 * ratio4
    j = j0
    while j + 4 <= j1:
        out[load, j] += (g + m) * wp
        out[load, j + 1] += (g1 + m1) * wp
        out[load, j + 2] += (g2 + m2) * wp
        out[load, j + 3] += (g3 + m3) * wp
        g, g1, g2, g3 = g * q0, g1 * q1, g2 * q2, g3 * q3
        m, m1, m2, m3 = m * t0, m1 * t1, m2 * t2, m3 * t3
        q0, q1, q2, q3 = q0 * c16, q1 * c16, q2 * c16, q3 * c16
        t0, t1, t2, t3 = t0 * c16, t1 * c16, t2 * c16, t3 * c16
        j += 4
    if j < j1:
        out[load, j] += (g + m) * wp
    if j + 1 < j1:
        out[load, j + 1] += (g1 + m1) * wp
    if j + 2 < j1:
        out[load, j + 2] += (g2 + m2) * wp


def sub_sums(
    log_tc: Any,
    kern: Any,
    log_a2: Any,
    need: Any,
    out: Any,
    table: Any,
    grid: Any,
    lo: int,
    tau1: float,
    phi1: Any,
) -> bool:  # pragma: no cover - compiled (its plain-Python form is tested)
    """``out[l, e] = sum_m kern[e, m] Phi_l(log_tc[e, m] + log_a2[l, e])`` where ``need[l, e]``;
    True when done, False (``out`` partly written) where an argument falls in the linear first
    interval with ``Phi_1 != 0``: its ``exp`` is numpy's (which differs from libm's, numba's
    ``math.exp``, in the last bit for ~5 % of arguments), so the caller takes the numpy path.

    ``table`` (n_load, n_grid - lo) and ``grid``: ``Phi``'s look-up table (``_Phi._table``,
    loads by rows) and ``lo`` its first kept node; ``tau1`` and ``phi1`` (n_load,): the
    linear first interval.
    ``log_a2`` finite or ``-inf`` (no NaN).
    """
    n_load, n_edge = log_a2.shape
    m = log_tc.shape[1]
    n = grid.size
    g0, inv_dg = grid[0], 1.0 / (grid[1] - grid[0])
    top = n - 1.000001
    log_tau1 = math.log(tau1)
    vals = np.empty(m)
    for r in range(n_load):
        p1 = phi1[r]
        for e in range(n_edge):
            if not need[r, e]:
                continue
            la = log_a2[r, e]
            for k in range(m):
                x = log_tc[e, k] + la
                if x < log_tau1:  # the linear first interval (0 where Phi_1 = 0)
                    v = 0.0
                    if p1 != 0.0 and x > -746.0:  # numpy's exp: the numpy path
                        return False
                else:
                    u = min(max((x - g0) * inv_dg, lo), top)
                    i = int(u)
                    u -= i
                    v0 = table[r, i - lo]
                    v = (table[r, i - lo + 1] - v0) * u + v0
                vals[k] = v * kern[e, k]
            out[r, e] = _pairwise(vals, m)
    return True


def spline_rhs(
    yt: Any, dx: Any, d0: float, d1: float, slope: Any, b: Any
) -> None:  # pragma: no cover - compiled (its plain-Python form is tested)
    """The secants and right-hand sides of :func:`~._fastnum._row_slopes` (not-a-knot ends).

    ``yt`` (n, n_row) the data by knot, ``dx`` (n - 1,) the knot steps, ``d0 = x[2] - x[0]``
    and ``d1 = x[-1] - x[-3]``; written: ``slope`` (n - 1, n_row) and ``b`` (n, n_row), the
    operations of the numpy form in its order.
    """
    n, n_row = yt.shape
    for i in range(n - 1):
        for r in range(n_row):
            slope[i, r] = (yt[i + 1, r] - yt[i, r]) / dx[i]
    for i in range(1, n - 1):
        for r in range(n_row):
            b[i, r] = (dx[i] * slope[i - 1, r] + dx[i - 1] * slope[i, r]) * 3.0
    e0 = (dx[0] + 2.0 * d0) * dx[1]
    e1 = (2.0 * d1 + dx[n - 2]) * dx[n - 3]
    for r in range(n_row):
        b[0, r] = (e0 * slope[0, r] + dx[0] ** 2 * slope[1, r]) / d0
        b[n - 1, r] = (dx[n - 2] ** 2 * slope[n - 3, r] + e1 * slope[n - 2, r]) / d1


def spline_slopes(
    dl: Any, d: Any, du: Any, b: Any
) -> int:  # pragma: no cover - compiled (its plain-Python form is tested)
    """LAPACK ``dgtsv`` (as scipy's ``solve_banded`` for one sub- and super-diagonal calls it)
    on the columns of ``b`` (n, n_rhs; C order: the right-hand sides along the rows), in place,
    with ``dl``, ``d``, ``du`` (overwritten): the factors once, then every right-hand side
    with dgtsv's operations, each column's in its order. Returns
    ``info`` (0, or the index of a zero pivot: ``b`` is then not solved)."""
    n = d.shape[0]
    swap = np.zeros(n, dtype=np.bool_)
    fact = np.zeros(n)
    info = _gtsv_factor(dl, d, du, swap, fact)
    if info:
        return info
    m = b.shape[1]  # every right-hand side at once along the rows: no latency chains
    for i in range(n - 1):
        f = fact[i]
        if swap[i]:
            for j in range(m):
                temp = b[i, j]
                b[i, j] = b[i + 1, j]
                b[i + 1, j] = temp - f * b[i + 1, j]
        else:
            for j in range(m):
                b[i + 1, j] = b[i + 1, j] - f * b[i, j]
    for j in range(m):
        b[n - 1, j] = b[n - 1, j] / d[n - 1]
    if n > 1:
        for j in range(m):
            b[n - 2, j] = (b[n - 2, j] - du[n - 2] * b[n - 1, j]) / d[n - 2]
    for i in range(n - 3, -1, -1):
        for j in range(m):
            b[i, j] = (b[i, j] - du[i] * b[i + 1, j] - dl[i] * b[i + 2, j]) / d[i]
    return 0


def _gtsv_factor(dl: Any, d: Any, du: Any, swap: Any, fact: Any) -> int:
    """dgtsv's elimination of the matrix alone (:func:`spline_slopes`): the interchanges
    ``swap`` and factors ``fact`` of every row, ``dl``, ``d``, ``du`` overwritten; ``info``."""
    n = d.shape[0]
    for i in range(n - 1):
        if abs(d[i]) >= abs(dl[i]):  # no row interchange
            if d[i] == 0.0:
                return i + 1
            fact[i] = dl[i] / d[i]
            d[i + 1] = d[i + 1] - fact[i] * du[i]
            if i < n - 2:
                dl[i] = 0.0
        else:  # interchange rows i and i + 1
            swap[i] = True
            fact[i] = d[i] / dl[i]
            d[i] = dl[i]
            temp = d[i + 1]
            d[i + 1] = du[i] - fact[i] * temp
            if i < n - 2:
                dl[i] = du[i + 1]
                du[i + 1] = -fact[i] * dl[i]
            du[i] = temp
    return n if d[n - 1] == 0.0 else 0


def spline_coefficients(
    yt: Any, dx: Any, slope: Any, sl: Any, c: Any
) -> None:  # pragma: no cover - compiled (its plain-Python form is tested)
    """The Hermite coefficients ``c`` (4, n - 1, n_row) of :func:`~._fastnum._row_spline` from
    the data ``yt`` (n, n_row), the steps ``dx`` (n - 1,), the secants and the slopes ``sl``
    at the knots (n, n_row)."""
    n_row = yt.shape[1]
    for i in range(dx.size):
        h = dx[i]
        for r in range(n_row):
            t = sl[i, r] + sl[i + 1, r]
            t -= 2.0 * slope[i, r]
            t /= h
            c[0, i, r] = t / h
            c[1, i, r] = (slope[i, r] - sl[i, r]) / h - t
            c[2, i, r] = sl[i, r]
            c[3, i, r] = yt[i, r]


def spline_values(
    c: Any, k: Any, s: Any, out: Any, transposed: bool
) -> None:  # pragma: no cover - compiled (its plain-Python form is tested)
    """``max(spline, 0)`` of :func:`~._fastnum._ppoly_at`: at the points of intervals ``k``
    and local abscissae ``s``, ``out[row, point]`` (or ``out[point, row]`` when
    ``transposed``), PPoly's operations in its order."""
    n_row = c.shape[2]
    for p in range(k.size):
        i, sp = k[p], s[p]
        z = sp * sp
        z3 = z * sp
        for r in range(n_row):
            v = c[2, i, r] * sp + c[3, i, r] + c[1, i, r] * z + c[0, i, r] * z3
            if not v > 0.0 and v == v:  # np.maximum(v, 0.0): +0.0 for -0.0, NaN kept
                v = 0.0
            if transposed:
                out[p, r] = v
            else:
                out[r, p] = v


def row_values(
    c: Any, knots: Any, x: Any, out: Any
) -> None:  # pragma: no cover - compiled (its plain-Python form is tested)
    """:func:`~._curve._rows` (every load's spline at its own points ``x`` (n_load, n_point),
    no NaN): the clip to the knots, ``searchsorted(side="right") - 1`` clipped to the
    intervals (a bisection: the same index), and the Horner form in numpy's order."""
    for r in range(x.shape[0]):
        for p in range(x.shape[1]):
            i, d = knot_interval(knots, x[r, p])
            out[r, p] = ((c[0, i, r] * d + c[1, i, r]) * d + c[2, i, r]) * d + c[3, i, r]


def crossing_newton(
    coef: Any, xk: Any, xc: Any, lo: Any, hi: Any, a_c: float
) -> None:  # pragma: no cover - compiled (its plain-Python form is tested)
    """The safeguarded Newton steps of :func:`~._percolation._newton` (every row's cubic
    ``coef`` (4, n) about ``xk`` equal to ``a_c`` in the bracket ``lo, hi``; all three
    updated in place): its operations in its order, row by row (the same number of
    steps, each row until its own step is below 1e-15 relative or 60 steps)."""
    for r in range(xc.size):
        c0, c1, c2, c3 = coef[0, r], coef[1, r], coef[2, r], coef[3, r]
        for _ in range(60):
            x = xc[r]
            d = x - xk[r]
            f = ((c0 * d + c1) * d + c2) * d + c3
            df = ((3.0 * c0) * d + 2.0 * c1) * d + c2
            res = f - a_c
            if res > 0:
                lo[r] = x
            if res <= 0:
                hi[r] = x
            step = res / df if df < 0 else 0.0
            xn = x - step
            if not (xn > lo[r] and xn < hi[r]):
                xn = 0.5 * (lo[r] + hi[r])
            ax = abs(x)
            if not ax >= 1.0 and ax == ax:  # np.maximum(1.0, |x|): NaN kept
                ax = 1.0
            xc[r] = xn
            if abs(xn - x) <= 1e-15 * ax:
                break
