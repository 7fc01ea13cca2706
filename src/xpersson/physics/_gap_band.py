"""Band-limited sums over (load, bin) terms for the gap kernels (private).

Each term of :func:`~xpersson.physics.gap_pdf` or :func:`~xpersson.physics.gap_cdf` varies only
inside a band of ``u`` around its centre (a Gaussian is exactly 0 farther than 38.6 widths, an
``erf`` exactly +-1 farther than 6): on the README spectrum about half of the dense
(term, ``u``) tensor is such constant. Here each term is evaluated on a window of columns that
holds its band (terms of similar width padded to a common width, blocks kept cache-sized) and
the windows are summed per load with ``np.bincount``; the constant parts outside the windows
are added by the caller (a difference array and one ``cumsum``). The windows are laid out
``(width, terms)``: the per-term factors broadcast along long rows.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

#: Elements per window block (about 128 kB of float64: the blocks' temporaries and the
#: ``erf`` table stay in the 1 MB level-2 cache; 4x larger blocks ran 2-3x slower).
_WIN_BLOCK = 1 << 14


def pairs(
    weight: NDArray[np.float64], negligible: float = 0.0
) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """(load, bin) indices of the terms that count (:func:`counted`); ordered by load, then
    bin."""
    return np.nonzero(counted(weight, negligible))


def counted(weight: NDArray[np.float64], negligible: float = 0.0) -> NDArray[np.bool_]:
    """The (load, bin) terms that count: non-zero weight (NaN kept), optionally not below
    ``negligible`` times the load's largest ``|weight|``."""
    nz = weight != 0.0
    if negligible > 0.0:
        with np.errstate(invalid="ignore"):
            scale = np.max(np.abs(weight), axis=1, initial=0.0, keepdims=True)
            nz &= ~(np.abs(weight) < negligible * scale)
    return nz


