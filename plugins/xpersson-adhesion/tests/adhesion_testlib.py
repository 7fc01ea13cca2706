"""Scenes and helpers of the xpersson-adhesion tests (a uniquely named module)."""

from __future__ import annotations

import copy
import math

import numpy as np
from scipy.optimize import brentq

from xpersson.physics import SelfAffineRollOff, diffusion_time
from xpersson.testing import material, scene, spectrum

# The spectrum of xpersson.testing's tiny scene: H = 0.8, q_L = 1e3, q_r = 1e4, q_1 = 1e7 1/m.
SPECTRUM = spectrum()
PSD = SelfAffineRollOff.from_h_rms(1e-6, 0.8, 1e3, 1e4, 1e7)
ZETA_1 = 1e4

# PDMS-like elastomer on a rough glass-like surface (the plugin's example scene).
PDMS = scene(
    spectrum(q_L="1e4 1/m", q_r="1e5 1/m", q_1="1e9 1/m"),
    material("1 MPa"),
    p0=["-2 kPa", "1 kPa", "10 kPa"],
    boundary={"model": "jkr", "work_of_adhesion": "0.05 J/m**2"},
    output={"zeta_per_decade": 3},
)


def unit_scene(tau_max: float = 2.0) -> tuple[dict, float]:
    """Scene on the tiny spectrum with E* chosen so that tau(zeta_1) = tau_max [Pa^2].

    Returns the scene (nu = 0, so E* = E; no load, boundary or output yet) and E* [Pa].
    """
    e_star = math.sqrt(tau_max / float(diffusion_time(PSD, 1.0, ZETA_1)))
    return scene(material=material(f"{e_star!r} Pa", nu=0.0)), e_star


def tau_of(zeta: np.ndarray, e_star: float) -> np.ndarray:
    """Diffusion time [Pa^2] of the tiny spectrum."""
    return np.asarray(diffusion_time(PSD, e_star, np.asarray(zeta, float)), float)


def zeta_at(tau: float, e_star: float) -> float:
    """Magnification at which the diffusion time reaches ``tau`` [Pa^2]."""
    return brentq(
        lambda z: float(tau_of(np.array([z]), e_star)[0]) - tau, 1.0, ZETA_1, xtol=1e-14, rtol=1e-15
    )


def with_(scene: dict, **sections: dict) -> dict:
    """Deep copy of ``scene`` with whole sections replaced."""
    out = copy.deepcopy(scene)
    out.update(copy.deepcopy(sections))
    return out
