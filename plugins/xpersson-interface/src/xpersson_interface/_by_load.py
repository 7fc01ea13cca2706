"""Many loads through a table in the load (private): ``gap_pdf`` and ``leakage`` at a cost per
load that does not grow with the number of loads.

The direct path costs about 100 us per load (the dense re-solve of the curve, ``Phi``, the
detachment's sub-problem sums, the Gaussian sums of 256 separations per load), ten to
eighty times the batched solve of the same loads. Every output of these analyses is a smooth
function of the load: the area curve of a ``load_similar`` boundary depends on ``p0`` only
through ``tau/p0^2``, and each output is an integral of it. So above :data:`TABLE_MIN`
distinct loads only the *node* loads are computed directly: a subset of the requested loads,
about 1/:data:`PER_DECADE` decade apart in ``ln p0`` (the lowest and the highest load always
among them). Every other load takes each output from the Lagrange polynomial through the
:data:`ORDER` nearest nodes in ``ln p0``, of the output's logarithm (every output here is
positive: near full contact the detached area falls super-exponentially, its logarithm stays
a smooth function of ``ln p0``; the gap density is taken element by element, floored at
:data:`FLOOR`).

**Error, estimated per load and checked.** The table at twice the spacing (the even nodes)
interpolates the odd nodes; its largest relative error among the odd nodes of a load's
stencil, times :data:`SCALE`, is the load's estimate (a polynomial through ``ORDER`` points
has an error ``~ h^ORDER``: halving the spacing divides it by ``2^ORDER = 64``; :data:`SCALE`
= 1/4 keeps a factor 16 in reserve for round-off and the exact path's own noise, ~1e-6 of
``Phi``'s linear table). The error is measured against each load's largest value: of the row
for ``gap_pdf`` (its largest density), of the value itself for every other output. A load
whose estimate exceeds :data:`TOL`, or whose stencil holds a non-finite or non-positive value
(sealed, a flooded effective medium, an empty row), is computed directly, unless the two
nodes around it hold the same such value (both sealed: a load between two sealed loads is
sealed, since the contact area grows with the load). The estimate is written to the output
per load (0 for the loads computed directly).

Up to :data:`TABLE_MIN` distinct loads, or where the nodes would be more than half of them,
every load is computed directly, as before (bit for bit).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "DEPTH",
    "FLOOR",
    "ORDER",
    "PER_DECADE",
    "SCALE",
    "TABLE_MIN",
    "TOL",
    "by_load",
    "subset",
]

#: Distinct loads from which the table is used.
TABLE_MIN = 400
#: Node loads per decade of ``p0`` (the spacing of the table).
PER_DECADE = 32
#: Points of each interpolating polynomial (degree ``ORDER - 1``).
ORDER = 6
#: Largest estimated relative error of an interpolated load; above it the load is computed.
TOL = 1e-4
#: The estimate: this times the error of the table at twice the spacing.
SCALE = 16.0
#: Smallest density interpolated in logarithm (below: this; the error stays below it).
FLOOR = 1e-300
#: Rows' errors are relative to the larger of the row's largest value and this fraction of the
#: largest over every load (a row 1e-57 of the others, near full contact, is 0 to this).
DEPTH = 1e-30

Exact = Callable[[NDArray[np.intp]], dict[str, NDArray[np.float64]]]


def by_load(
    p0: NDArray[np.float64],
    exact: Exact,
    steps: frozenset[str] = frozenset(),
    tol: float = TOL,
) -> tuple[dict[str, NDArray[np.float64]], NDArray[np.float64]]:
    """The outputs of every load (``{name: (n_load, ...)}``) and the estimated error per load.

    ``exact(rows)`` gives the outputs of the loads ``p0[rows]`` computed directly (arrays with
    the loads along the first axis: per-load values or rows of them, all positive where
    regular); ``steps`` names the flags among them (0/1: never interpolated).
    """
    p0 = np.asarray(p0, dtype=float)
    n = p0.size
    if n < TABLE_MIN or not np.all(np.isfinite(p0) & (p0 > 0.0)):
        return exact(np.arange(n)), np.zeros(n)
    xs, first, inverse = np.unique(np.log(p0), return_index=True, return_inverse=True)
    nodes = _nodes(xs, math.log(10.0) / PER_DECADE)
    if nodes.size < 2 * ORDER or 2 * nodes.size > xs.size:
        return exact(np.arange(n)), np.zeros(n)
    at = exact(first[nodes])
    logs = {k: _log(v) for k, v in at.items() if k not in steps}
    xn = xs[nodes]
    check = _check(xn, at, logs, steps)  # (n_node,): error at twice the spacing, at the odd nodes
    rest = np.setdiff1d(np.arange(xs.size), nodes)
    vals, bad = _interpolate(xn, at, logs, xs[rest], steps)
    idx, _ = _stencil(xn, xs[rest])
    est = np.max(check[idx], axis=1) * SCALE
    est[bad] = np.inf
    direct = est > tol
    out = {k: np.empty((xs.size,) + v.shape[1:]) for k, v in at.items()}
    for k, v in at.items():
        out[k][nodes] = v
        out[k][rest] = vals[k]
    err = np.zeros(xs.size)
    err[rest] = est
    if direct.any():
        again = rest[direct]
        more = exact(first[again])
        for k, v in more.items():
            out[k][again] = v
        err[again] = 0.0
    return {k: v[inverse] for k, v in out.items()}, err[inverse]


def _nodes(xs: NDArray[np.float64], h: float) -> NDArray[np.intp]:
    """Indices of sorted ``xs`` about ``h`` apart: each node the last value within ``h`` of
    the one before (at least the next), the last value always included."""
    out = [0]
    last = xs.size - 1
    while out[-1] < last:
        i = out[-1]
        j = int(np.searchsorted(xs, xs[i] + h, side="right")) - 1
        out.append(min(max(j, i + 1), last))
    return np.asarray(out, dtype=np.intp)


def _log(v: NDArray[np.float64]) -> NDArray[np.float64]:
    """The logarithm of the values (rows: floored at :data:`FLOOR`; per-load values: NaN where
    not finite and positive)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        if v.ndim > 1:
            return np.log(np.maximum(v, FLOOR))
        return np.where(np.isfinite(v) & (v > 0.0), np.log(np.where(v > 0.0, v, 1.0)), np.nan)


