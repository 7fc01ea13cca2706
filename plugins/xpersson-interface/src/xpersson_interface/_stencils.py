"""The load table's stencils (private, :mod:`._by_load`): each output's logarithm (or its
transform) interpolated in ``ln p0`` by the Lagrange polynomial through the nearest nodes of
its segment (runs of nodes alike in every key and in which outputs are regular)."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from ._stencil_sums import stencil_rows, sums

#: Smallest density interpolated in logarithm (below: this; the error stays below it).
FLOOR = 1e-300
#: Rows' errors are relative to the larger of the row's largest value and this fraction of the
#: largest over every load (a row 1e-57 of the others, near full contact, is 0 to this).
DEPTH = 1e-30
#: A row's interpolated element above ``SPIKE`` times every value of that element at its
#: stencil's nodes, or above ``SPIKE`` times the row's largest element interpolated in its own
#: right (the logarithm of each node's row maximum, through the same weights), is no
#: interpolation of a smooth row: the load is unusable (refined, or computed directly). Only
#: where the element is above ``SPIKE_SIZE`` of that maximum (at least :data:`DEPTH` of the
#: largest over the nodes: the scale of the rows' errors, :func:`_relative`): a smaller
#: overshoot lies within every estimate's allowance for the direct path's own irregularity
#: (at least ``2 _by_load.NOISE``). A smooth row resolved to the table's tolerance does
#: neither. The check at the odd nodes cannot see elements that change by hundreds of decades
#: between nodes, small at every node: their polynomials in the logarithm rose to 1.8 times
#: the row's maximum (``gap_pdf``, ``separation = "almqvist"``, 1000 loads on the speed design;
#: with the first test alone: up to 3e-3), to 1.3e6 times (the same on a 9-decade spectrum)
#: and to 6e9 times (``method = "diffusion"``; with the second test alone: 9e2). Both forms
#: are now computed directly (``_params.UNTABLED``); the tests stay for any other row that is
#: not smooth in the load (``benchmarks/load_table_extreme.py``).
SPIKE, SPIKE_SIZE = 2.0, 1e-5
#: Runs of one stencil in a block of rows above which :func:`_rows` gathers each row's limits
#: rather than testing run by run (a run costs ~15 us of numpy calls, a gathered row ~0.3 us).
_RUNS = 8
#: Outputs tabled transformed, ``(names, f)``: ``f(outputs, x)`` gives per load ``(W, S)``
#: (``W > 0``) from the other outputs (interpolated first) and ``x = ln p0``, and each output
#: ``v`` named is tabled as ``W ln v - S``: a known singularity made regular (the leak
#: analysis: ``ln u1 ~ f/W`` as ``zeta_c`` approaches the largest magnification; the effective
#: medium's conductance ``~ S`` as the contact approaches its sealing value).
Weight = tuple[
    frozenset[str],
    Callable[
        [dict[str, NDArray[np.float64]], NDArray[np.float64]],
        tuple[NDArray[np.float64], NDArray[np.float64]],
    ],
]
#: The outputs' roles: the keys (never interpolated) and the transformed outputs.
_Roles = tuple[frozenset[str], tuple[Weight, ...]]


def _logs(
    at: dict[str, NDArray[np.float64]], roles: _Roles, xn: NDArray[np.float64]
) -> dict[str, NDArray[np.float64]]:
    """The tabled logarithm of every output but the keys at the nodes ``xn`` (transformed
    outputs: ``W ln v - S``; the per-load outputs' in one pass, element by element the
    same)."""
    keys, weights = roles
    one = [k for k, v in at.items() if k not in keys and v.ndim == 1]
    stacked = dict(zip(one, _log(np.array([at[k] for k in one])), strict=True)) if one else {}
    logs = {k: stacked.get(k) for k in at if k not in keys}
    logs = {k: _log(at[k], True) if v is None else v for k, v in logs.items()}  # (rows)
    for names, f in weights:
        W, S = f(at, xn)
        for k in names:
            logs[k] = logs[k] * W - S
    return logs


def _log(v: NDArray[np.float64], rows: bool = False) -> NDArray[np.float64]:
    """The logarithm of the values (rows: floored at :data:`FLOOR`; per-load values, stacked
    or not: NaN where not finite and positive)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        if rows:
            return np.log(np.maximum(v, FLOOR))
        return np.where(np.isfinite(v) & (v > 0.0), np.log(np.where(v > 0.0, v, 1.0)), np.nan)


