"""Fast numerics shared by the interface physics (private): exp without numpy's slow path for
vanishing results, cache-sized blocks of loads, and many cubic splines on shared knots."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from .. import _scratch
from ._compiled import kernel

if TYPE_CHECKING:
    from scipy.interpolate import PPoly

#: exp(x) is normal (not subnormal) for x >= _EXP_LO, and exactly 0 for x <= _EXP_ZERO; below
#: _EXP_LO numpy's exp takes a slow path (50x for subnormal results, 8x for underflow to zero),
#: and 1 - A near full contact spans hundreds of decades, so most values of a dense curve or of
#: the gap tensor can lie there.
_EXP_LO = -708.0
_EXP_ZERO = -746.0


def _exp(y: NDArray[np.float64]) -> NDArray[np.float64]:
    """``np.exp(y)`` (bit-identical, a new array) without numpy's slow path where it is 0.

    Where ``y <= -746`` the result is exactly 0 and is not computed; only the thin band of
    subnormal results (``-746 < y < -708``) goes through numpy's slow path.
    """
    y = np.asarray(y, dtype=float)
    if y.size == 0 or not y.min() < _EXP_LO:  # the common case: one pass, no masks
        return np.exp(y)
    out = np.zeros(y.shape)
    np.exp(y, out=out, where=y > _EXP_ZERO)
    return out


def _exp_inplace(y: NDArray[np.float64]) -> NDArray[np.float64]:
    """:func:`_exp` of a float array, written over ``y`` (bit-identical to ``np.exp(y)``)."""
    if y.size == 0 or not y.min() < _EXP_LO:
        return np.exp(y, out=y)
    keep = y > _EXP_ZERO
    np.exp(y, out=y, where=keep)
    y[~keep] = 0.0
    return y


#: Elements per block of loads in the large per-load tensors (about 0.5 MB of float64: the
#: temporaries of one block stay in the cache; whole-batch temporaries are memory-bound).
_BLOCK = 1 << 16


#: Elements of a small buffer (64 kB): below malloc's threshold for fresh memory (mmap), so
#: reused from the heap without page faults.
_SMALL = 1 << 13


def _block(per_load: int) -> int:
    """Loads per block for a tensor of ``per_load`` elements per load."""
    return max(1, _BLOCK // max(int(per_load), 1))


def _row_spline(x: NDArray[np.float64], y: NDArray[np.float64]) -> PPoly:
    """``CubicSpline(x, y, axis=1)`` (not-a-knot) of many rows on shared knots, built fast.

    The same banded system and Hermite coefficients as scipy's ``CubicSpline``, assembled in the
    layout its ``PPoly`` keeps (``c`` of shape ``(4, n - 1, n_row)``) without its axis moves and
    stacking copies (3-6x faster for 100 rows of 600 knots). Fewer than 4 knots: scipy's own.
    """
    from scipy.interpolate import CubicSpline, PPoly  # lazily: ~0.2 s to import

    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    n = x.size
    if n < 4 or y.ndim != 2:
        return CubicSpline(x, y, axis=1)
    fn = kernel(y.size * 8, "spline_coefficients")
    if fn is not None:
        yt, dx_, slope, sl = _compiled_slopes(x, y)
        c = _scratch.empty((4, n - 1, y.shape[0]))  # (on kept pages: the solve's splines)
        fn(yt, dx_, slope, sl, c)
        return PPoly.construct_fast(c, x, extrapolate=True, axis=1)
    yt, dx, slope, sl = _row_slopes(x, y)
    sl = np.ascontiguousarray(sl)  # LAPACK's (n_row, n) memory: one transposed copy, then rows
    c = np.empty((4, n - 1, yt.shape[1]))
    t = np.add(sl[:-1], sl[1:], out=c[3])  # c[3] as scratch
    t -= 2.0 * slope
    t /= dx
    np.divide(t, dx, out=c[0])
    np.subtract(slope, sl[:-1], out=c[1])
    c[1] /= dx
    c[1] -= t
    c[2] = sl[:-1]
    c[3] = yt[:-1]
    return PPoly.construct_fast(c, x, extrapolate=True, axis=1)


def _row_slopes(x: NDArray[np.float64], y: NDArray[np.float64]) -> tuple[NDArray[np.float64], ...]:
    """``(y.T, dx, slope, sl)`` of :func:`_row_spline` (``n >= 4`` knots): the data by knot
    (n, n_row), the knot steps (n - 1, 1), the secants (n - 1, n_row) and the spline's slopes
    at the knots (n, n_row), from which every interval's coefficients follow."""
    from scipy.linalg import solve_banded

    n = x.size
    yt = np.ascontiguousarray(y.T)  # (n, n_row)
    dx = np.diff(x)[:, None]
    slope = np.diff(yt, axis=0)
    slope /= dx
    ab = np.zeros((3, n))
    ab[1, 1:-1] = 2.0 * (dx[:-1, 0] + dx[1:, 0])
    ab[0, 2:] = dx[:-1, 0]
    ab[2, :-2] = dx[1:, 0]
    b = np.empty((yt.shape[1], n)).T  # Fortran order: LAPACK solves it in place
    mid = np.multiply(dx[1:], slope[:-1], out=b[1:-1])
    mid += dx[:-1] * slope[1:]
    mid *= 3.0
    d0, d1 = x[2] - x[0], x[-1] - x[-3]
    ab[1, 0], ab[0, 1] = dx[1, 0], d0
    b[0] = ((dx[0] + 2.0 * d0) * dx[1] * slope[0] + dx[0] ** 2 * slope[1]) / d0
    ab[1, -1], ab[2, -2] = dx[-2, 0], d1
    b[-1] = (dx[-1] ** 2 * slope[-2] + (2.0 * d1 + dx[-1]) * dx[-2] * slope[-1]) / d1
    sl = solve_banded((1, 1), ab, b, overwrite_ab=True, overwrite_b=True, check_finite=False)
    return yt, dx, slope, sl


