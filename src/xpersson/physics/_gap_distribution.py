"""Gap distribution from detached-area bins :cite:p:`almqvist2011`."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.special import erf

from . import _gap_band
from ._compiled import kernel as _compiled_kernel
from ._compiled import uniform_from_zero
from ._curve import _TINY
from ._fasterf import ERF_DIFF_B, erf_diff_coefficients, erf_nonneg, fast_erf
from ._fastnum import _BLOCK, _EXP_LO, _exp
from ._gap_band import _WIN_BLOCK, flat_cuts, pairs, rank, sorted_rows, window_plan, windowed_sum

__all__ = ["Detachment", "gap_pdf", "gap_cdf", "gap_mean"]

_SQRT2 = math.sqrt(2.0)


@dataclass(frozen=True)
class Detachment:
    """Detached-area bins of the gap distribution (SI units, per load).

    Attributes
    ----------
    p0 : ndarray, (n_load,)
        Nominal pressures [Pa].
    zeta : ndarray, (n_edge,)
        Bin edges [1] (the curve's magnifications, optionally refined).
    area : ndarray, (n_load, n_edge)
        Contact area fraction at the edges [1].
    ubar : ndarray, (n_load, n_edge)
        Mean separation of the apparent contact at the edges [m] (``ubar[:, 0] = u(p0)``).
    weight : ndarray, (n_load, n_bin)
        Detached area per bin ``A_{k-1} - A_k`` [1].
    u1 : ndarray, (n_load, n_bin)
        Mean separation of the area detaching in the bin [m].
    h : ndarray, (n_bin,)
        rms height of the roughness finer than the bin's (geometric) midpoint [m].
    h_rms : float
        rms height of the roughness up to the last edge [m].
    """

    p0: NDArray[np.float64]
    zeta: NDArray[np.float64]
    area: NDArray[np.float64]
    ubar: NDArray[np.float64]
    weight: NDArray[np.float64]
    u1: NDArray[np.float64]
    h: NDArray[np.float64]
    h_rms: float

    @property
    def contact(self) -> NDArray[np.float64]:
        """Contact fraction at the last edge [1] (weight of ``delta(u)``), (n_load,)."""
        return self.area[:, -1]

    @property
    def mean_gap(self) -> NDArray[np.float64]:
        """Persson's mean separation ``u(p0)`` [m], (n_load,)."""
        return self.ubar[:, 0]


def _by_pairs(
    weight: NDArray[np.float64],
    n_u: int,
    kernel: Callable[[NDArray, NDArray], NDArray],
    negligible: float = 0.0,
    block: int = _BLOCK,
) -> NDArray[np.float64]:
    """``sum_k weight[l, k] kernel(l, k)[u]`` per load, over the non-zero weights only.

    ``kernel(ls, ks)`` gives the rows ``(n_pair, n_u)`` of the (load, bin) pairs ``ls, ks``.
    Bins that detach no area (most bins near zeta = 1 at high load, 60 % on the README
    spectrum) contribute exactly 0 and are skipped; pairs are taken in blocks of loads whose
    tensors stay in the cache. ``negligible`` > 0 also skips the bins whose weight is below
    that fraction of the load's largest.
    """
    n_load = weight.shape[0]
    out = np.zeros((n_load, n_u))
    nz = weight != 0.0  # NaN weights kept (they propagate as before)
    if negligible > 0.0:
        with np.errstate(invalid="ignore"):
            scale = np.max(np.abs(weight), axis=1, initial=0.0, keepdims=True)
            nz &= ~(np.abs(weight) < negligible * scale)
    cum = np.cumsum(nz.sum(axis=1)) * max(n_u, 1)
    start = 0
    while start < n_load:
        base = cum[start - 1] if start else 0
        stop = max(start + 1, int(np.searchsorted(cum, base + block, side="right")))
        ls, ks = np.nonzero(nz[start:stop])
        ls += start
        if ls.size:
            vals = kernel(ls, ks)
            vals *= weight[ls, ks][:, None]
            first = np.flatnonzero(np.concatenate(([True], ls[1:] != ls[:-1])))
            out[ls[first]] = np.add.reduceat(vals, first, axis=0)
        start = stop
    return out


#: Half-widths of the bands where the terms vary, with a margin: a Gaussian is exactly 0 beyond
#: 38.61 widths (``exp(-745.14)`` underflows to 0) and an ``erf`` exactly +-1 beyond 5.93.
_GAUSS_BAND = 39.0
_ERF_BAND = 5.3
#: ``|b - a|`` below which ``exp(-(b - a)^2/2)`` stays normal (exponent above -708).
_EXP_SAFE = math.sqrt(-2.0 * _EXP_LO)


def _bands(
    u: NDArray[np.float64],
    row: NDArray[np.intp],
    centre: NDArray[np.float64],
    inv: NDArray[np.float64],
    half: float,
    *finite: NDArray[np.float64],
) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """Columns ``[j0, j1)`` of ``u[row]`` where ``|u inv - centre| < half`` (whole row for
    terms with a non-finite ``centre``, bound or any of ``finite``: evaluated everywhere)."""
    with np.errstate(over="ignore", invalid="ignore"):
        lo, hi = (centre - half) / inv, (centre + half) / inv
    j0, j1 = rank(u, row, lo), rank(u, row, hi)
    ok = np.isfinite(lo) & np.isfinite(hi)
    for f in finite:
        ok &= np.isfinite(f)
    j0[~ok], j1[~ok] = 0, u.shape[1]
    return j0, np.maximum(j1, j0)


def gap_pdf(det: Detachment, u: ArrayLike) -> NDArray[np.float64]:
    """Continuous part ``rho(u)`` of the gap distribution [1/m], shape (n_load, n_u).

    ``rho = sum_k weight_k [N(u; u1_k, h_k^2) + N(u; -u1_k, h_k^2)]`` for ``u >= 0`` (the mirror
    term keeps detached area out of contact); ``int_0^inf rho = 1 - A(zeta_max)``. For sorted
    ``u`` each bin is evaluated only within 39 of its widths of ``u1`` (exactly 0 beyond).
    """
    u = np.asarray(u, dtype=float)
    inv_h = 1.0 / np.maximum(det.h, _TINY)  # (n_bin,)
    with np.errstate(over="ignore", invalid="ignore"):  # u / h per bin, gathered per pair
        u_h = np.minimum(u[None, :] * inv_h[:, None], 1e150)  # (n_bin, n_u)
    weight = det.weight * inv_h / math.sqrt(2.0 * math.pi)
    fast = _compiled_pdf(det, u, u_h, inv_h, weight)
    if fast is not None:
        return fast

    def kernel(b: NDArray, a: NDArray, plain: bool = False) -> NDArray[np.float64]:
        """``exp(-(b - a)^2/2) (1 + exp(-2 a b))``, ``b`` overwritten. ``plain``: no exponent
        below -708 (``|b - a| < 37.6``, ``2ab < 708``): numpy's exp needs no guard there."""
        with np.errstate(under="ignore", over="ignore", invalid="ignore"):
            d = b - a
            d *= d
            d *= -0.5
            e = np.exp(d) if plain else _exp(d)  # mirror pair: N(u - u1) (1 + exp(-2uu1/h^2))
            b *= -2.0 * a  # = (b a) (-2) bit for bit: scaling by 2 is exact (|b a| <= 1e300)
            if not plain:
                np.maximum(b, _EXP_LO, out=b)  # 1 + exp(x) is exactly 1 below: same factor
            m = np.exp(b, out=b)
            m += 1.0
            e *= m
        return e

    def centre(ls: NDArray, ks: NDArray) -> NDArray[np.float64]:
        with np.errstate(under="ignore", over="ignore", invalid="ignore"):
            return np.minimum(det.u1[ls, ks] * inv_h[ks], 1e150)  # finite

    if u.ndim != 1 or not u.size or not sorted_rows(u[None, :]):
        return _by_pairs(weight, u.size, lambda ls, ks: kernel(u_h[ks], centre(ls, ks)[:, None]))
    ls, ks = pairs(weight)
    a, w = centre(ls, ks), weight[ls, ks]
    # pairs whose exponents stay above -708 on the whole grid (b is monotone: check the ends)
    # as whole rows, unguarded; the others on the columns within 39 widths of u1
    with np.errstate(over="ignore", invalid="ignore"):
        lo, hi = u_h[ks, 0] - a, u_h[ks, -1] - a
        full = (
            (np.abs(lo) < _EXP_SAFE)
            & (np.abs(hi) < _EXP_SAFE)
            & (a * u_h[ks, -1] < _EXP_SAFE**2 / 4)
        )
    full &= np.isfinite(w)
    dense = np.zeros_like(weight)
    dense[ls[full], ks[full]] = w[full]
    rho = _by_pairs(
        dense,
        u.size,
        lambda l_, k_: kernel(u_h[k_], centre(l_, k_)[:, None], True),
        0.0,
        _WIN_BLOCK,
    )
    part = np.flatnonzero(~full)
    ls, ks, a, w = ls[part], ks[part], a[part], w[part]
    j0, j1 = _bands(u[None, :], np.zeros_like(ls), a, inv_h[ks], _GAUSS_BAND, w)
    u_h = np.concatenate((u_h, np.zeros((u_h.shape[0], 1))), axis=1)  # + the dump column

    def values(t: NDArray, cols: NDArray) -> NDArray[np.float64]:
        e = kernel(np.take(u_h, ks[t] * (u.size + 1) + cols), a[t])
        e *= w[t]
        return e

    return rho + windowed_sum(ls, j0, j1, rho.shape, values)


def _compiled_pdf(
    det: Detachment, u: NDArray, u_h: NDArray, inv_h: NDArray, weight: NDArray
) -> NDArray[np.float64] | None:
    """:func:`gap_pdf` by the compiled recurrence (:mod:`._compiled`), or None where it
    does not apply (grid not uniform from 0, infinite or negative terms, kernel off). A NaN
    weight or centre spoils its load's row only, as in the numpy path."""
    if not uniform_from_zero(u):
        return None
    ls, ks = pairs(weight)
    fn = _compiled_kernel(ls.size * u.size)
    if fn is None:
        return None
    with np.errstate(under="ignore", over="ignore", invalid="ignore"):
        a = np.minimum(det.u1[ls, ks] * inv_h[ks], 1e150)
    w = weight[ls, ks]
    if np.any(np.isinf(a) | np.isinf(w) | (a < 0.0)):
        return None
    nan = np.isnan(a) | np.isnan(w)
    out = np.zeros((weight.shape[0], u.size))
    fn(ls[~nan], ks[~nan], a[~nan], w[~nan], np.ascontiguousarray(u_h), out)
    out[ls[nan]] = np.nan
    return out


def _erf_terms_dense(det: Detachment, u: NDArray, inv: NDArray, negligible: float) -> NDArray:
    """``sum w [erf(b - a) + erf(b + a)]`` over every (pair, ``u``): any ``u`` (unsorted)."""
    rows = u.ndim == 2

    def kernel(ls: NDArray, ks: NDArray) -> NDArray[np.float64]:
        with np.errstate(over="ignore", invalid="ignore"):
            a = np.minimum(det.u1[ls, ks] * inv[ks], 1e150)[:, None]  # no inf - inf below
            b = np.minimum((u[ls] if rows else u[None, :]) * inv[ks, None], 1e150)
            lo = fast_erf(b - a)
            b += a
            lo += fast_erf(b, out=b)
        return lo

    return _by_pairs(det.weight, u.shape[-1], kernel, negligible, _WIN_BLOCK)


def gap_cdf(det: Detachment, u: ArrayLike, *, negligible: float = 0.0) -> NDArray[np.float64]:
    """``int_0^u rho du'`` [1], shape (n_load, n_u) (add the contact weight for the full CDF).

    ``u`` (n_u,) shared by every load, or (n_load, n_u) per load. ``negligible`` > 0 leaves
    out the bins whose detached weight is below that fraction of the load's largest (near
    full contact ``dA`` spans hundreds of decades: 20 % of the non-zero bins on the README
    spectrum lie below 1e-30); each value then changes by at most that fraction of the
    load's detached area, but far-tail values made of such bins alone change entirely.

    ``erf`` is :func:`~xpersson.physics._fasterf.fast_erf` (within 1.7e-13 of the exact one),
    so each value is within ``2e-13 (1 - A)`` of the exact sum, plus round-off. For ``u >= 0``
    sorted along each row, each ``erf`` is evaluated only where it differs from +-1 by more
    than ``erfc(5.3) = 6.6e-14``, ``erf(a + b) - erf(a - b)`` by its Taylor series in
    ``b = u/(sqrt2 h) <= 1`` (within 2e-14), and the result is made non-decreasing along the
    row (the exact CDF is; the correction stays within the same bound). Other ``u``: every
    element, densely.
    """
    u = np.asarray(u, dtype=float)
    inv = 1.0 / (_SQRT2 * np.maximum(det.h, _TINY))
    rows = u.ndim == 2
    u2 = u if rows else u[None, :]
    if not (u2.shape[1] and sorted_rows(u2) and np.all(u2[:, 0] >= 0.0)):
        return 0.5 * _erf_terms_dense(det, u, inv, negligible)
    return _cdf_banded(det, u2, inv, rows, negligible)


#: Relative size (to the load's detached weight) below which the tail of a pair's series is
#: dropped on a column, and Cramer's bound ``K_n`` on ``|c_n(a)| exp(a^2/2)`` (the tail from
#: term ``n`` on stays below ``2 K_n b^(2n+1)`` for ``b <= 1``: each next bound < 0.47x).
_SERIES_TAU = 1e-18
_K = np.log(
    [
        2.0
        * (4.0 / math.sqrt(math.pi))
        * 1.0865
        * math.sqrt(4.0**n * math.factorial(2 * n))
        / math.factorial(2 * n + 1)
        for n in range(16)
    ]
)


def _series_sum(
    ls: NDArray, jt: NDArray, a: NDArray, w: NDArray, iv: NDArray, u2: NDArray, n_load: int
) -> NDArray[np.float64]:
    """``sum_k w [erf(a + b) - erf(a - b)]`` over each load's pairs on their columns ``[0, jt)``
    (where ``b = u iv <= 1``), as one polynomial in ``x = u sigma`` per (load, column).

    Pairs (all finite, ``jt > 0``) ordered by load. Coefficients ``w c_n (iv/sigma)^(2n+1)``;
    a column's polynomial sums those of the pairs whose prefix holds it, accumulated from the
    largest ``jt`` down (no differences: every term stays bounded by ``w |c_n|`` where it is
    used). Term ``n`` is evaluated only from the first column (of any row) where some pair's
    tail from ``n`` on may exceed ``_SERIES_TAU`` times its load's weight: each value changes
    by at most ``1e-18`` times the number of its load's pairs times that weight.
    """
    n_u = u2.shape[1]
    out = np.zeros((n_load, n_u))
    sigma = float(np.max(iv))
    q = iv / sigma
    coef = erf_diff_coefficients(a, w * q, q * q)  # (n_term, n_pair)
    n_term = coef.shape[0]
    # the first column where term n may count: ln u >= (ln tau - ln(2 K_n w/W) + a^2/2)/(2n+1)
    aw = np.abs(w)
    ln_rel = np.log(aw / np.bincount(ls, aw, minlength=n_load)[ls]) - 0.5 * np.minimum(a, 6.0) ** 2
    ln_rel, ln_iv = _gap_band.dominant(ln_rel, np.log(iv))  # (each term's minimum is theirs)
    with np.errstate(divide="ignore"):
        lim = (math.log(_SERIES_TAU) - _K[:, None] - ln_rel) / (2 * np.arange(n_term) + 1)[:, None]
    lim = np.exp(np.min(lim - ln_iv, axis=1))  # (n_term,) [m]
    # columns below it in every row: below it in the rows' column-wise largest entries
    start = np.searchsorted(np.max(u2, axis=0), lim, side="left")
    start = np.minimum.accumulate(start[::-1])[::-1]  # non-decreasing in n
    top = int(np.max(jt))  # no pair's prefix holds a column beyond
    # per load, the longest prefix first (np.lexsort((-jt, ls))'s order; the pairs come by
    # load, so the merge sort of the one key runs through nearly sorted data: 10x faster)
    order = np.argsort(ls * (top + 1) + (top - jt), kind="stable")
    lu, ju = ls[order], jt[order]
    first = np.searchsorted(lu, lu)  # slot of each pair within its load
    slot = np.arange(lu.size) - first
    n_slot = int(slot.max()) + 2
    fn = _compiled_kernel(float(n_term * top * n_load), "series_horner")
    if fn is not None:  # the loops below element by element (the same bits)
        fn(coef, order, lu, ju, slot, n_slot, u2, sigma, start, top, out)
        return out
    acc = np.zeros((n_term, n_slot, n_load))
    acc[:, slot + 1, lu] = coef[:, order]
    # acc[:, m, l]: the m longest prefixes of load l (a sequential running sum, as a loop)
    np.cumsum(acc[:, 1:], axis=1, out=acc[:, 1:])
    acc = acc.reshape(n_term, -1)
    # columns j of load l lie in the prefixes of the pairs with jt > j: count them
    cnt = np.bincount(lu * (n_u + 1) + ju, minlength=n_load * (n_u + 1)).reshape(n_load, -1)
    cnt = np.cumsum(cnt[:, top:0:-1], axis=1)[:, ::-1]
    cnt = np.ascontiguousarray(cnt.T)  # (top, n_load): a term's first columns are whole rows
    cnt *= n_load
    cnt += np.arange(n_load)
    x = np.multiply(u2[:, :top].T, sigma, out=np.empty((top, u2.shape[0])))  # (never u2 itself)
    np.minimum(x, 1e150, out=x)  # no 0 * inf where no prefix holds the column
    x2 = x * x
    res, d = np.zeros((top, n_load)), np.empty((top, n_load))
    for n in range(n_term - 1, 0, -1):  # Horner, term n from its first column on
        j = int(start[n])
        if j < top:  # (a cache-sized row block at a time: no (n_term, top, n_load) tensor)
            part = res[j:]
            part += np.take(acc[n], cnt[j:], out=d[j:], mode="clip")
            part *= x2[j:]
    res += np.take(acc[0], cnt, out=d, mode="clip")
    res *= x
    out[:, :top] = res.T
    return out


def _cdf_banded(
    det: Detachment, u2: NDArray, inv: NDArray, rows: bool, negligible: float
) -> NDArray[np.float64]:
    """:func:`gap_cdf` for rows of ``u >= 0`` sorted ascending: each pair on the columns where
    its terms vary (the rest as constants), by a Taylor series where ``u/(sqrt2 h) <= 1``."""
    n_load, n_u = det.weight.shape[0], u2.shape[1]
    ls, ks = pairs(det.weight, negligible)
    with np.errstate(over="ignore", invalid="ignore"):
        a = np.minimum(np.abs(det.u1[ls, ks]) * inv[ks], 1e150)  # the sum is even in u1
    iv, w = inv[ks], det.weight[ls, ks]
    row = ls if rows else np.zeros_like(ls)
    # u >= 0: erf(b + a) varies on [0, j2), erf(b - a) on [j0, j1), the series serves [0, jt)
    with np.errstate(over="ignore", invalid="ignore"):
        top = np.full_like(a, ERF_DIFF_B)
        bounds = np.concatenate((a - _ERF_BAND, a + _ERF_BAND, _ERF_BAND - a, top)) / np.tile(iv, 4)
    j0, j1, j2, jt = rank(u2, np.tile(row, 4), bounds).reshape(4, -1)
    ok = np.isfinite(a) & np.isfinite(w) & np.isfinite(bounds[: 3 * a.size].reshape(3, -1)).all(0)
    j0[~ok], j1[~ok], j2[~ok] = n_u, n_u, n_u  # evaluated everywhere by both erfs
    jt = np.where(ok, np.minimum(jt, j2), 0)
    j1 = np.maximum(j1, j0)
    j0 = np.maximum(j0, j2)  # both vary on [0, j2), erf(b + a) = 1 on [j2, j1)
    ser = np.flatnonzero(jt > 0)
    if ser.size:  # the series in u sigma: its bins' 1/h within 1e9 of sigma (no overflow of
        sigma = float(np.max(iv[ser]))  # (u sigma)^31, no underflow of the coefficients)
        jt[iv < 1e-9 * sigma] = 0
        ser = np.flatnonzero(jt > 0)
    u2 = np.concatenate((u2, np.zeros((u2.shape[0], 1))), axis=1)  # + the dump column

    def scaled(t: NDArray, cols: NDArray) -> NDArray[np.float64]:
        """``u / (sqrt2 h)`` on the columns (as the dense form: no inf - inf below)."""
        with np.errstate(over="ignore", invalid="ignore"):
            b = np.take(u2, row[t] * (n_u + 1) + cols)
            b *= iv[t]
            return np.minimum(b, 1e150, out=b)

    plain = bool(ok.all())  # b + a >= 0 and finite everywhere: erf without sign or NaN passes

    def both(t: NDArray, cols: NDArray) -> NDArray[np.float64]:
        b, at = scaled(t, cols), a[t]
        v = fast_erf(b - at)
        b += at
        v += erf_nonneg(b) if plain else fast_erf(b, out=b)
        v *= w[t]
        return v

    def one(t: NDArray, cols: NDArray) -> NDArray[np.float64]:
        b = scaled(t, cols)
        b -= a[t]
        v = fast_erf(b, out=b)
        v += 1.0
        v *= w[t]
        return v

    shape = (n_load, n_u)
    cdf = np.zeros(shape)
    if ser.size:
        cdf += _series_sum(ls[ser], jt[ser], a[ser], w[ser], iv[ser], u2[:, :n_u], n_load)
    args = (n_u, u2.ravel(), row, iv, a, w)
    cdf += _windowed(ls, jt, j2, shape, both, 1 if plain else 0, args)
    cdf += _windowed(ls, j0, j1, shape, one, 2, args)
    # right of its band each pair adds 2 w (left of it 0): a difference array summed along u
    diff = np.bincount(ls * (n_u + 1) + j1, weights=2.0 * w, minlength=n_load * (n_u + 1))
    cdf += np.cumsum(diff.reshape(n_load, n_u + 1)[:, :n_u], axis=1)
    cdf *= 0.5
    if np.all(cdf[:, 1:] >= cdf[:, :-1]):  # already non-decreasing (and free of NaN)
        return cdf
    return np.maximum.accumulate(cdf, axis=1, out=cdf)


def gap_mean(det: Detachment) -> NDArray[np.float64]:
    """Mean of the gap distribution (mirror term included) [m], (n_load,).

    ``sum w [u1 erf(u1/(sqrt2 h)) + h sqrt(2/pi) exp(-u1^2/(2h^2))]``; exceeds ``u(p0)``
    (:cite:p:`almqvist2011`).
    """
    h = np.maximum(det.h, _TINY)[None, :]
    u1 = det.u1
    with np.errstate(under="ignore", over="ignore"):
        m = u1 * erf(u1 / (_SQRT2 * h)) + h * math.sqrt(2.0 / math.pi) * np.exp(
            -0.5 * (u1 / h) ** 2
        )
    return np.sum(det.weight * m, axis=1)


def _windowed(
    load: NDArray, j0: NDArray, j1: NDArray, shape: tuple[int, int], values: Callable,
    kind: int, args: tuple,
) -> NDArray[np.float64]:  # fmt: skip
    """:func:`~._gap_band.windowed_sum` of ``_cdf_banded``'s terms (``values``; ``kind`` and
    ``args`` (n_u, flat u2, row, iv, a, w) the same terms for the compiled
    :func:`~._band_sums.band_sums`, bit for bit) by the kernel where built."""
    width = j1 - j0
    fn = _compiled_kernel(8.0 * float(np.sum(width)), "band_sums")
    if fn is None:
        return windowed_sum(load, j0, j1, shape, values)
    order, ws, blocks, flat = window_plan(width)
    if flat:
        terms = order[ws > 0]
        bounds = np.unique(np.concatenate(([0], np.minimum(flat_cuts(width[terms]), terms.size))))
        bounds = np.append(bounds, terms.size) if bounds[-1] < terms.size else bounds
        ends = np.concatenate(([0], np.cumsum(width[terms])))
        spec = np.stack((bounds[:-1], bounds[1:], np.zeros(bounds.size - 1, dtype=np.intp)), 1)
        most = int(np.max(ends[bounds[1:]] - ends[bounds[:-1]], initial=0))
    else:
        terms = order
        spec = np.array([(i, i + c, w) for i, c, w in blocks], dtype=np.intp).reshape(-1, 3)
        most = max((c * w for _, c, w in blocks), default=0)
    n_load, n_u = shape
    out = np.zeros(n_load * (n_u + 1))
    fn(out, np.zeros(out.size), np.empty((2, most), dtype=np.intp), spec, terms, j0, j1, load,
       *args, kind)  # fmt: skip
    return out.reshape(n_load, n_u + 1)[:, :n_u]
