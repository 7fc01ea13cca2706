"""Percolation: the magnification where the contact area crosses a threshold (§6.1)."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._compiled import kernel
from ._fastnum import _compiled_slopes, _row_slopes, _row_spline

__all__ = ["critical_magnification"]


def critical_magnification(zeta: ArrayLike, area: ArrayLike, a_c: float) -> NDArray[np.float64]:
    """Magnification [1] where the area curve crosses ``a_c`` (NaN where it stays above).

    The crossing interval is found on the nodes; inside it the cubic spline of ``A`` in
    ``ln zeta`` is solved by safeguarded Newton steps (exact at the nodes).
    """
    z = np.asarray(zeta, dtype=float)
    A = np.atleast_2d(np.asarray(area, dtype=float))
    if not 0.0 < a_c < 1.0:
        raise ValueError(f"a_c must lie in (0, 1), got {a_c!r}")
    x = np.log(z)
    below = A <= a_c
    crossed = below.any(axis=1)
    j = np.where(crossed, np.argmax(below, axis=1), 1)  # first node at or below a_c
    j = np.clip(j, 1, z.size - 1)
    out = np.full(A.shape[0], np.nan)
    if not crossed.any():
        return out
    rows = np.arange(A.shape[0])
    lo, hi = x[j - 1], x[j]
    a_lo, a_hi = A[rows, j - 1], A[rows, j]
    t = (a_lo - a_c) / np.where(a_lo > a_hi, a_lo - a_hi, 1.0)
    xc = lo + np.clip(t, 0.0, 1.0) * (hi - lo)
    c = crossed  # the loads that stay above a_c take no steps (their NaN is known)
    if z.size > 2:  # each load's crossing interval (fixed) of CubicSpline(x, A, axis=1)
        every = bool(c.all())  # every load crosses: no row copies
        coef = _crossing_coefficients(x, A if every else A[c], j[c] - 1)
        xc = _newton(coef, x[j[c] - 1], xc[c], lo[c], hi[c], a_c)
    else:
        xc = xc[c]
    out[c] = np.exp(xc)
    return out


def _crossing_coefficients(
    x: NDArray[np.float64], A: NDArray[np.float64], k: NDArray[np.intp]
) -> tuple[NDArray[np.float64], ...]:
    """``CubicSpline(x, A, axis=1).c[:, k[l], l]`` for every row ``l`` (bit for bit): the
    coefficients of one interval per row, from the spline's slopes at the knots."""
    if x.size < 4:
        return tuple(_row_spline(x, A).c[:, k, np.arange(A.shape[0])])
    if kernel(A.size * 8, "spline_coefficients") is not None:  # as _row_spline: compiled slopes
        yt, dx, slope, sl = _compiled_slopes(x, A)  # (bit for bit; dx 1-D)
        dx = dx[:, None]
    else:
        yt, dx, slope, sl = _row_slopes(x, A)
    rows = np.arange(A.shape[0])
    h, m, s0, s1 = dx[k, 0], slope[k, rows], sl[k, rows], sl[k + 1, rows]
    t = (s0 + s1 - 2.0 * m) / h
    return t / h, (m - s0) / h - t, s0, yt[k, rows]


def _newton(
    coef: tuple[NDArray[np.float64], ...],
    xk: NDArray[np.float64],
    xc: NDArray[np.float64],
    lo: NDArray[np.float64],
    hi: NDArray[np.float64],
    a_c: float,
) -> NDArray[np.float64]:
    """Safeguarded Newton steps for ``A(x) = a_c`` on every row's cubic (bracket ``lo, hi``),
    each row until its own step is below 1e-15 (relative) or 60 steps: a row's crossing never
    depends on the other rows."""
    c0, c1, c2, c3 = coef
    lo, hi = lo.copy(), hi.copy()
    fn = kernel(60.0 * 40.0 * xc.size, "crossing_newton")
    if fn is not None:  # the same operations, row by row (the same bits)
        xc = np.array(xc, dtype=float)
        fn(np.array([c0, c1, c2, c3], dtype=float), np.ascontiguousarray(xk), xc, lo, hi, a_c)
        return xc
    xc = np.array(xc, dtype=float)
    act = np.arange(xc.size)  # the rows still stepping: each stops on its own step
    c0, c1, c2, c3, xk = c0 + 0.0, c1 + 0.0, c2 + 0.0, c3 + 0.0, xk + 0.0
    for _ in range(60):
        if not act.size:
            break
        x = xc[act]
        d = x - xk
        f = c0 * d
        f += c1
        f *= d
        f += c2
        f *= d
        f += c3
        df = (3.0 * c0) * d
        df += 2.0 * c1
        df *= d
        df += c2
        r = f - a_c
        la, ha = lo[act], hi[act]
        np.copyto(la, x, where=r > 0)
        np.copyto(ha, x, where=r <= 0)
        lo[act], hi[act] = la, ha
        neg = df < 0
        step = r / np.where(neg, df, -1.0)
        step[~neg] = 0.0
        xn = x - step
        bad = ~((xn > la) & (xn < ha))
        if bad.any():
            np.copyto(xn, 0.5 * (la + ha), where=bad)
        xc[act] = xn
        going = ~(np.abs(xn - x) <= 1e-15 * np.maximum(1.0, np.abs(x)))
        if not going.all():  # the rows done leave (with their coefficients)
            act, c0, c1, c2, c3, xk = (a[going] for a in (act, c0, c1, c2, c3, xk))
    return xc
