"""Percolation: the magnification where the contact area crosses a threshold (§6.1)."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._fastnum import _row_spline

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
    spl = _row_spline(x, A) if z.size > 2 else None  # CubicSpline(x, A, axis=1)
    rows = np.arange(A.shape[0])
    lo, hi = x[j - 1], x[j]
    a_lo, a_hi = A[rows, j - 1], A[rows, j]
    t = (a_lo - a_c) / np.where(a_lo > a_hi, a_lo - a_hi, 1.0)
    xc = lo + np.clip(t, 0.0, 1.0) * (hi - lo)
    if spl is not None:
        k = j - 1
        c0, c1, c2, c3 = spl.c[:, k, rows]  # each load's crossing interval (fixed): once
        c0_3, c1_2, xk = 3.0 * c0, 2.0 * c1, x[k]
        for _ in range(60):
            d = xc - xk
            f = ((c0 * d + c1) * d + c2) * d + c3
            df = (c0_3 * d + c1_2) * d + c2
            r = f - a_c
            lo = np.where(r > 0, xc, lo)
            hi = np.where(r <= 0, xc, hi)
            step = np.where(df < 0, r / np.where(df < 0, df, -1.0), 0.0)
            xn = xc - step
            bad = ~((xn > lo) & (xn < hi))
            xn = np.where(bad, 0.5 * (lo + hi), xn)
            if np.all(np.abs(xn - xc) <= 1e-15 * np.maximum(1.0, np.abs(xc))):
                xc = xn
                break
            xc = xn
    out[crossed] = np.exp(xc[crossed])
    return out