def _stencil(xn: NDArray[np.float64], x: NDArray[np.float64]) -> tuple[NDArray, NDArray]:
    """The :data:`ORDER` nodes around each ``x`` (indices, (n, ORDER)) and their Lagrange
    weights."""
    m = ORDER
    i = np.clip(np.searchsorted(xn, x, side="right") - m // 2, 0, xn.size - m)
    idx = i[:, None] + np.arange(m)
    X = xn[idx]
    w = np.ones((x.size, m))
    for a in range(m):
        for b in range(m):
            if a != b:
                w[:, a] *= (x - X[:, b]) / (X[:, a] - X[:, b])
    return idx, w


def _interpolate(
    xn: NDArray[np.float64],
    at: dict[str, NDArray[np.float64]],
    logs: dict[str, NDArray[np.float64]],
    x: NDArray[np.float64],
    steps: frozenset[str],
) -> tuple[dict[str, NDArray[np.float64]], NDArray[np.bool_]]:
    """Every output at ``x`` from the nodes ``xn`` and whether a load's stencil is unusable
    (``steps``: flags, taken where both nodes around agree)."""
    idx, w = _stencil(xn, x)
    bad = np.zeros(x.size, dtype=bool)
    around = np.searchsorted(xn, x, side="right")  # the node above x (x strictly inside)
    lo, hi = np.clip(around - 1, 0, xn.size - 1), np.clip(around, 0, xn.size - 1)
    out = {}
    for k, v in at.items():
        L = logs.get(k)
        if v.ndim > 1:
            out[k] = _rows(L, idx, w)
            bad |= ~np.all(np.all(np.isfinite(v), axis=1)[idx], axis=1)
            continue
        if k in steps:  # a flag: the value of both nodes around, where they agree
            y = v[lo].copy()
            bad |= v[lo] != v[hi]
            out[k] = y
            continue
        regular = np.isfinite(L)
        y = np.exp(np.einsum("nk,nk->n", w, np.where(regular, L, 0.0)[idx]))
        irregular = ~np.all(regular[idx], axis=1)
        # both nodes around hold the same irregular value (NaN, 0 or inf): that value
        same = irregular & ~regular[lo] & ~regular[hi] & _same(v[lo], v[hi])
        y[same] = v[lo][same]
        bad |= irregular & ~same
        out[k] = y
    return out, bad


def _same(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.bool_]:
    return (a == b) | (np.isnan(a) & np.isnan(b))


def _rows(L: NDArray[np.float64], idx: NDArray, w: NDArray) -> NDArray[np.float64]:
    """``exp(sum_k w_k L[idx_k])`` per row, in blocks of rows that stay in the cache."""
    n = idx.shape[0]
    out = np.empty((n, L.shape[1]))
    step = max(1, 2**17 // max(L.shape[1], 1))
    for s in range(0, n, step):
        t = slice(s, s + step)
        acc = out[t]
        np.multiply(L[idx[t, 0]], w[t, 0, None], out=acc)
        for k in range(1, idx.shape[1]):
            acc += L[idx[t, k]] * w[t, k, None]
        np.exp(acc, out=acc)
    return out


def _check(
    xn: NDArray[np.float64],
    at: dict[str, NDArray[np.float64]],
    logs: dict[str, NDArray[np.float64]],
    steps: frozenset[str],
) -> NDArray[np.float64]:
    """Per node: the relative error of the even nodes' table at the node (odd nodes; 0 at the
    even ones), the largest over the outputs (inf where unusable)."""
    odd = np.arange(1, xn.size, 2)
    even = np.arange(0, xn.size, 2)
    sub = {k: v[even] for k, v in at.items() if k not in steps}  # flags: per load only
    logs_even = {k: v[even] for k, v in logs.items()}
    vals, bad = _interpolate(xn[even], sub, logs_even, xn[odd], steps)
    err = np.zeros(odd.size)
    for k in sub:
        top = float(np.nanmax(np.abs(np.where(np.isfinite(at[k]), at[k], 0.0))))
        err = np.maximum(err, _relative(vals[k], at[k][odd], top))
    err[bad] = np.inf
    out = np.zeros(xn.size)
    out[odd] = err
    return out


def _relative(
    y: NDArray[np.float64], exact: NDArray[np.float64], top: float = 0.0
) -> NDArray[np.float64]:
    """``|y - exact|`` relative to each load's largest ``|exact|``, at least :data:`DEPTH`
    times ``top`` (the largest over every load); 0 where both are the same irregular value,
    inf where only one is."""
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


def subset(ctx: Any, ds: Any, rows: NDArray[np.intp]) -> tuple[Any, Any]:
    """The analysis context and Dataset of the loads ``rows`` alone (their ``solve_at``
    re-solves those loads of the same solve); all loads: ``ctx`` and ``ds`` themselves."""
    p0 = np.atleast_1d(np.asarray(ctx.p0, dtype=float))
    if rows.size == p0.size and np.array_equal(rows, np.arange(p0.size)):
        return ctx, ds
    solve_at = getattr(ctx, "solve_at", None)
    if solve_at is not None:
        whole = solve_at

        def solve_at(zeta: Any, loads: Any = None, tau: Any = None) -> Any:
            sel = rows if loads is None else rows[np.asarray(loads, dtype=int)]
            return whole(zeta, sel, tau)

    sub = dataclasses.replace(ctx, p0=p0[rows], solve_at=solve_at)
    return sub, ds.isel(p0=rows)