def dominant(
    r: NDArray[np.float64], s: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``r`` and ``s`` at the terms no earlier one in decreasing ``r`` reaches in ``s`` (every
    term where either has a NaN): for each term ``p`` one ``q`` kept with ``r_q >= r_p`` and
    ``s_q >= s_p``. So a value non-increasing in both, as ``gap_cdf``'s series limit
    ``(c_n - r) / d_n - s`` (``d_n > 0``; each operation correctly rounded, so monotone), has
    its minimum over every term among these, bit for bit (a few dozen of thousands)."""
    if np.isnan(r).any() or np.isnan(s).any():
        return r, s
    order = np.argsort(-r)
    s_o = s[order]
    keep = np.ones(r.size, dtype=bool)
    keep[1:] = s_o[1:] > np.maximum.accumulate(s_o)[:-1]
    return r[order[keep]], s_o[keep]


def sorted_rows(u: NDArray[np.float64]) -> bool:
    """True when every row of ``u`` (n_row, n_u) is non-decreasing and free of NaN."""
    with np.errstate(invalid="ignore"):
        return bool(np.all(u[:, 1:] >= u[:, :-1])) and not np.isnan(u[:, :1]).any()


def rank(u: NDArray[np.float64], row: NDArray[np.intp], x: NDArray[np.float64]) -> NDArray:
    """Number of entries of ``u[row[t]]`` below ``x[t]``, per term ``t`` (sorted rows of ``u``).

    Each count is first guessed as if the row were geometric from its second entry on (the
    leakage cells: ``0, u_1, u_1 r, ...``) and kept where the row's entries around it confirm
    it; the others by a vectorised bisection (``log2(n_u) + 1`` steps over those terms at
    once). NaN ``x`` gives 0.
    """
    n_u = u.shape[1]
    flat = u.ravel()
    if u.shape[0] == 1:  # one row: numpy's own
        return np.searchsorted(flat, x, side="left").astype(np.intp)
    base = row * n_u
    out = np.zeros(x.size, dtype=np.intp)
    todo = np.arange(x.size)
    if n_u > 2:
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            ln1 = np.log(u[:, 1])
            step = (np.log(u[:, -1]) - ln1) / (n_u - 2)
            g = np.ceil((np.log(x) - ln1[row]) / step[row])
        g = np.minimum(np.where(g > 0.0, g, 0.0), n_u - 1).astype(np.intp) + 1  # NaN -> 1
        g[~(x > np.take(flat, base))] = 0  # at most the row's first entry (or NaN)
        left = np.take(flat, base + np.maximum(g - 1, 0))
        right = np.take(flat, base + np.minimum(g, n_u - 1))
        ok = ((g == 0) | (left < x)) & ((g == n_u) | (right >= x))
        out[ok] = g[ok]
        todo = np.flatnonzero(~ok)
        if not todo.size:
            return out
    base, xt = base[todo], x[todo]
    lo = np.zeros(todo.size, dtype=np.intp)
    hi = np.full(todo.size, n_u, dtype=np.intp)
    for _ in range(int(n_u).bit_length()):
        mid = (lo + hi) >> 1
        below = np.take(flat, base + np.minimum(mid, n_u - 1)) < xt
        below &= mid < hi
        lo = np.where(below, mid + 1, lo)
        hi = np.where(below, hi, mid)
    out[todo] = lo
    return out


def windowed_sum(
    load: NDArray[np.intp],
    j0: NDArray[np.intp],
    j1: NDArray[np.intp],
    shape: tuple[int, int],
    values: Callable[[NDArray[np.intp], NDArray[np.intp]], NDArray[np.float64]],
) -> NDArray[np.float64]:
    """``sum_t values_t[u]`` over each term's window of columns ``[j0, j1)``, per load.

    Parameters
    ----------
    load, j0, j1 : ndarray of int, (n_term,)
        Each term's load and the columns ``[j0, j1)`` it is evaluated on (0 elsewhere).
    shape : (int, int)
        ``(n_load, n_u)`` of the result.
    values : callable
        ``values(terms, cols)`` gives the terms' values ``(w, n)`` on the columns ``cols``
        ``(w, n)`` (terms along the rows: per-term factors broadcast as ``x[terms]``). Terms
        of similar width are padded to a common one, the padding columns set to ``n_u`` (a
        dump column: its values, which must be finite, are dropped); where that would pad
        by more than half, each window's columns are laid along one row ``(1, n)`` instead,
        with ``terms`` (n,) repeated per column.

    Returns
    -------
    ndarray, (n_load, n_u)
        Sum of the windows' values.
    """
    n_load, n_u = shape
    width = j1 - j0
    order, ws, blocks, flat = window_plan(width)
    out = np.zeros(n_load * (n_u + 1))
    slot = np.empty(out.size, dtype=np.intp)  # scratch of _add (never read before written)
    if flat:  # widths spread: no padding
        _flat(order[ws > 0], j0, width, load, n_u, values, out, slot)
        blocks = []
    for i, c, w in blocks:
        sel = order[i : i + c]
        cols = np.arange(w)[:, None] + j0[sel]  # (w, n): long rows, the terms along them
        if ws[i] < w:
            cols = np.where(cols < j1[sel], cols, n_u)
        v = values(sel, cols)
        cols += load[sel] * (n_u + 1)
        _add(out, cols.ravel(), v.ravel(), slot)
    return out.reshape(n_load, n_u + 1)[:, :n_u]


def window_plan(
    width: NDArray[np.intp],
) -> tuple[NDArray[np.intp], NDArray[np.intp], list[tuple[int, int, int]], bool]:
    """:func:`windowed_sum`'s blocks: the terms by width (``order``, ``ws`` their widths), runs
    ``(first, count, padded width)`` of ``order`` (empty windows left out), and whether the
    windows are laid flat (unpadded, :func:`flat_cuts`) instead: padding would add over half."""
    order = stable_order(width)
    ws = width[order]
    i = int(np.searchsorted(ws, 1))  # empty windows: nothing to evaluate
    blocks = []
    while i < order.size:
        # the largest run of terms whose padded block (count x widest) fits the block size
        size = np.arange(1, order.size - i + 1) * ws[i:]
        c = max(1, int(np.searchsorted(size, _WIN_BLOCK, side="right")))
        blocks.append((i, c, int(ws[i + c - 1])))
        i += c
    return order, ws, blocks, sum(c * w for _, c, w in blocks) > 1.5 * float(np.sum(ws))


def stable_order(key: NDArray[np.intp]) -> NDArray[np.intp]:
    """``np.argsort(key, kind="stable")`` of integer keys: the same permutation (a stable order
    is unique), by numpy's radix sort where the keys fit 16 bits (widths of cells, slots of
    loads and cells: 8x faster than the merge sort of 64-bit keys at 6000 terms)."""
    if key.size and -(1 << 15) <= int(key.min()) and int(key.max()) < (1 << 15):
        return np.argsort(key.astype(np.int16), kind="stable")
    return np.argsort(key, kind="stable")


def flat_cuts(wt: NDArray[np.intp]) -> NDArray[np.intp]:
    """Where :func:`_flat` splits terms of window widths ``wt`` (all > 0) into blocks of
    about :data:`_WIN_BLOCK` elements (``np.split`` indices)."""
    ends = np.cumsum(wt)
    cut = np.searchsorted(ends, np.arange(1, int(ends[-1]) // _WIN_BLOCK + 1) * _WIN_BLOCK)
    return cut + 1


def _add(
    out: NDArray[np.float64], idx: NDArray[np.intp], v: NDArray[np.float64], slot: NDArray[np.intp]
) -> None:
    """``out += np.bincount(idx, weights=v, minlength=out.size)``, bit for bit, in time
    linear in ``idx.size`` (not ``out.size``: a block's sums over every load's columns made the
    sum quadratic in the number of loads). Each touched entry gets the block's sum of its
    values in input order, as ``np.bincount`` forms it; untouched entries are left alone
    (``x + 0.0 == x``: ``out`` never holds ``-0.0``, a sum started at ``0.0`` never is).

    ``slot`` (``out.size``, any content): scratch shared by the blocks. Each element's entry
    is named by the last element of the block that writes it (``slot[idx] = arange``, read
    back at once): one bin per touched entry without sorting (``np.unique`` sorted every
    block: 12 % of ``gap_pdf`` at 1000 loads); the bins' sums are ``np.bincount``'s own."""
    lo, hi = int(idx.min()), int(idx.max()) + 1
    if hi - lo <= 4 * idx.size:  # a narrow span: a slice of out
        out[lo:hi] += np.bincount(idx - lo, weights=v, minlength=hi - lo)
        return
    order = np.arange(idx.size)
    slot[idx] = order
    rep = slot[idx]  # the entry's representative element (the same for all its elements)
    sums = np.bincount(rep, weights=v, minlength=idx.size)
    first = np.flatnonzero(rep == order)  # one element per touched entry
    out[idx[first]] += sums[first]


def _flat(
    terms: NDArray[np.intp],
    j0: NDArray[np.intp],
    width: NDArray[np.intp],
    load: NDArray[np.intp],
    n_u: int,
    values: Callable[[NDArray[np.intp], NDArray[np.intp]], NDArray[np.float64]],
    out: NDArray[np.float64],
    slot: NDArray[np.intp],
) -> None:
    """:func:`windowed_sum`'s windows of ``terms`` unpadded: each element of a window one
    column of a single row ``(1, n)`` (its term repeated), in blocks of about ``_WIN_BLOCK``
    elements; the sums added to ``out`` (flat, ``n_load * (n_u + 1)``; ``slot``: :func:`_add`'s)."""
    wt = width[terms]
    cut = flat_cuts(wt)
    for sel, w in zip(np.split(terms, cut), np.split(wt, cut), strict=True):
        if not sel.size:
            continue
        t = np.repeat(sel, w)
        offset = np.cumsum(w) - w
        cols = np.arange(t.size) - np.repeat(offset - j0[sel], w)
        v = values(t, cols[None, :])
        cols += load[t] * (n_u + 1)
        _add(out, cols, v.ravel(), slot)
