"""Optional compiled window sums of :func:`~xpersson.physics.gap_cdf`'s ``erf`` terms (numba),
bit for bit the numpy path.

:func:`band_sums` evaluates the terms of :func:`~._gap_band.windowed_sum` for the two kinds of
``_cdf_banded`` (``erf(b - a) + erf(b + a)`` and ``erf(b - a) + 1``, times the weight, with
``b = min(u / (sqrt2 h), 1e150)``) by :func:`~._fasterf.fast_erf`'s table cubic (no ``exp``:
its operations element by element) and sums them per (load, column) as ``np.bincount`` does,
block by block in the order of :func:`~._gap_band.window_plan`: one pass, without the blocks'
index and value temporaries. Padding elements (the dump column) are skipped: their sums were
dropped. Built and gated with the kernels of :mod:`._compiled`.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ._fasterf import _C0, _C1, _C2, _C3, _N, _X_ONE

__all__ = ["band_sums", "series_horner"]

_NODES = float(_N)
_TOP = _X_ONE * _N


def _erf(x: float) -> float:
    """:func:`~._fasterf.fast_erf` of one value (the table is a compiled constant)."""
    t = abs(x) * _NODES
    if t != t:
        return math.nan
    if t > _TOP:  # np.fmin (no NaN here)
        t = _TOP
    i = int(t)
    f = t - i
    return math.copysign(((_C3[i] * f + _C2[i]) * f + _C1[i]) * f + _C0[i], x)


def _erf_nonneg(x: float) -> float:
    """:func:`~._fasterf.erf_nonneg` of one value ``x >= 0`` (no NaN)."""
    t = x * _NODES
    if t > _TOP:
        t = _TOP
    i = int(t)
    f = t - i
    return ((_C3[i] * f + _C2[i]) * f + _C1[i]) * f + _C0[i]


def band_sums(
    out: Any,
    acc: Any,
    touched: Any,
    blocks: Any,
    terms: Any,
    j0: Any,
    j1: Any,
    load: Any,
    n_u: int,
    u2: Any,
    row: Any,
    iv: Any,
    a: Any,
    w: Any,
    kind: int,
) -> None:  # pragma: no cover - compiled (its plain-Python form is tested)
    """Add the window sums of the blocks ``(first, stop, pad)`` (rows of ``blocks``) of
    ``terms`` to ``out`` (flat ``(n_load, n_u + 1)``; ``u2`` flat the same): a padded block
    (``pad > 0`` columns) element by element columns outer, terms inner; a flat one
    (``pad == 0``) terms outer, their columns inner (the orders of
    :func:`~._gap_band.windowed_sum`); each entry's sum formed from 0 in that order and added
    once (``+ 0.0`` for its repeats: ``out`` never holds ``-0.0``). ``kind`` 0: ``erf(b - a) +
    erf(b + a)``, 1: the same with every ``b + a >= 0`` (``erf_nonneg``), 2: ``erf(b - a) +
    1``; times ``w``. ``acc`` (zeros, ``out``'s size) and ``touched`` (int, (2, the largest
    block's elements)): scratch, ``acc`` left as found."""
    nu1 = n_u + 1
    for k in range(blocks.shape[0]):
        first, stop, pad = blocks[k, 0], blocks[k, 1], blocks[k, 2]
        nt = 0  # the block's elements (term, column) in its order
        if pad > 0:
            for m in range(pad):
                for q in range(first, stop):
                    t = terms[q]
                    if j0[t] + m < j1[t]:  # (else the dump column: dropped)
                        touched[0, nt] = t
                        touched[1, nt] = j0[t] + m
                        nt += 1
        else:
            for q in range(first, stop):
                t = terms[q]
                for col in range(j0[t], j1[t]):
                    touched[0, nt] = t
                    touched[1, nt] = col
                    nt += 1
        for n in range(nt):
            t, col = touched[0, n], touched[1, n]
            b = u2[row[t] * nu1 + col] * iv[t]
            if b > 1e150:  # np.minimum (NaN kept)
                b = 1e150
            v = _erf(b - a[t])
            if kind == 2:
                v += 1.0
            elif kind == 1:
                v += _erf_nonneg(b + a[t])
            else:
                v += _erf(b + a[t])
            v *= w[t]
            e = load[t] * nu1 + col
            acc[e] += v
            touched[1, n] = e
        for n in range(nt):
            e = touched[1, n]
            out[e] += acc[e]
            acc[e] = 0.0


def series_horner(
    coef: Any,
    order: Any,
    lu: Any,
    ju: Any,
    slot: Any,
    n_slot: int,
    u2: Any,
    sigma: float,
    start: Any,
    top: int,
    out: Any,
) -> None:  # pragma: no cover - compiled (its plain-Python form is tested)
    """The prefix sums, the column counts and the Horner loop of
    ``_gap_distribution._series_sum`` (pairs ``order``, their loads ``lu``, prefixes ``ju``
    and slots ``slot``), numpy's operations on each element in its order.

    ``acc[n, slot + 1, lu] = coef[n, order]`` from zeros, then the running sums along the
    slots (numpy's sequential ``cumsum`` of ``acc[:, 1:]``: the first copied); per load ``l``
    and column ``j < top``, ``k`` the number of its pairs with ``ju > j``, ``e = k n_load + l``
    (clipped as ``np.take(mode="clip")``) and ``x = min(u2[l, j] sigma, 1e150)`` (``u2[0,
    j]`` when ``u2`` has one row): ``r = (r + acc[n, e]) x^2`` over the terms ``n = n_term -
    1 .. 1`` with ``start[n] <= j`` (from ``r = 0``), then ``out[l, j] = (r + acc[0, e]) x``
    (the columns from ``top`` on are left as found)."""
    n_term, n_load = coef.shape[0], out.shape[0]
    acc = np.zeros((n_term, n_slot, n_load))
    counts = np.zeros((n_load, top + 1), dtype=np.intp)
    for p in range(order.size):
        counts[lu[p], ju[p]] += 1
        for n in range(n_term):
            acc[n, slot[p] + 1, lu[p]] = coef[n, order[p]]
    for n in range(n_term):
        for m in range(2, n_slot):
            for l in range(n_load):
                acc[n, m, l] = acc[n, m - 1, l] + acc[n, m, l]
    flat = acc.reshape(n_term, n_slot * n_load)
    size = n_slot * n_load
    r, x, x2 = np.empty(top), np.empty(top), np.empty(top)
    e = np.empty(top, dtype=np.intp)
    for l in range(n_load):
        ul = l if u2.shape[0] > 1 else 0  # one row of u shared by every load
        k = 0
        for j in range(top - 1, -1, -1):
            k += counts[l, j + 1]
            i = k * n_load + l
            e[j] = 0 if i < 0 else (size - 1 if i >= size else i)
        for j in range(top):
            v = u2[ul, j] * sigma
            if v > 1e150:  # np.minimum (NaN kept)
                v = 1e150
            x[j], x2[j], r[j] = v, v * v, 0.0
        for n in range(n_term - 1, 0, -1):
            for j in range(start[n], top):
                r[j] = (r[j] + flat[n, e[j]]) * x2[j]
        for j in range(top):
            out[l, j] = (r[j] + flat[0, e[j]]) * x[j]
