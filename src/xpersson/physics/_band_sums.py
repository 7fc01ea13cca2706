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

from ._fasterf import _C0, _C1, _C2, _C3, _N, _X_ONE

__all__ = ["band_sums"]

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
