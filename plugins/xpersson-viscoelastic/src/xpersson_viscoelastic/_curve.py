"""The stand-alone vectorised friction curve :func:`friction_curve` (the kernels of
:mod:`.kernel` put together), and the curve read at output magnifications (``zeta=...``).

Without ``zeta`` it integrates ``mu_visc`` on Gauss-Legendre panels up to ``zeta_max`` only
(graded towards ``q_L`` where needed, see :mod:`.kernel`). A scene's Dataset holds more: the
running integral ``mu_visc_cumulative`` at every output magnification. Given those, the kernel
takes them as panel edges (the panels of :func:`._graded.layout`, graded towards ``q_L`` where
the area drops just above it, narrow panels at the reduced node counts of :mod:`._panels`), so
the running integral is read there exactly, with the closed-form area at every node. This is
the arithmetic of the friction analysis's graded panels (:mod:`._graded`), applied to the whole
output grid.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from xpersson.physics import area_fraction, effective_ratio

from . import _graded
from ._gauss import spectral_rule as _rule
from ._modulus import ModulusModel
from .kernel import (
    NODES,
    PANELS_PER_DECADE,
    _area_factor,
    _checked_nu,
    _nodes,
    first_panel_width,
    friction_integral,
    graded_edges,
)

__all__ = ["friction_curve", "friction_on_grid", "checked_zeta"]

Array = NDArray[np.float64]


def checked_zeta(zeta: Any, zeta_max: float | None) -> Array:
    """The output magnifications [1] as a 1-D float array: strictly increasing, >= 1, the last
    equal to ``zeta_max`` where that is given; one clear error otherwise."""
    z = np.atleast_1d(np.asarray(zeta, dtype=float))
    if z.ndim != 1 or z.size < 1 or not np.all(np.isfinite(z)) or z[0] < 1.0:
        raise ValueError(f"zeta: magnifications must be finite and >= 1 (dimensionless), got {z}")
    if np.any(np.diff(z) <= 0):
        raise ValueError("zeta: magnifications must be strictly increasing (dimensionless)")
    if zeta_max is not None and float(zeta_max) != z[-1]:
        raise ValueError(
            f"zeta_max: {zeta_max:g} differs from the last of zeta ({z[-1]:g}); give one of them"
        )
    return z


def _area(tau: Array, p0: Array, closure: str, closure_gamma: float | None) -> Array:
    """``A/A0`` [1] of loads ``p0`` [Pa] (last axis of the result) at ``tau`` [Pa^2] (any
    shape ``S``): shape ``S[:-1] + (n_p0,) + S[-1:]``."""
    t = tau[..., None, :]
    G = t / (p0[:, None] ** 2)
    ratio = effective_ratio(G, closure, closure_gamma) if closure != "persson01" else 1.0
    A, _ = area_fraction(p0[:, None], G * p0[:, None] ** 2 * ratio)
    return np.asarray(A, dtype=float)


def friction_on_grid(
    psd: Any,
    model: Any,
    nu: float,
    p0: Array,
    scale: Array,
    zeta: Array,
    closure: str,
    closure_gamma: float | None,
    correction: str,
    gamma: float,
) -> dict[str, Array]:
    """``mu_visc_cumulative`` (n_T, n_v, n_p0, n_zeta) at the magnifications ``zeta`` [1] of
    speeds x shift factors ``scale = a_T v`` (n_T, n_v) [m/s] and loads ``p0`` [Pa]; with
    ``mu_visc`` and ``area_fraction`` at ``zeta[-1]`` (n_T, n_v, n_p0) [1]."""
    fnu = _checked_nu(nu)
    q_L = float(psd.q_L)
    z = np.unique(np.concatenate([[1.0], zeta]))  # the integrals start at q_L
    d0 = first_panel_width(psd, model, fnu, float(np.min(p0)), scale, float(z[-1]) * q_L)
    t = min(1.0, float(z[-1]) - 1.0)
    n = max(1, int(np.ceil(2.0 * np.log10(t / d0) - 1e-9))) if 0.0 < d0 < t else 0
    lay = _graded.layout(psd, z, z.size - 1, n, PANELS_PER_DECADE)
    w = scale.reshape(-1)[:, None] * lay.qn  # (K, N)
    tau, dL, top = _graded.integrals_and_top(psd, model, nu, lay, w)
    K, n_p = w.shape[0], p0.size
    g = _area_factor(_area(tau, p0, closure, closure_gamma), correction, gamma)  # (K, n_p, N)
    run = _graded.running(
        g.reshape(K * n_p, -1), np.repeat(dL, n_p, axis=0), lay, np.tile(p0, K)
    ).reshape(scale.shape + (n_p, z.size))
    run = run[..., np.searchsorted(z, zeta)]
    A_end = _area(top[:, None], p0, closure, closure_gamma)[..., 0].reshape(scale.shape + (n_p,))
    return {"mu_visc": run[..., -1], "area_fraction": A_end, "mu_visc_cumulative": run}


def friction_curve(
    psd: Any,
    model: ModulusModel,
    nu: float,
    p0: ArrayLike,
    v: ArrayLike,
    aT: ArrayLike = 1.0,
    *,
    zeta_max: float | None = None,
    zeta: ArrayLike | None = None,
    closure: str = "persson01",
    closure_gamma: float | None = None,
    correction: str = "none",
    gamma: float = 0.5,
    nodes: int = NODES,
    panels_per_decade: int = PANELS_PER_DECADE,
) -> dict[str, Array]:
    """Stand-alone vectorised ``mu_visc(v, T, p0)`` with the (closure) erf contact area.

    The pipeline's friction analysis reads the solved area from the Dataset instead; this
    kernel evaluates the area in closed form at every quadrature node (for studies and the
    benchmark: 50 velocities x 3 temperatures x 40 modes in milliseconds).

    Parameters
    ----------
    psd, model, nu
        As in :func:`diffusion_time`.
    p0 : array_like, shape (n_p0,)
        Nominal pressures [Pa].
    v : array_like, shape (n_v,)
        Sliding speeds [m/s].
    aT : array_like, shape (n_T,)
        Shift factors [1] (one per temperature).
    zeta_max : float, optional
        Upper magnification of the integrals (default ``q_1 / q_L``).
    zeta : array_like, optional
        Output magnifications [1] (strictly increasing, >= 1; the last is the upper limit):
        also return ``mu_visc_cumulative`` there, as a scene's Dataset holds it (the panels
        then end at every one of them, :mod:`._curve`).
    closure, closure_gamma
        Correction closure of the contact area (:mod:`xpersson.physics.closures`).
    correction : {"none", "s_factor"}
        ``S = 1`` or ``S = gamma + (1 - gamma) P^2`` in ``mu_visc``.

    Returns
    -------
    dict
        ``mu_visc`` and ``area_fraction`` (at ``zeta_max``), shape ``(n_T, n_v, n_p0)``; with
        ``zeta``, also ``mu_visc_cumulative``, shape ``(n_T, n_v, n_p0, n_zeta)``.
    """
    fnu = _checked_nu(nu)
    p0 = np.atleast_1d(np.asarray(p0, dtype=float))
    scale = np.multiply.outer(
        np.atleast_1d(np.asarray(aT, dtype=float)), np.atleast_1d(np.asarray(v, dtype=float))
    )  # (n_T, n_v)
    if zeta is not None:  # the running integral at output magnifications
        z = checked_zeta(zeta, zeta_max)
        return friction_on_grid(
            psd, model, nu, p0, scale, z, closure, closure_gamma, correction, gamma
        )
    zmax = float(psd.q_1 / psd.q_L) if zeta_max is None else float(zeta_max)
    q_hi = zmax * float(psd.q_L)
    d0 = first_panel_width(psd, model, fnu, float(np.min(p0)), scale, q_hi)
    edges = graded_edges(psd, q_hi, d0, panels_per_decade)
    graded = d0 < min(1.0, zmax - 1.0)
    qn, wq, jac, half = _nodes(edges, nodes, float(psd.q_L) if graded else None)
    _, wgl, Q = _rule(nodes)
    q3C = qn**3 * np.asarray(psd.C(qn), dtype=float)
    excess_sq, loss = model.parts(scale[..., None, None] * qn)  # (n_T, n_v, n_panel, n)
    # tau at every node: exact E_r^2 I3 plus the spectral cumulative of the excess; graded:
    # all of <|E|^2> spectrally (I3(q) loses digits where q - q_L is near round-off of q)
    exact_sq = 0.0 if graded else model.E_r**2
    dens = q3C * jac * (excess_sq + (model.E_r**2 - exact_sq))  # integrand in u
    within = half[:, None] * np.einsum("ij,...pj->...pi", Q, dens)
    ends = np.sum(half[:, None] * wgl * dens, axis=-1)
    before = np.concatenate(
        [np.zeros(scale.shape + (1,)), np.cumsum(ends, axis=-1)[..., :-1]], axis=-1
    )
    excess = before[..., None] + within
    tau = (np.pi / 4.0) * (exact_sq * np.asarray(psd.I3(qn)) + excess) / (fnu * fnu)
    tau = np.maximum(tau, 0.0)
    G = tau[..., None, :, :] / (p0[:, None, None] ** 2)  # (n_T, n_v, n_p0, n_panel, n)
    ratio = effective_ratio(G, closure, closure_gamma) if closure != "persson01" else 1.0
    A, _ = area_fraction(p0[:, None, None], G * p0[:, None, None] ** 2 * ratio)
    g = _area_factor(np.asarray(A), correction, gamma)
    dL = (q3C * wq * loss / fnu)[..., None, :, :]
    mu = friction_integral((g * dL).reshape(g.shape[:-2] + (-1,)), p0)[..., -1]
    total = before[..., -1] + ends[..., -1]
    tau_end = (
        (np.pi / 4.0) * (exact_sq * float(psd.I3(zmax * float(psd.q_L))) + total) / (fnu * fnu)
    )
    G_end = tau_end[..., None] / p0**2
    r_end = effective_ratio(G_end, closure, closure_gamma) if closure != "persson01" else 1.0
    A_end, _ = area_fraction(p0, G_end * p0**2 * r_end)
    return {"mu_visc": mu, "area_fraction": np.asarray(A_end)}
