"""The negligible tails of the gap distribution's Gaussians (of :func:`~._compiled.gap_rows`).

A load's density on a column, ``S_j = sum_p t_p(j)`` with
``t_p = w_p [N(b; a_p) + N(b; -a_p)]`` (unit Gaussians of ``b = u/h_p``, ``a_p, b >= 0``), is
at least each of its terms when no weight is negative; in particular at least
``w_q exp(-(b - a_q)^2/2)`` of two reference pairs ``q`` of the load: its heaviest and, among
those of at least 1e-3 of that weight, its widest (largest ``h``: the far tail's). A term is at
most ``2 w_p exp(-(b - a_p)^2/2)`` (the mirror term is the smaller). On the columns beyond the
last one where that bound reaches :data:`TAIL` of the references' bound, the pair is not
summed: each density then changes by at most ``n_pairs TAIL`` of itself (``n_bins 1e-18``;
8e-17 at the default 80 bins), element by element at every size. On the speed design's
scenes that leaves out 35-45 % of the (pair, column) elements of the recurrence: the wide
Gaussians' tails dominate where the narrow ones' still lie above the exponent's underflow.

Both kernels are compiled with :func:`~._compiled.gap_rows` (plain Python without numba).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = ["LOG_TAIL", "TAIL", "tail_floor", "tail_stop"]

#: Largest ratio [1] of a pair's left-out term to its load's density (on every column left out).
TAIL = 1e-18
LOG_TAIL = math.log(TAIL)
#: Weight [1] relative to the load's heaviest above which a pair may be the wide reference.
WIDE_MIN = 1e-3


def tail_floor(
    ls: Any, ks: Any, a: Any, w: Any, u_h: Any, floor: Any, refs: Any
) -> None:  # pragma: no cover - compiled (its plain-Python form is tested)
    """``floor[l, j] = ln TAIL + max_q (ln w_q - (b_qj - a_q)^2/2)`` over the two reference
    pairs ``q`` of load ``l`` (arguments as :func:`~._compiled.gap_rows`'); ``floor``
    (n_load, n_u) is given filled with ``-inf``, which stays on loads with a negative weight
    or none positive (nothing left out there). ``refs`` (n_load, 2, 3), given NaN: the
    references' grid step in ``b``, centre and ``ln w`` (for :func:`tail_stop`)."""
    n_load, n_u = floor.shape
    top = np.zeros(n_load)
    heavy = np.full(n_load, -1, dtype=np.int64)
    wide = np.full(n_load, -1, dtype=np.int64)
    negative = np.zeros(n_load, dtype=np.bool_)
    for p in range(ls.size):
        if w[p] < 0.0:
            negative[ls[p]] = True
        elif w[p] > top[ls[p]]:
            top[ls[p]], heavy[ls[p]] = w[p], p
    for p in range(ls.size):  # the widest: the smallest span of b over the grid
        q = wide[ls[p]]
        span = u_h[ks[p], n_u - 1] - u_h[ks[p], 0]
        if w[p] > 0.0 and w[p] >= WIDE_MIN * top[ls[p]]:
            if q < 0 or span < u_h[ks[q], n_u - 1] - u_h[ks[q], 0]:
                wide[ls[p]] = p
    for load in range(n_load):
        if negative[load] or heavy[load] < 0:
            continue
        for r, q in enumerate((heavy[load], wide[load])):
            lw, aq, row = LOG_TAIL + math.log(w[q]), a[q], u_h[ks[q]]
            refs[load, r, 0] = (row[n_u - 1] - row[0]) / (n_u - 1)
            refs[load, r, 1], refs[load, r, 2] = aq, math.log(w[q])
            for j in range(n_u):
                x = row[j] - aq
                v = lw - 0.5 * (x * x)
                if v > floor[load, j]:
                    floor[load, j] = v


def tail_stop(
    row: Any, ap: float, wp: float, floor: Any, load: int, lo: int, hi: int, refs: Any
) -> int:  # pragma: no cover - compiled (its plain-Python form is tested)
    """One past the last column of ``[lo, hi)`` where the bound ``2 wp exp(-(b - ap)^2/2)`` of
    a pair of load ``load`` (``b = row[j]``) reaches ``exp(floor[load, j])``
    (:func:`tail_floor`); ``lo`` when none does. A zero weight reaches only ``-inf``; a
    negative one every column.

    The columns are tested from the last down, from where a reference wider than the pair
    (``refs[load]``: :func:`tail_floor`'s) leaves it out on every column beyond: the larger
    root of the quadratic ``(j d - ap)^2 - (j d_q - a_q)^2 = 2 ln(2 wp / (TAIL w_q)) + 2``
    (a factor ``e`` of margin), plus one column.
    """
    lu = math.log(2.0 * wp) if wp > 0.0 else (-math.inf if wp == 0.0 else math.inf)
    start, n = hi, row.size
    if wp > 0.0 and n > 1:
        d = (row[n - 1] - row[0]) / (n - 1)
        for r in range(2):
            dq = refs[load, r, 0]
            c2 = d * d - dq * dq
            if not c2 > 0.0:  # not wider (or no reference: NaN)
                continue
            aq = refs[load, r, 1]
            c1 = -2.0 * (d * ap - dq * aq)
            c0 = ap * ap - aq * aq - (2.0 * (lu - LOG_TAIL - refs[load, r, 2]) + 2.0)
            disc = c1 * c1 - 4.0 * c2 * c0
            root = -math.inf if disc < 0.0 else (math.sqrt(disc) - c1) / (2.0 * c2)
            if root + 2.0 < start:  # (false for NaN)
                start = max(lo, int(max(root, -1.0)) + 2)
    for j in range(start - 1, lo - 1, -1):
        x = row[j] - ap
        if lu - 0.5 * (x * x) >= floor[load, j]:
            return j + 1
    return lo