def _segments(at: dict[str, NDArray[np.float64]], keys: frozenset[str]) -> NDArray[np.intp]:
    """Per node, the number of its segment: runs of nodes alike in every key and in which
    outputs are regular (finite and, per-load values, positive); the keys and the per-load
    outputs each in one pass."""
    n = next(iter(at.values())).shape[0]
    change = np.zeros(max(n - 1, 0), dtype=bool)
    key = [at[k] for k in at if k in keys]
    if key:
        c = np.array(key)
        c = np.where(np.isnan(c), np.inf, c)
        change |= np.any(c[:, 1:] != c[:, :-1], axis=0)
    one = [v for k, v in at.items() if k not in keys and v.ndim == 1]
    if one:
        c = np.array(one)
        c = np.isfinite(c) & (c > 0.0)
        change |= np.any(c[:, 1:] != c[:, :-1], axis=0)
    for k, v in at.items():
        if k not in keys and v.ndim > 1:
            c = np.all(np.isfinite(v), axis=1)
            change |= c[1:] != c[:-1]
    return np.concatenate(([0], np.cumsum(change)))


def _stencil(
    xn: NDArray[np.float64],
    x: NDArray[np.float64],
    seg: NDArray[np.intp],
    m: int,
    seg_x: NDArray[np.intp] | None = None,
    lz: NDArray[np.float64] | None = None,
    vals: NDArray[np.float64] | None = None,
) -> tuple[NDArray, NDArray, NDArray, NDArray, NDArray, NDArray, NDArray | None]:
    """The ``m`` nodes around each ``x`` (indices, (n, m)), their Lagrange weights, the sums
    of the weights' magnitudes (the Lebesgue function), the weighted sums of each row of
    ``lz`` (n_out, n_node: per node a logarithm, 0 where not finite), where there are none,
    the node below each ``x`` and (compiled; else None) per row of ``vals`` (the outputs'
    values) whether each stencil's values are alike (:func:`_alike`): all within the
    segment of the two nodes around ``x`` (``seg``; shifted to one side near its ends),
    unusable where those two differ or the segment holds fewer than ``m`` nodes. ``seg_x``:
    each ``x``'s own segment, where known (a node checked by the others: one-sided past its
    segment's last node of the others). The sums compiled where built (:mod:`._stencil_sums`:
    the same numbers, bit for bit)."""
    lz = np.zeros((0, xn.size)) if lz is None else lz
    got = sums(xn, x, seg, seg_x, m, lz, lz if vals is None else vals)
    if got is not None:
        return got
    around = np.clip(np.searchsorted(xn, x, side="right"), 1, xn.size - 1)
    lo = around - 1
    if seg_x is None:
        bad = seg[lo] != seg[around]
        seg_x = seg[lo]
    else:
        bad = np.zeros(x.size, dtype=bool)
    first = np.searchsorted(seg, seg_x, side="left")  # the first node of x's segment
    last = np.searchsorted(seg, seg_x, side="right") - 1
    bad |= last - first + 1 < m
    i = np.clip(around - m // 2, first, np.maximum(last - m + 1, first))
    i = np.clip(i, 0, xn.size - m)
    idx = i[:, None] + np.arange(m)
    w = _lagrange(xn, x, i, m)
    ys = np.array([np.einsum("nk,nk->n", w, z[idx]) for z in lz]).reshape(lz.shape[0], x.size)
    return idx, w, np.sum(np.abs(w), axis=1), ys, bad, lo, None


def _lagrange(
    xn: NDArray[np.float64], x: NDArray[np.float64], i: NDArray[np.intp], m: int
) -> NDArray[np.float64]:
    """The Lagrange weights ``w_a = prod_{b != a} (x - X_b)/(X_a - X_b)`` of the ``m`` nodes
    ``X`` from ``xn[i]`` on, each product in the order ``b = 0 .. m-1``: one pass per ``b``
    over all ``a`` (its factor ``q_bb`` set to 1: a multiplication by 1 is exact), (n, m).
    Computed as (m, n), the loads innermost (numpy's loops then run along the loads, not
    along the ``m`` nodes: 4x faster at 826 loads), element by element the same operations."""
    X = xn[i + np.arange(m)[:, None]]  # (b, n)
    num = x - X  # (b, n): x - X_b
    w = np.ones((m, x.size))
    q = np.empty_like(w)  # (a, n): q_ab, one buffer for every b (the same operations)
    with np.errstate(divide="ignore", invalid="ignore"):
        for b in range(m):
            np.subtract(X, X[b], out=q)
            np.divide(num[b], q, out=q)
            q[b] = 1.0
            w *= q
    return np.ascontiguousarray(w.T)  # (the callers' layout: their sums' order kept)


def _interpolate(
    xn: NDArray[np.float64],
    at: dict[str, NDArray[np.float64]],
    logs: dict[str, NDArray[np.float64]],
    x: NDArray[np.float64],
    roles: _Roles,
    m: int,
    segs: tuple[NDArray[np.intp], NDArray[np.intp] | None] | None = None,
    spikes: bool = True,
) -> tuple[dict[str, NDArray[np.float64]], NDArray[np.bool_], NDArray[np.float64], NDArray]:
    """Every output at ``x`` from the nodes ``xn`` (each from nodes of its segment), whether
    a load is unusable (between two segments, or a segment too short) and the sum of its
    weights' magnitudes (the stencil's Lebesgue function), and the stencils (``m`` nodes).
    Weighted outputs last: ``exp`` of their interpolated ``W ln v`` over the load's ``W``
    from the other outputs' interpolated values. ``segs``: the nodes' and the ``x``'s
    segments, where known (:func:`_check`; the ``x``'s None: from the nodes around each).
    ``spikes``: rows that spike (:data:`SPIKE`) unusable (the check at the odd nodes, whose
    loads are nodes, need not test them)."""
    keys, weights = roles
    one = [k for k, v in at.items() if k not in keys and v.ndim == 1]  # (per-load outputs)
    row = {k: j for j, k in enumerate(one)}
    L = np.array([logs[k] for k in one]).reshape(len(one), xn.size)
    regular = np.isfinite(L)
    vals = np.array([at[k] for k in one]).reshape(L.shape)
    seg, seg_x = (_segments(at, keys), None) if segs is None else segs
    got = _stencil(xn, x, seg, m, seg_x, np.where(regular, L, 0.0), vals)
    idx, w, lebesgue, ys, bad, below, alike = got
    lo = idx[:, 0]
    regular_lo = regular[:, lo]  # whether each stencil's first node is regular
    out = {}
    late = {k: f for names, f in weights for k in names}
    done: dict[int, tuple[NDArray[np.bool_], NDArray[np.float64], NDArray[np.float64]]] = {}
    for k, v in sorted(at.items(), key=lambda kv: kv[0] in late):
        if k in keys:
            out[k] = v[lo]
            continue
        if v.ndim > 1:
            out[k], spike = _rows(logs[k], idx, w, spikes)
            bad |= spike
            continue
        at_lo, y = regular_lo[row[k]], ys[row[k]]
        if k in late:
            f = late[k]
            if id(f) not in done:  # once per group (from the outputs interpolated first)
                done[id(f)] = _transform(*f(out, x))
            ok, S, W = done[id(f)]
            bad |= at_lo & ~ok
            y = np.where(ok, (y + S) / W, 0.0)
        with np.errstate(over="ignore"):  # (an extrapolation far off: unusable, below)
            y = np.exp(y)
        bad |= np.isinf(y) & at_lo
        # a segment of irregular values (NaN, 0 or inf): the value, where its nodes agree
        irr = np.flatnonzero(~at_lo)
        if irr.size:
            y[irr] = v[lo[irr]]
            same = alike[row[k], irr] if alike is not None else _alike(v, lo[irr], m)
            bad[irr] |= ~same
        out[k] = y
    flat = _flat(at, regular, below)
    if flat.any():  # (the loads of a sealed stretch and their node below, found once)
        on, node = np.flatnonzero(flat), below[flat]
        for k, v in out.items():
            v[on] = at[k][node]
    return out, bad & ~flat, lebesgue, idx, flat


def _transform(
    W: NDArray[np.float64], S: NDArray[np.float64]
) -> tuple[NDArray[np.bool_], NDArray[np.float64], NDArray[np.float64]]:
    """Where a transform applies (``W > 0``, ``S`` finite) and its ``S`` and ``W`` there (0 and
    1 elsewhere): the tabled ``W ln v - S`` gives ``ln v = (y + S) / W``."""
    ok = (W > 0.0) & np.isfinite(S)
    return ok, np.where(ok, S, 0.0), np.where(ok, W, 1.0)


def _alike(v: NDArray[np.float64], start: NDArray[np.intp], m: int) -> NDArray[np.bool_]:
    """Per stencil (``m`` consecutive nodes from ``start``): whether its values are all alike
    (equal, or all NaN), from the node pairs that differ (a prefix count over the nodes)."""
    differ = np.concatenate(([0], np.cumsum(~_same(v[:-1], v[1:]))))  # before node j
    return differ[start + m - 1] == differ[start]


def _flat(
    at: dict[str, NDArray[np.float64]], regular: NDArray[np.bool_], below: NDArray[np.intp]
) -> NDArray[np.bool_]:
    """The loads (``below``: the node below each) between two nodes alike in every output,
    none of them regular (``regular``: per output but the keys, per node; a sealed stretch:
    its flags, zeros and NaN; exact, for outputs monotone in the load, whatever the segment's
    length), decided per pair of nodes (every output in one pass)."""
    if any(v.ndim > 1 for v in at.values()):
        return np.zeros(below.size, dtype=bool)
    a = np.array(list(at.values()))  # (n_output, n_node)
    pair = np.all(_same(a[:, :-1], a[:, 1:]) if a.shape[1] > 1 else _same(a, a), axis=0)
    pair &= ~np.any(regular[:, : pair.size], axis=0)  # (nodes j and j + 1: j irregular)
    return pair[below]


def _window_max(c: NDArray[np.float64], idx: NDArray[np.intp]) -> NDArray[np.float64]:
    """``np.max(c[idx], axis=1)`` for stencils of consecutive nodes (``idx``: (n, m), rows
    ``start + 0 .. m-1``): the largest over every window of ``m`` nodes once, then per
    stencil (the same values: a maximum is exact in any order)."""
    m = idx.shape[1]
    if c.size < m:  # (no full window: as numpy's)
        return np.max(c[idx], axis=1)
    return _windows(c, m)[idx[:, 0]]


def _errors(
    vals: dict[str, NDArray[np.float64]],
    at: dict[str, NDArray[np.float64]],
    odd: NDArray[np.intp],
    names: list[str],
) -> NDArray[np.float64]:
    """Per node ``odd``: the largest over the outputs ``names`` of the relative error
    (:func:`_relative`) of ``vals`` against ``at`` there, each at least :data:`DEPTH` times the
    output's largest finite magnitude over ``at``; the per-load outputs in one pass (the same
    operations, element by element)."""
    err = np.zeros(odd.size)
    one = [k for k in names if at[k].ndim == 1]
    if one:
        a = np.array([at[k] for k in one])
        top = np.abs(np.where(np.isfinite(a), a, 0.0)).max(axis=1)  # (no NaN left)
        y = np.concatenate([vals[k] for k in one])
        r = _relative(y, a[:, odd].ravel(), np.repeat(top, odd.size))
        err = np.maximum(err, r.reshape(len(one), odd.size).max(axis=0))
    for k in names:
        if at[k].ndim > 1:
            top = float(np.abs(np.where(np.isfinite(at[k]), at[k], 0.0)).max())  # (no NaN left)
            err = np.maximum(err, _relative(vals[k], at[k][odd], top))
    return err


def _relative(
    y: NDArray[np.float64], exact: NDArray[np.float64], top: float | NDArray[np.float64] = 0.0
) -> NDArray[np.float64]:
    """``|y - exact|`` relative to each load's largest ``|exact|``, at least :data:`DEPTH`
    times ``top`` (the largest over every load; per-load values: per element, where an array);
    0 where both are the same irregular value, inf where only one is."""
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        d = np.abs(y - exact)
        if exact.ndim > 1:
            scale = np.maximum(np.max(np.abs(exact), axis=1), DEPTH * top)
            d = np.max(d, axis=1)
        else:
            scale = np.maximum(np.abs(exact), DEPTH * top)
            d = np.where(_same(y, exact), 0.0, d)
        r = np.where(
            scale > 0.0, d / np.where(scale > 0.0, scale, 1.0), np.where(d > 0, np.inf, 0.0)
        )
    return np.where(np.isnan(r), np.inf, r)


def _same(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.bool_]:
    return (a == b) | (np.isnan(a) & np.isnan(b))


def _rows(
    L: NDArray[np.float64], idx: NDArray, w: NDArray, test: bool = True
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """``exp(sum_k w_k L[idx_k])`` per row, in blocks of rows that stay in the cache, and per
    row whether it spikes (:data:`SPIKE`; rows sorted by their stencils: each run of one
    stencil tested against its nodes' largest elements at once, in the block; ``test``
    False: none tested, none spikes). The sums and the test compiled where built
    (:func:`._stencil_sums.stencil_rows`: the same bits; 3-5x faster at 1000-1e4 loads)."""
    n, m = idx.shape
    out = np.empty((n, L.shape[1]))
    spike = np.zeros(n, dtype=bool)
    if test:
        top, floor, most = _spike_limits(L, idx, w)
    first = idx[:, 0]
    step = max(1, 2**17 // max(L.shape[1], 1))
    for s in range(0, n, step):
        t = slice(s, min(s + step, n))
        acc = out[t]
        if stencil_rows(L, idx, w, out, spike, (top, floor, most) if test else None, t):
            np.exp(acc, out=acc)  # (the sums and the test compiled: one pass, no gathers)
            continue
        np.multiply(L[idx[t, 0]], w[t, 0, None], out=acc)
        for k in range(1, m):
            acc += L[idx[t, k]] * w[t, k, None]
        if not test:
            np.exp(acc, out=acc)
            continue
        with np.errstate(invalid="ignore"):  # (NaN rows: irregular, bad already)
            spike[t] = np.max(acc, axis=1) > np.maximum(top[t], floor[t])
            cut = np.flatnonzero(np.diff(first[t])) + 1  # (the runs of one stencil)
            if cut.size > _RUNS:  # short runs: every row's limits gathered at once
                spike[t] |= np.any(acc > most[first[t]], axis=1)
            else:  # long runs: each run against its one row of limits (no gather)
                for a, b in zip(np.r_[0, cut], np.r_[cut, acc.shape[0]], strict=True):
                    spike[s + a : s + b] |= np.any(acc[a:b] > most[first[s + a]], axis=1)
        np.exp(acc, out=acc)
    return out, spike


def _spike_limits(
    L: NDArray[np.float64], idx: NDArray, w: NDArray
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """The logarithms of :data:`SPIKE`'s limits for rows interpolated from the nodes' ``L``
    through the stencils ``idx`` (weights ``w``, rows sorted by stencil): per row, ``SPIKE``
    times its largest element interpolated and ``SPIKE_SIZE`` of its scale; per window of
    nodes (by its first), ``SPIKE`` times each element's largest value at them, at least the
    smallest ``SPIKE_SIZE`` limit of its rows (one limit per element and window)."""
    peak = np.max(L, axis=1)  # (per node: the logarithm of its row's largest element)
    with np.errstate(invalid="ignore"):
        top = np.einsum("nk,nk->n", w, peak[idx])  # (the row's largest, interpolated)
        depth = np.max(peak, where=peak == peak, initial=-np.inf) + math.log(DEPTH)
        floor = np.maximum(top, depth) + math.log(SPIKE_SIZE)
        most = _windows(L, idx.shape[1]) + math.log(SPIKE)
        first = idx[:, 0]
        if first.size:
            starts = np.flatnonzero(np.r_[True, first[1:] != first[:-1]])
            runs = first[starts]
            most[runs] = np.maximum(most[runs], np.minimum.reduceat(floor, starts)[:, None])
    return top + math.log(SPIKE), floor, most


def _windows(v: NDArray[np.float64], m: int) -> NDArray[np.float64]:
    """Per window of ``m`` consecutive nodes (by its first node), the largest of each column of
    ``v`` (nodes, columns) over the window (fewer nodes: over all of them)."""
    n = v.shape[0]
    if n < m:  # (every window the whole, for any stencil start a short segment clips to)
        return np.broadcast_to(np.max(v, axis=0), (m,) + v.shape[1:])
    top = v[: n - m + 1].copy()
    for k in range(1, m):
        np.maximum(top, v[k : n - m + 1 + k], out=top)
    return top
