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

__all__ = ["TAIL", "tail_floor", "tail_stop"]

#: Largest ratio [1] of a pair's left-out term to its load's density (on every column left out).
TAIL = 1e-18
#: Weight [1] relative to the load's heaviest above which a pair may be the wide reference.
WIDE_MIN = 1e-3


def tail_floor(
    ls: Any, ks: Any, a: Any, w: Any, u_h: Any, floor: Any
) -> None:  # pragma: no cover - compiled (its plain-Python form is tested)
    """``floor[l, j] = ln TAIL + max_q (ln w_q - (b_qj - a_q)^2/2)`` over the two reference
    pairs ``q`` of load ``l`` (arguments as :func:`~._compiled.gap_rows`'); ``floor``
    (n_load, n_u) is given filled with ``-inf``, which stays on loads with a negative weight
    or none positive (nothing left out there)."""
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
    log_tail = math.log(TAIL)
    for load in range(n_load):
        if negative[load] or heavy[load] < 0:
            continue
        for q in (heavy[load], wide[load]):
            lw, aq, row = log_tail + math.log(w[q]), a[q], u_h[ks[q]]
            for j in range(n_u):
                x = row[j] - aq
                v = lw - 0.5 * (x * x)
                if v > floor[load, j]:
                    floor[load, j] = v


def tail_stop(
    row: Any, ap: float, wp: float, floor_row: Any, lo: int, hi: int
) -> int:  # pragma: no cover - compiled (its plain-Python form is tested)
    """One past the last column of ``[lo, hi)`` where the bound ``2 wp exp(-(b - ap)^2/2)`` of
    a pair (``b = row[j]``) reaches ``exp(floor_row[j])`` (:func:`tail_floor`); ``lo`` when
    none does. A zero weight reaches only ``-inf``; a negative one every column."""
    lu = math.log(2.0 * wp) if wp > 0.0 else (-math.inf if wp == 0.0 else math.inf)
    for j in range(hi - 1, lo - 1, -1):
        x = row[j] - ap
        if lu - 0.5 * (x * x) >= floor_row[j]:
            return j + 1
    return lo
