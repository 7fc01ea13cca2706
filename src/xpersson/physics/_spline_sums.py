"""Optional compiled sums of ``Phi``'s spline over sub-problem nodes (numba), bit for bit, and
the solved curve's splines at points shared by every load (:func:`shared_row_values`).

:func:`spline_sub_sums` is the ``spline=True`` branch of
:func:`~xpersson.physics._subgap._sub_mean_gap` (``separation_at``'s difference quotient, per-load
cut-offs): for every (load, edge) the arguments ``ln tau_c + ln A^2``, ``Phi``'s spline at them
(:meth:`~xpersson.physics._phi._Phi.spline_at_log_tau_per_load`: clip to the knots, the
interval by ``searchsorted(side="right") - 1``, Horner, ``max(., 0)``), times the weights,
summed over the nodes in numpy's pairwise order: the same operations as the numpy path, in one
pass without its (loads, edges, nodes) temporaries. Arguments below ``Phi``'s first knot take
the linear first interval (an ``exp``): numpy computes those values (on the gathered arguments
only, the same ``exp``) and the kernel reads them. Built and gated with the kernels of
:mod:`._compiled`.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ._pairwise import _pairwise

__all__ = ["knot_interval", "shared_row_values", "spline_sub_sums"]


def knot_interval(knots: Any, v: float) -> tuple[int, float]:
    """The interval ``i`` of the sorted ``knots`` that holds ``v`` clipped to them (numpy's
    ``searchsorted(side="right") - 1`` clipped to the intervals, by bisection: the same index)
    and ``v - knots[i]``: the look-up of :func:`shared_row_values` and
    :func:`~._compiled.row_values` (compiled with them)."""
    n_knot = knots.size
    first, last = knots[0], knots[n_knot - 1]
    v = v if v > first else first  # np.clip(v, first, last)
    v = v if v < last else last
    lo, hi = 0, n_knot  # the first knot above v
    while lo < hi:
        mid = (lo + hi) // 2
        if knots[mid] <= v:
            lo = mid + 1
        else:
            hi = mid
    i = min(max(lo - 1, 0), n_knot - 2)
    return i, v - knots[i]


def spline_sub_sums(
    lt: Any, kern: Any, lin: Any, b: Any, c: Any, rows: Any, log_tau1: float, out: Any
) -> None:  # pragma: no cover - compiled (its plain-Python form is tested)
    """``out[l, e] = sum_m kern[l, e, m] v[l, e, m]``, ``v`` ``Phi``'s spline of load
    ``rows[l]`` (knots ``b``, coefficients ``c`` (4, n_b - 1, n_load)) at ``lt[l, e, m]``
    (clipped to the knots, ``max(., 0)``), or where ``lt < log_tau1`` the next of ``lin``
    (the linear first interval's values there, in C order); NaN stays NaN. Rows of at most
    :data:`~._compiled.PAIRWISE` nodes (numpy's pairwise order)."""
    n_load, n_edge, m = lt.shape
    nb = b.size
    vals = np.empty(m)
    b0, b1 = b[0], b[nb - 1]
    p = 0
    for r in range(n_load):
        q = rows[r]
        for e in range(n_edge):
            n_le = 0
            for j in range(m):
                x = lt[r, e, j]
                if x < log_tau1:
                    v = lin[p]
                    p += 1
                elif x != x:
                    v = x
                else:
                    s = min(max(x, b0), b1)  # np.clip
                    # searchsorted(b, s, side="right"): the count of knots <= s, walked from
                    # the last node's (the nodes' arguments are monotonic in m: a few steps)
                    while n_le < nb and b[n_le] <= s:
                        n_le += 1
                    while n_le > 0 and b[n_le - 1] > s:
                        n_le -= 1
                    k = min(max(n_le - 1, 0), nb - 2)
                    d = s - b[k]
                    v = ((c[0, k, q] * d + c[1, k, q]) * d + c[2, k, q]) * d + c[3, k, q]
                    if not v > 0.0 and v == v:  # np.maximum(v, 0.0): +0.0 for -0.0
                        v = 0.0
                vals[j] = v * kern[r, e, j]
            out[r, e] = _pairwise(vals, m)


def shared_row_values(
    c: Any, knots: Any, x: Any, out: Any
) -> None:  # pragma: no cover - compiled (its plain-Python form is tested)
    """:func:`~._compiled.row_values` at points ``x`` (1-D, no NaN) shared by every load:
    ``out[r, p]`` (n_load, x.size), each point's clip and interval found once, then every
    load's Horner form (its coefficients read along the loads, contiguously): the same
    operations per element as ``row_values`` on the broadcast points."""
    for p in range(x.size):
        i, d = knot_interval(knots, x[p])
        for r in range(out.shape[0]):
            out[r, p] = ((c[0, i, r] * d + c[1, i, r]) * d + c[2, i, r]) * d + c[3, i, r]
