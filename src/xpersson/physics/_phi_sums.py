"""Optional compiled kernels of ``Phi``'s sums (numba), bit for bit the numpy path: the
Stieltjes node values and sums of the solved curve (:meth:`~._curve._Curve.dF_weighted`:
:func:`df_logs`, :func:`df_sums`), the shared sums of ``Phi``'s table
(:meth:`~._phi._Phi.sums_at_log_tau`: :func:`table_sums`), the table itself
(:meth:`~._phi._Phi._table`: :func:`table_values`) and ``Phi``'s node integrals
(:func:`phi_cumsum`). Built and gated with the kernels of
:mod:`._compiled` (:data:`KERNELS`); plain Python without numba.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = [
    "KERNELS",
    "df_logs",
    "df_sums",
    "phi_cumsum",
    "table_sums",
    "table_values",
]


def df_logs(
    c: Any, jb: int, k0: int, d: Any, off: int, y: Any
) -> float:  # pragma: no cover - compiled (its plain-Python form is tested)
    """``ln(1 - F)`` (clipped at 0 from above) at the Stieltjes nodes of
    :meth:`~._curve._Curve._dF_compiled`, the operations of :meth:`~._curve._Curve._dF_blocks`
    in order; returns the smallest value written (NaN if any is NaN; 0 if none), as the
    ``y.min()`` of :func:`~._fastnum._exp_inplace`.

    ``c`` (4, n_int, n_load): the spline's coefficients, from interval ``jb`` on and load ``k0``
    on; ``d`` (m, n_d) the nodes' local abscissae, from column ``off`` on; written ``y``
    (n, m, rows): the loads innermost, read contiguously from ``c`` (vectorised).
    """
    n, m, rows = y.shape
    lo = np.zeros(rows)
    for j in range(n):
        c0, c1 = c[0, jb + j, k0 : k0 + rows], c[1, jb + j, k0 : k0 + rows]
        c2, c3 = c[2, jb + j, k0 : k0 + rows], c[3, jb + j, k0 : k0 + rows]
        for a in range(m):
            x = d[a, off + j]
            ya = y[j, a]
            for r in range(rows):
                v = ((c0[r] * x + c1[r]) * x + c2[r]) * x + c3[r]
                # np.minimum(v, 0.0): v where v < 0 or NaN, else +0.0 (also for -0.0)
                v = v if (v < 0.0 or v != v) else 0.0
                ya[r] = v
                lo[r] = v if (v < lo[r] or v != v) else lo[r]  # a NaN stays
    low = 0.0
    for r in range(rows):
        low = lo[r] if (lo[r] < low or lo[r] != lo[r]) else low
    return low


def df_sums(
    c: Any, jb: int, k0: int, d: Any, off: int, stop: Any, e: Any, w_t: Any, start: int, out: Any
) -> None:  # pragma: no cover - compiled (its plain-Python form is tested)
    """``out[k0 + r, start + j] = sum_a dy[j, a, r] e[j, a, r] w_t[a, start + j]`` in the
    order of numpy's sum over the nodes (:meth:`~._curve._Curve.dF_weighted`), ``e = 1 - F``
    (``exp`` of :func:`df_logs`, (n, m, rows)) and the slope ``dy`` of ``ln(1 - F)`` (at 0
    from below) computed here, as :meth:`~._curve._Curve._dF_blocks` does (the same
    arguments as :func:`df_logs`): 0 on a row's first ``stop[r]`` intervals (that row's own
    quiet ones, :func:`~._curve._quiet_rows`)."""
    n, m, rows = e.shape
    acc = np.empty(rows)
    for j in range(n):
        c0, c1 = c[0, jb + j, k0 : k0 + rows], c[1, jb + j, k0 : k0 + rows]
        c2 = c[2, jb + j, k0 : k0 + rows]
        for a in range(m):
            x, wa, ea = d[a, off + j], w_t[a, start + j], e[j, a]
            for r in range(rows):
                w = ((3.0 * c0[r]) * x + 2.0 * c1[r]) * x + c2[r]
                dy = w if (w > 0.0 or w != w) else 0.0  # np.maximum(w, 0.0)
                dy = dy if j >= stop[r] else 0.0
                t = (dy * ea[r]) * wa
                acc[r] = t if a == 0 else acc[r] + t
        for r in range(rows):
            out[k0 + r, start + j] = acc[r]


def table_sums(
    log_tau: Any, kern: Any, tab: Any, at: Any, log_tau1: float, out: Any, need: Any
) -> None:  # pragma: no cover - compiled (its plain-Python form is tested)
    """The sparse product of :meth:`~._phi._Phi.sums_at_log_tau` without building the CSR
    matrix: ``out[l, e] = sum_m kern[e, m] ((1 - u) T[l, i] + u T[l, i + 1])`` over the nodes
    ``m`` past the linear first interval whose table nodes are not both 0 for every load,
    the look-up's ``u``, ``i`` by its operations (``at``: the grid's first value, its inverse
    step, the table's first node ``lo``, the clip's top, ``g0``), each row's terms added to 0
    in the CSR's order as scipy's ``csr_matvecs`` does (``y += a x``, node ``i`` then
    ``i + 1``): its bits. ``tab`` (loads, nodes); ``log_tau`` finite (the caller's check);
    ``need`` (loads, rows) bool: the entries summed (the others 0)."""
    n_row, m_max = log_tau.shape
    base, inv, lo, top, g0 = at[0], at[1], at[2], at[3], at[4]
    node = np.full((n_row, m_max), -1, dtype=np.intp)  # -1: left out
    w0, w1 = np.empty((n_row, m_max)), np.empty((n_row, m_max))
    for e in range(n_row):
        for m in range(m_max):
            lt = log_tau[e, m]
            if lt < log_tau1:  # the linear first interval (added by the caller)
                continue
            u = (lt - base) * inv
            u = u if u > lo else lo  # np.clip(u, lo, top)
            u = u if u < top else top
            i = int(u)
            u -= i
            if i + 1 < g0:  # nodes i, i + 1 both 0 for every load: left out
                continue
            k = kern[e, m]
            w1[e, m] = k * u
            w0[e, m] = k - w1[e, m]
            node[e, m] = i - int(lo)
    for load in range(tab.shape[0]):
        for e in range(n_row):
            y = 0.0
            if not need[load, e]:
                out[load, e] = y
                continue
            for m in range(m_max):
                r = node[e, m]
                if r >= 0:
                    y += w0[e, m] * tab[load, r]
                    y += w1[e, m] * tab[load, r + 1]
            out[load, e] = y


def table_values(
    c: Any, k: Any, s: Any, tab: Any, col0: int, zero: Any
) -> None:  # pragma: no cover - compiled (its plain-Python form is tested)
    """``Phi``'s look-up table (:meth:`~._phi._Phi._table`, loads by rows): ``tab[r, :zero[r]]
    = 0`` and, from column ``zero[r] >= col0`` on, ``max(spline, 0)`` of row ``r`` at the
    point ``p = column - col0`` (interval ``k[p]``, local abscissa ``s[p]``), the operations of
    :func:`~._compiled.spline_values` in its order. A load's columns below its own first
    non-zero node (less the margin) are not evaluated; the loads in blocks of 8 (a cache line
    of the coefficients ``c`` (4, n_int, n_row)), the points along each block's rows."""
    n_row, width = tab.shape
    for r in range(n_row):
        for j in range(zero[r]):
            tab[r, j] = 0.0
    for r0 in range(0, n_row, 8):
        r1 = min(r0 + 8, n_row)
        first = width
        for r in range(r0, r1):
            first = min(first, zero[r])
        for j in range(first, width):
            p = j - col0
            i, sp = k[p], s[p]
            z = sp * sp
            z3 = z * sp
            for r in range(r0, r1):
                if j < zero[r]:
                    continue
                v = c[2, i, r] * sp + c[3, i, r] + c[1, i, r] * z + c[0, i, r] * z3
                if not v > 0.0 and v == v:  # np.maximum(v, 0.0): +0.0 for -0.0, NaN kept
                    v = 0.0
                tab[r, j] = v


def phi_cumsum(
    inc: Any, p0: Any
) -> None:  # pragma: no cover - compiled (its plain-Python form is tested)
    """``inc[r] = cumsum(inc[r] / p0[r])`` in place (:class:`~._phi._Phi`'s node integrals,
    (n_load, n_int)): numpy's division and sequential ``add.accumulate``, row by row."""
    for r in range(inc.shape[0]):
        p = p0[r]
        t = inc[r, 0] / p
        inc[r, 0] = t
        for j in range(1, inc.shape[1]):
            t = t + inc[r, j] / p
            inc[r, j] = t


#: The kernels of this module, built with those of :mod:`._compiled`.
KERNELS = (df_logs, df_sums, table_sums, table_values, phi_cumsum)
