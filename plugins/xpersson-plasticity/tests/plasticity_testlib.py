"""Test helpers of xpersson-plasticity: a scene context and a diffusion clock without the core
pipeline (a uniquely named module, importable from any test folder layout)."""

from __future__ import annotations

import numpy as np

from xpersson.plugins import DiffusionClock, SceneContext

SIGMA_Y = 1.0e9  # Pa
A = 2.0  # f(zeta) = F0 zeta**A  [Pa^2]


def make_clock(tau_max: float, zeta_max: float = 1e3) -> DiffusionClock:
    """Clock with f = F0 zeta^2 and tau(zeta_max) = tau_max [Pa^2]."""
    f0 = tau_max * (A + 1) / (zeta_max ** (A + 1) - 1)

    def tau_fn(z: np.ndarray) -> np.ndarray:
        return f0 * (np.asarray(z, dtype=float) ** (A + 1) - 1.0) / (A + 1)

    def f(z: np.ndarray) -> np.ndarray:
        return f0 * np.asarray(z, dtype=float) ** A

    return DiffusionClock(tau_fn, f, zeta_max)


def make_ctx(p0, zeta_max: float = 1e3, n_zeta: int = 31) -> SceneContext:
    """Scene context with loads ``p0`` [Pa] and log-spaced output magnifications."""
    zeta = np.geomspace(1.0, zeta_max, n_zeta)
    return SceneContext(
        psd=None,
        E=210e9,
        nu=0.3,
        E_star=210e9 / (1 - 0.09),
        p0=np.atleast_1d(np.asarray(p0, dtype=float)),
        zeta=zeta,
    )
