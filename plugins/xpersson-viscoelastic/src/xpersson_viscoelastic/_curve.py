"""The stand-alone friction curve read at output magnifications (``friction_curve(zeta=...)``).

:func:`~xpersson_viscoelastic.kernel.friction_curve` integrates ``mu_visc`` on Gauss-Legendre
panels up to ``zeta_max`` only. A scene's Dataset holds more: the running integral
``mu_visc_cumulative`` at every output magnification. Given those magnifications, the kernel
takes them as panel edges (the panels of :func:`._graded.layout`, graded towards ``q_L`` where
the area drops just above it, narrow panels at the reduced node counts of :mod:`._panels`), so
the running integral is read there exactly, with the closed-form area at every node. This is
the arithmetic of the friction analysis's graded panels (:mod:`._graded`), applied to the whole
output grid.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from xpersson.physics import area_fraction, effective_ratio

from . import _graded
from .kernel import PANELS_PER_DECADE, _area_factor, _checked_nu, first_panel_width

__all__ = ["friction_on_grid", "checked_zeta"]

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
