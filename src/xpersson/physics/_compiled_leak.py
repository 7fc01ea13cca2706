"""Optional compiled kernels (numba) of the leak analysis's direct path, built with
:mod:`._compiled`'s kernels (:func:`._compiled.kernel`): each does its numpy form's operations
in its order, so the same bits. Plain Python here (tested without numba on small inputs).

:func:`crossing_newton` is :func:`~._percolation.critical_magnification`'s safeguarded Newton
steps, :func:`csr_sums` the sparse product of :meth:`~._phi._Phi.sums_at_log_tau`,
:func:`series_horner` the Horner sums of :func:`~._gap_distribution._series_sum`: numpy ran
them as tens of passes over small arrays (25-42 Newton steps; 16 series terms), a fixed cost
in every direct call of the leak table (``xpersson_interface._by_load``).
"""

from __future__ import annotations

from typing import Any

__all__ = ["crossing_newton", "csr_sums", "series_horner"]


def crossing_newton(
    coef: Any, xk: Any, xc: Any, lo: Any, hi: Any, a_c: float
) -> None:  # pragma: no cover - compiled (its plain-Python form is tested)
    """The safeguarded Newton steps of :func:`~._percolation._newton` (every row's cubic
    ``coef`` (4, n) about ``xk`` equal to ``a_c`` in the bracket ``lo, hi``; all three
    updated in place): its operations in its order, all rows in lockstep (the same number of
    steps, until every row's step is below 1e-15 relative or 60 steps)."""
    for _ in range(60):
        every = True
        for r in range(xc.size):
            c0, c1, c2, c3 = coef[0, r], coef[1, r], coef[2, r], coef[3, r]
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
            if not abs(xn - x) <= 1e-15 * ax:
                every = False
            xc[r] = xn
        if every:
            break


def csr_sums(
    ptr: Any, cols: Any, data: Any, tab: Any, out: Any
) -> None:  # pragma: no cover - compiled (its plain-Python form is tested)
    """``out = W @ tab`` of the CSR matrix ``W`` (``ptr``, ``cols``, ``data``) and the dense
    ``tab`` (n, n_vec): scipy's ``csr_matvecs`` in its order (``out`` zeroed, then each stored
    element's ``data tab[col]`` added to its row in storage order): the same bits."""
    n_vec = tab.shape[1]
    for k in range(ptr.size - 1):
        for v in range(n_vec):
            out[k, v] = 0.0
        for e in range(ptr[k], ptr[k + 1]):
            a, j = data[e], cols[e]
            for v in range(n_vec):
                out[k, v] += a * tab[j, v]


def series_horner(
    acc: Any, cnt: Any, start: Any, x: Any, x2: Any, out: Any
) -> None:  # pragma: no cover - compiled (its plain-Python form is tested)
    """The Horner sums of :func:`~._gap_distribution._series_sum`, element by element: per
    column ``j`` (of ``cnt`` (top, n_load)) and load ``l``, from 0 each term ``n`` from the
    last down to 1 whose first column ``start[n] <= j`` adds ``acc[n, cnt[j, l]]`` (index
    clipped, as ``np.take(mode="clip")``) and multiplies by ``x2[j, l]`` (``x`` and ``x2``
    (top, 1 or n_load)), then term 0 and ``x``: its operations in its order, written to
    ``out[l, j]``."""
    top, n_load = cnt.shape
    n_term, last = acc.shape[0], acc.shape[1] - 1
    one = x.shape[1] == 1
    for j in range(top):
        for col in range(n_load):
            c = col if not one else 0
            i = min(max(cnt[j, col], 0), last)
            r = 0.0
            for n in range(n_term - 1, 0, -1):
                if start[n] <= j:
                    r += acc[n, i]
                    r *= x2[j, c]
            r += acc[0, i]
            r *= x[j, c]
            out[col, j] = r
