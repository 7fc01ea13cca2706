"""The friction integral ``int P S dL`` where the output grid does not resolve the area.

With no roll-off plateau, or a stiff (fast, cold) rubber, ``G`` grows from 0 to >> 1 within the
first output interval: ``P = A/A0`` falls from 1 to ``~ 1/sqrt(pi G) ~ (zeta - 1)^(-1/2)`` just
above ``zeta = 1``, and most of ``mu_visc`` comes from there. A cubic through the output points
cannot follow that drop (issue 22: +27 % at 1 m/s, 5.7x at 10 m/s on 20 points per decade).

For such loads the integral is evaluated on a dense grid geometric in ``zeta - 1`` (from
where ``G <= 1e-4`` up to the output point of :func:`dense_top`, past ``zeta = 100`` and past the
last large step of ``P``; :data:`PER_DECADE` points per decade, merged with the output grid) in
the variable ``ln(zeta - 1)``, in which the drop is smooth, and continued on the output grid:

* the area comes from the same solve at the dense magnifications (``ctx.solve_at``); without
  it, from the solved ``G`` (not ``P``): ``G / (zeta - 1)`` and ``P / erf(1/(2 sqrt(G)))`` are
  smooth at ``zeta = 1`` and are interpolated in ``ln zeta``, then ``P = ratio erf(1/(2 sqrt G))``
  (exact for the elastic wall with the Persson 2001 closure);
* the loss integral from the coefficient (``coefficient.loss_integral(ctx, zeta)``) where it
  offers it, else ``L / (zeta - 1)`` interpolated in ``ln zeta``.

Loads whose curve is resolved (``1 - P <= 1e-6`` at the first output point and steps of ``P``
below 0.02) keep the output-grid rule.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import CubicSpline
from scipy.special import erf

from .kernel import stieltjes_increments

__all__ = [
    "PER_DECADE",
    "unresolved",
    "dense_top",
    "dense_tops",
    "dense_grid",
    "dense_area",
    "dense_loss",
    "area_at",
    "running_integral",
    "dense_x",
]

Array = NDArray[np.float64]

#: Dense points per decade of ``zeta - 1``.
PER_DECADE = 24
#: ``1 - P`` at the first output point above which the drop is sampled densely.
MAX_FIRST = 1e-6
#: Largest step of ``P`` between output points integrated on the output grid.
MAX_STEP = 0.02
#: The dense grid reaches at least this magnification.
TOP = 100.0


def unresolved(area: Array) -> NDArray[np.bool_]:
    """Loads (rows of ``area`` (n_load, n_zeta)) whose area curve the output grid misses."""
    if area.shape[-1] < 4:
        return np.ones(area.shape[0], dtype=bool)
    step = np.max(np.abs(np.diff(area, axis=-1)), axis=-1)
    return (1.0 - area[:, 1] > MAX_FIRST) | (step > MAX_STEP)


def dense_top(zeta: Array, area: Array) -> int:
    """Index of the last output point sampled densely: past ``zeta = 100`` (where the
    ``(zeta - 1)^(-1/2)`` shape of the area is smooth in ``ln zeta``) and four points past the
    last step of ``P`` above :data:`MAX_STEP` (``area`` (n_sel, n_zeta) of the loads)."""
    n = zeta.size
    k = int(np.searchsorted(zeta, TOP))
    big = np.flatnonzero(np.max(np.abs(np.diff(area, axis=-1)), axis=0) > MAX_STEP)
    if big.size:
        k = max(k, int(big[-1]) + 5)
    return min(k, n - 1)


def dense_tops(zeta: Array, area: Array, need: NDArray[np.bool_]) -> NDArray[np.intp]:
    """:func:`dense_top` of every point of a block at once: ``area`` (K, n_load, n_zeta),
    ``need`` (K, n_load) the loads each point samples densely (:func:`unresolved`)."""
    n = zeta.size
    k = int(np.searchsorted(zeta, TOP))
    big = (np.abs(np.diff(area, axis=-1)) > MAX_STEP) & need[..., None]
    big = big.any(axis=1)  # (K, n_zeta - 1)
    last = big.shape[1] - 1 - np.argmax(big[:, ::-1], axis=1)
    tops = np.where(big.any(axis=1), np.maximum(k, last + 5), k)
    return np.minimum(tops, n - 1)


def dense_grid(zeta: Array, G: Array) -> tuple[Array, NDArray[np.intp]]:
    """Dense magnifications (``zeta[0] = 1`` first) and the indices of ``zeta`` in them.

    ``G`` (n_load, n_zeta) [1] sets the first dense point: ``G(1 + d0) <= 1e-4`` from the mean
    slope over the first output interval (with a margin of 10).
    """
    z1 = float(zeta[1]) - 1.0
    slope = float(np.max(G[:, 1])) / z1
    d0 = min(z1, 1e-5 / slope) if slope > 0 else z1
    top = float(zeta[-1]) - 1.0
    n = max(2, int(np.ceil(PER_DECADE * np.log10(top / d0))) + 1)
    extra = np.geomspace(d0, top, n)
    # drop dense points closer than a quarter spacing to an output point (stencil conditioning)
    gap = np.min(np.abs(np.log(extra)[:, None] - np.log(zeta[1:] - 1.0)[None, :]), axis=1)
    extra = 1.0 + extra[gap > 0.25 * np.log(10.0) / PER_DECADE]
    zd = np.unique(np.concatenate([zeta, extra[extra < zeta[-1]]]))
    return zd, np.searchsorted(zd, zeta)


def _smooth(zeta: Array, y: Array, zd: Array) -> Array:
    """``y(zd)`` from ``y / (zeta - 1)`` (a smooth function at ``zeta = 1``, the value there
    extrapolated) by a cubic spline in ``ln zeta``; ``y(1) = 0``."""
    x = np.log(zeta[1:])
    s = CubicSpline(x, y[..., 1:] / (zeta[1:] - 1.0), axis=-1)
    out = np.zeros(y.shape[:-1] + zd.shape)
    out[..., 1:] = s(np.log(zd[1:])) * (zd[1:] - 1.0)
    return out


def _elastic_area(G: Array) -> Array:
    with np.errstate(divide="ignore"):
        return np.where(G > 0, erf(0.5 / np.sqrt(np.maximum(G, 1e-300))), 1.0)


def dense_area(ctx: Any, zeta: Array, area: Array, G: Array, zd: Array, loads: Array) -> Array:
    """``P`` (n_sel, n_dense) of the loads ``loads`` at ``zd`` (see the module docstring)."""
    solve_at = getattr(ctx, "solve_at", None)
    if solve_at is not None:
        return np.asarray(solve_at(zd, loads)["area_fraction"], dtype=float).reshape(loads.size, -1)
    Gd = np.maximum(_smooth(zeta, G[loads], zd), 0.0)
    ratio = area[loads] / _elastic_area(G[loads])
    x = np.log(zeta)
    r = CubicSpline(x, ratio, axis=-1)(np.log(zd))
    return np.clip(r * _elastic_area(Gd), 0.0, 1.0)


def area_at(ctx: Any, zeta: Array, area: Array, G: Array, zc: float) -> Array:
    """``P`` (n_load,) at one magnification ``zc`` [1] between output points: the same solve
    there (``ctx.solve_at``), else ``ratio erf(1/(2 sqrt(G)))`` with ``G / (zeta - 1)`` and the
    ratio interpolated in ``ln zeta`` (see the module docstring)."""
    solve_at = getattr(ctx, "solve_at", None)
    if solve_at is not None:
        return np.asarray(solve_at(np.array([1.0, zc]))["area_fraction"], dtype=float)[:, -1]
    zd = np.array([1.0, zc])
    Gc = np.maximum(_smooth(zeta, G, zd)[:, -1], 0.0)
    ratio = CubicSpline(np.log(zeta), area / _elastic_area(G), axis=-1)(np.log(zc))
    return np.clip(ratio * _elastic_area(Gc), 0.0, 1.0)


def dense_loss(ctx: Any, zeta: Array, L: Array, zd: Array) -> Array:
    """``L`` [Pa] at ``zd``: the coefficient's own integral where offered, else interpolated."""
    at = getattr(ctx.coefficient, "loss_integral", None) if ctx is not None else None
    if callable(at):
        return np.asarray(at(ctx, zd), dtype=float)
    return _smooth(zeta, np.asarray(L, dtype=float), zd)


def running_integral(
    g: Array, L: Array, zd: Array, weights: tuple[Array, Array] | None = None
) -> Array:
    """Running ``int_1^zeta g dL`` on the dense grid ``zd`` (``zd[0] = 1``), last axis.

    The first interval ``[1, zd[1]]`` (where ``g ~ 1`` and ``L`` is linear) by the trapezoid,
    the rest by :func:`~xpersson_viscoelastic.kernel.stieltjes_increments` in ``ln(zeta - 1)``
    (``weights``: its cubic weights on that grid, computed already for a block of grids).
    """
    first = 0.5 * (g[..., :1] + g[..., 1:2]) * (L[..., 1:2] - L[..., :1])
    rest = stieltjes_increments(g[..., 1:], L[..., 1:], dense_x(zd), weights)
    inc = np.concatenate([first, rest], axis=-1)
    return np.concatenate([np.zeros(g.shape[:-1] + (1,)), np.cumsum(inc, axis=-1)], axis=-1)


def dense_x(zd: Array) -> Array:
    """The grid ``ln(zeta - 1)`` of :func:`running_integral`'s cubic rule on ``zd``."""
    return np.log(zd[1:] - 1.0)