def _compiled_slopes(
    x: NDArray[np.float64], y: NDArray[np.float64]
) -> tuple[NDArray[np.float64], ...]:
    """``(y.T, dx, slope, sl)`` of :func:`_row_slopes` by the compiled kernels of
    :mod:`._compiled` (bit for bit; ``dx`` 1-D): the same system, solved by dgtsv's own
    elimination."""
    n = x.size
    dx = np.diff(x)
    dl, d, du = np.empty(n - 1), np.empty(n), np.empty(n - 1)  # sub-, main, super-diagonal
    d[1:-1] = 2.0 * (dx[:-1] + dx[1:])
    dl[:-1], du[1:] = dx[1:], dx[:-1]
    d0, d1 = x[2] - x[0], x[-1] - x[-3]
    d[0], du[0] = dx[1], d0
    d[-1], dl[-1] = dx[-2], d1
    slope = np.empty((n - 1, y.shape[0]))
    b = np.empty((n, y.shape[0]))  # the right-hand sides along the rows
    yt = np.ascontiguousarray(y.T)  # (n, n_row)
    kernel(0, "spline_rhs")(yt, dx, float(d0), float(d1), slope, b)  # type: ignore[misc]
    if kernel(0, "spline_slopes")(dl, d, du, b):  # type: ignore[misc]
        from numpy.linalg import LinAlgError

        raise LinAlgError("singular matrix")
    return yt, dx, slope, b


def _ppoly_at(
    spl: PPoly,
    xs: NDArray[np.float64],
    out: NDArray[np.float64] | None = None,
    out_t: NDArray[np.float64] | None = None,
) -> NDArray[np.float64]:
    """``max(spl(xs), 0)`` of a spline of :func:`_row_spline` (rows on axis 1), bit for bit,
    at 1-D ``xs`` inside its breakpoints: (n_row, xs.size), written into ``out`` if given.

    The same arithmetic as scipy's ``PPoly`` evaluation (``c3 + c2 s + c1 s^2 + c0 s^3`` with
    the powers of ``s = x - x_i`` by repeated products), in blocks of points laid out as the
    coefficients (rows innermost) with two small buffers, each block clipped at 0 into its
    columns of ``out``: no per-point search, axis moves or large temporaries. ``out_t``
    (xs.size, n_row): the values in the transposed layout instead (computed in place there,
    nothing else written; returned).
    """
    b, c = spl.x, spl.c
    i = np.clip(np.searchsorted(b, xs, side="right") - 1, 0, b.size - 2)
    s = xs - b[i]
    fn = kernel(c.shape[2] * xs.size, "spline_values")
    if fn is not None and c.flags.c_contiguous:
        res = out_t if out_t is not None else out
        if res is None:
            res = np.empty((c.shape[2], xs.size))
        fn(c, i, s, res, out_t is not None)
        return res
    if out_t is None:
        res = np.empty((c.shape[2], xs.size)) if out is None else out
    step = max(1, _SMALL // c.shape[2])
    buf = np.empty((2, min(step, xs.size), c.shape[2]))
    for lo in range(0, xs.size, step):  # blocks of points: the temporaries stay in cache
        k, sk = i[lo : lo + step], s[lo : lo + step, None]
        r, t = buf[0, : k.size], buf[1, : k.size]
        if out_t is not None:
            r = out_t[lo : lo + k.size]
        np.take(c[2], k, axis=0, out=r)
        r *= sk
        r += np.take(c[3], k, axis=0, out=t)
        z = sk * sk
        np.take(c[1], k, axis=0, out=t)
        t *= z
        r += t
        z *= sk
        np.take(c[0], k, axis=0, out=t)
        t *= z
        r += t
        np.maximum(r, 0.0, out=r)
        if out_t is None:
            res[:, lo : lo + k.size] = r.T
    return res if out_t is None else out_t
