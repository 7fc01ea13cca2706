"""Cubic Stieltjes weights on many grids at once (split from :mod:`.kernel`).

``W[i, a, b] = int_{x_i}^{x_i+1} l_a(x) l_b'(x) dx`` for the 4-point Lagrange basis of the
stencil ``s_i .. s_i + 3`` (``s_i = clip(i - 1, 0, n - 4)``) of every interval of a grid; the
friction analysis's dense grids of a block of sweep points get theirs in one vectorised call
(:func:`stacked_weights`) instead of one call per point, with the same arithmetic per interval.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

__all__ = ["interval_weights", "stacked_weights"]

Array = NDArray[np.float64]

_GL3 = np.polynomial.legendre.leggauss(3)  # 3-point Gauss-Legendre (once, not per grid)


def interval_weights(xs: Array, lo: NDArray[np.intp], start: NDArray[np.intp]) -> Array:
    """The weights ``(n_interval, 4, 4)`` of the intervals ``[xs[lo], xs[lo + 1]]`` with the
    stencils ``xs[start] .. xs[start + 3]``.

    The integrand is a polynomial of degree 5: 3-point Gauss-Legendre on each interval is
    exact. Vectorised over the intervals.
    """
    h = xs[lo + 1] - xs[lo]
    S = xs[start[:, None] + np.arange(4)] - xs[lo, None]  # stencil, shifted: (n_int, 4)
    tg, wg = _GL3
    d = (0.5 * h[:, None] * (tg + 1.0))[:, :, None] - S[:, None, :]  # t - s_m: (n_int, 3, 4)
    val = np.empty_like(d)
    der = np.zeros_like(d)
    for a in range(4):
        others = [m for m in range(4) if m != a]
        denom = np.prod(S[:, a, None] - S[:, others], axis=-1)[:, None]  # (n_int, 1)
        val[..., a] = np.prod(d[..., others], axis=-1) / denom
        for m in others:
            rest = [k for k in others if k != m]
            der[..., a] += np.prod(d[..., rest], axis=-1) / denom
    return np.einsum("ig,iga,igb->iab", 0.5 * h[:, None] * wg, val, der)


def stacked_weights(grids: Sequence[Array]) -> list[tuple[Array, Array] | None]:
    """``(W, start)`` of each strictly increasing grid (as :func:`.kernel._cubic_weights`
    gives it; ``None`` for a grid of fewer than four points), all in one vectorised call."""
    sizes = [int(np.size(x)) for x in grids]
    use = [k for k, n in enumerate(sizes) if n >= 4]
    out: list[tuple[Array, Array] | None] = [None] * len(grids)
    if not use:
        return out
    xs = np.concatenate([np.asarray(grids[k], dtype=float) for k in use])
    offsets = np.concatenate([[0], np.cumsum([sizes[k] for k in use])])
    lo = np.concatenate([o + np.arange(sizes[k] - 1) for k, o in zip(use, offsets, strict=False)])
    start = np.concatenate(
        [np.clip(np.arange(sizes[k] - 1) - 1, 0, sizes[k] - 4) for k in use]
    )  # within each grid
    W = interval_weights(xs, lo, start + np.repeat(offsets[:-1], [sizes[k] - 1 for k in use]))
    at = 0
    for k in use:
        n = sizes[k] - 1
        out[k] = (W[at : at + n], np.clip(np.arange(n) - 1, 0, sizes[k] - 4))
        at += n
    return out
