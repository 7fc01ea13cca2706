"""The load table's stencils (private, :mod:`._stencils`) and nodes (:mod:`._by_load`) in an
optional compiled form (numba): the numbers of the numpy path, bit for bit.

Per load, :func:`._stencils._stencil` finds the ``m`` nodes of its segment, their Lagrange
weights (:func:`._stencils._lagrange`), their magnitudes' sum (the Lebesgue function) and, per
per-load output, the weighted sum of the nodes' logarithms (``einsum("nk,nk->n")``); and
whether each stencil's values agree (:func:`._stencils._alike`). In numpy these are ~60
passes over (8, n) or (n,) arrays: inside a 1000-load leak analysis (4 calls, ~830 and ~90
loads) the weights, Lebesgue and weighted sums alone took ~0.65 ms (timers in the solve,
2026-11-30); :func:`stencil_sums` does it all in ~0.2 ms, one load at a time, with the numpy
path's operations in its order:

- the stencil's indices as ``np.searchsorted`` and ``np.clip`` give them (integers: exact);
- ``w_a = prod_{b != a} (x - X_b)/(X_a - X_b)``, each factor's subtraction and division as
  there, the product from ``1`` in the order ``b = 0 .. m-1`` (times ``q_aa = 1`` as there);
- ``np.sum(np.abs(w), axis=1)`` in numpy's pairwise order (:func:`._newton._block_sum`, the
  stencil at most 128 points), added to the reduction's identity 0;
- ``np.einsum("nk,nk->n", w, Lz[idx])`` in the order of numpy's baseline SIMD loop
  (:func:`._newton._einsum_dot`), onto the zeroed output.

:func:`node_chain` is :func:`._by_load._nodes` (integers: exact) in one walk up the loads.
:func:`row_sums` is :func:`._stencils._rows`' weighted sums of the nodes' rows (``gap_pdf``'s
densities, the logarithms) and its spike test in one pass per row, each product and sum rounded
as numpy's (``exp`` stays numpy's): at 1e4 loads x 256 gap points numpy's gathers and
temporaries took ~45 ms of the row path's ~65, the kernel ~13 (2026-12-02).
It runs only where numba is already imported in the process (the physics' compiled kernels
import it once their work pays), ``xpersson.set_options(compiled=...)`` is on, and this
numpy's reductions take the orders reproduced (:func:`._newton.numpy_orders`, checked once);
otherwise the numpy path runs. The equality is asserted in
``plugins/xpersson-interface/tests/test_stencil_sums.py``.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ._newton import _block_sum, _einsum_dot, compiled

__all__ = [
    "MAX_POINTS",
    "chain",
    "kernel",
    "node_chain",
    "row_sums",
    "stencil_rows",
    "stencil_sums",
    "sums",
]

#: Largest stencil (points) the compiled sums take (:func:`._newton._block_sum`'s one block).
MAX_POINTS = 128

_STATE: dict[str, Any] = {}  # "fns": the compiled kernels once built (None: numba missing)


def kernel(name: str = "stencil_sums") -> Callable[..., Any] | None:
    """The compiled :func:`stencil_sums` (or :func:`node_chain`, :func:`row_sums`), or None:
    the option is off, or numba is not imported in this process, or missing, or this numpy's
    orders are others (built as :func:`._newton.kernel`, with its summation helpers)."""
    fns = compiled(_STATE, (stencil_sums, node_chain, row_sums), __name__)
    return None if fns is None else fns[name]


def chain(xs: NDArray[np.float64], h: float) -> NDArray[np.intp] | None:
    """:func:`._by_load._nodes` compiled (the indices of sorted ``xs`` about ``h`` apart), or
    None where the kernel is not built."""
    fn = kernel("node_chain")
    if fn is None or not xs.size:
        return None
    out = np.empty(xs.size, dtype=np.intp)
    return out[: fn(np.ascontiguousarray(xs, dtype=float), float(h), out)]


def node_chain(xs: Any, h: float, out: Any) -> int:  # pragma: no cover - compiled
    """Into ``out``: from index 0, each node the last value within ``h`` of the one before
    (``xs[j] + h``, as numpy's sum; at least the next), the last value always included; their
    number. One walk up the values (the successor only grows with the node)."""
    last = xs.size - 1
    out[0] = 0
    k, j, i = 1, 0, 0
    while j < last:
        t = xs[j] + h
        i = max(i, j)
        while i < last and xs[i + 1] <= t:
            i += 1
        j = min(max(i, j + 1), last)
        out[k] = j
        k += 1
    return k


def sums(
    xn: NDArray[np.float64],
    x: NDArray[np.float64],
    seg: NDArray[np.intp],
    seg_x: NDArray[np.intp] | None,
    m: int,
    lz: NDArray[np.float64],
    vals: NDArray[np.float64],
) -> tuple[NDArray, NDArray, NDArray, NDArray, NDArray, NDArray, NDArray] | None:
    """:func:`._stencils._stencil` compiled (the stencils, weights, Lebesgue sums, weighted
    sums of each row of ``lz`` (n_out, n_node), unusable loads, the node below each load, and
    per row of ``vals`` (the outputs' values at the nodes) whether each stencil's values are
    alike:
    :func:`._stencils._alike`), or None where the kernel is not built or the stencil does not
    fit (fewer nodes than ``m`` or than 2, more than :data:`MAX_POINTS` points)."""
    fn = kernel() if m <= MAX_POINTS and xn.size >= max(m, 2) else None
    if fn is None:
        return None
    idx, w = np.empty((x.size, m), dtype=np.intp), np.empty((x.size, m))
    leb, y = np.empty(x.size), np.empty((lz.shape[0], x.size))
    bad, below = np.empty(x.size, dtype=np.bool_), np.empty(x.size, dtype=np.intp)
    own = seg_x is not None
    sx = np.asarray(seg_x if own else seg[:0], dtype=np.intp)
    alike = np.empty(y.shape, dtype=np.bool_)
    sg = np.asarray(seg, dtype=np.intp)
    fn(xn, x, sg, sx, own, m, lz, vals, idx, w, leb, y, alike, bad, below)
    return idx, w, leb, y, bad, below, alike


def stencil_sums(
    xn: Any,
    x: Any,
    seg: Any,
    seg_x: Any,
    own: bool,
    m: int,
    lz: Any,
    vals: Any,
    idx: Any,
    w: Any,
    leb: Any,
    y: Any,
    alike: Any,
    bad: Any,
    below: Any,
) -> None:  # pragma: no cover - compiled (its plain-Python form is tested)
    """Per load ``p``: its stencil ``idx[p]`` (``m`` nodes of its segment, as
    :func:`._stencils._stencil`), their weights ``w[p]`` at ``x[p]``, ``leb[p]`` the sum of
    their magnitudes, ``y[o, p]`` their sum with ``lz[o]``, ``alike[o, p]`` whether
    ``vals[o]`` is alike on them (equal, or all NaN), ``bad[p]`` whether unusable,
    ``below[p]`` the node below ``x[p]``."""
    n = xn.size
    nodes, mag, g, v = np.empty(m), np.empty(m), np.empty(m), np.empty(m)
    right, first, last, known = 0, 0, 0, -1  # (the searches of the load before, reused)
    differ = np.zeros((lz.shape[0], n), dtype=np.intp)  # node pairs that differ before each
    for o in range(lz.shape[0]):
        for j in range(1, n):
            a0, a1 = vals[o, j - 1], vals[o, j]
            differ[o, j] = differ[o, j - 1] + (not (a0 == a1 or (a0 != a0 and a1 != a1)))
    for p in range(x.size):
        xp = x[p]
        if p and xp >= x[p - 1]:  # sorted loads: the first node above x walked up to
            while right < n and xn[right] <= xp:
                right += 1
        else:
            right = np.searchsorted(xn, xp, side="right")
        around = min(max(right, 1), n - 1)
        lo = around - 1
        sp = seg_x[p] if own else seg[lo]
        if sp != known or not p:  # the first and last node of the segment
            first = np.searchsorted(seg, sp, side="left")
            last = np.searchsorted(seg, sp, side="right") - 1
            known = sp
        bad[p] = (not own and seg[lo] != seg[around]) or last - first + 1 < m
        below[p] = lo
        s = min(max(around - m // 2, first), max(last - m + 1, first))
        s = min(max(s, 0), n - m)
        for b in range(m):
            idx[p, b] = s + b
            nodes[b] = xn[s + b]
            v[b] = 1.0
        for b in range(m):  # the factors of every weight at once (a loop numba vectorizes)
            num, xb = xp - nodes[b], nodes[b]
            for a in range(m):
                q = num / (nodes[a] - xb)
                v[a] = v[a] * (q if a != b else 1.0)
        for a in range(m):
            w[p, a] = v[a]
            mag[a] = abs(v[a])
        leb[p] = 0.0 + _block_sum(mag, 0, m)
        for o in range(lz.shape[0]):
            for k in range(m):
                g[k] = lz[o, s + k]
            y[o, p] = 0.0 + _einsum_dot(v, g, m)
            alike[o, p] = differ[o, s + m - 1] == differ[o, s]


def stencil_rows(
    L: NDArray[np.float64],
    idx: NDArray[np.intp],
    w: NDArray[np.float64],
    out: NDArray[np.float64],
    spike: NDArray[np.bool_],
    limits: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]] | None,
    rows: slice,
) -> bool:
    """:func:`._stencils._rows`' weighted sums and spike test of the rows ``rows`` compiled
    (:func:`row_sums`, before the ``exp``), or False where the kernel is not built (nothing
    written) or a row is empty. ``limits``: :func:`._stencils._spike_limits`' (None: no test)."""
    fn = kernel("row_sums") if L.shape[1] else None
    if fn is None:
        return False
    test = limits is not None
    top, floor, most = limits if test else (_NONE_1, _NONE_1, _NONE_2)
    fn(L, idx, w, rows.start, rows.stop, test, top, floor, most, out, spike)
    return True


_NONE_1, _NONE_2 = np.empty(0), np.empty((0, 0))


def row_sums(
    L: Any,
    idx: Any,
    w: Any,
    r0: int,
    r1: int,
    test: bool,
    top: Any,
    floor: Any,
    most: Any,
    out: Any,
    spike: Any,
) -> None:  # pragma: no cover - compiled (its plain-Python form is tested)
    """Rows ``r0 .. r1 - 1``: ``out[r] = sum_k w[r, k] L[idx[r, k]]`` as numpy's
    ``L[idx[:, 0]] * w[:, 0]`` then ``+= L[idx[:, k]] * w[:, k]`` (each product rounded, then
    each sum: the same bits), and with ``test`` ``spike[r]``: the row's largest element above
    ``max(top[r], floor[r])`` (numpy's NaN rules: a NaN element or limit tests False) or any
    element above its limit ``most[idx[r, 0]]``."""
    m, nc = idx.shape[1], L.shape[1]
    for r in range(r0, r1):
        i0, w0 = idx[r, 0], w[r, 0]
        for c in range(nc):
            out[r, c] = L[i0, c] * w0
        for k in range(1, m):
            ik, wk = idx[r, k], w[r, k]
            for c in range(nc):
                out[r, c] += L[ik, c] * wk
        if not test:
            continue
        mx, nan, hit = -np.inf, False, False
        for c in range(nc):
            v = out[r, c]
            if v != v:
                nan = True
            elif v > mx:
                mx = v
            if v > most[i0, c]:
                hit = True
        t, f = top[r], floor[r]
        if not nan and t == t and f == f and mx > max(t, f):
            hit = True
        spike[r] = hit
