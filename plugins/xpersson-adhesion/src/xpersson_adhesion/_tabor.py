"""Tabor-type parameter per scale (physics.md §2.3) and the JKR/DMT consistency warning.

``mu_T(q) = [R(q) dgamma^2 / (E*^2 dr^3)]^(1/3)`` with the asperity radius of curvature at the
scale ``q`` estimated from the curvature of a band of half an octave on each side of ``q``
(clipped to the spectrum's support)::

    R(q) = [2 pi int_{q/sqrt2}^{sqrt2 q} q'^5 C(q') dq']^(-1/2).

``mu_T >> 1``: soft solids, short-range attraction -> JKR-type detachment wall (``jkr``);
``mu_T << 1``: hard solids, long-range attraction -> attraction in the gaps (``dmt``).
The band estimate of R is a generic order-of-magnitude choice [M], as is the threshold 1.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "AdhesionLimitWarning",
    "JKR_MIN_TABOR",
    "DMT_MAX_TABOR",
    "tabor_parameter",
    "warn_outside_limit",
]

#: Finest-scale Tabor parameter below which ``jkr`` is outside its limit: the BEM referee
#: (docs/adhesion_bem.md) finds ``jkr`` several-fold low at 0.6-1.6; the Johnson-Greenwood
#: adhesion map puts the JKR regime at Maugis parameters above about 5.
JKR_MIN_TABOR = 5.0
#: Finest-scale Tabor parameter above which ``dmt`` leaves the range verified against the BEM.
DMT_MAX_TABOR = 2.0

_HALF_OCTAVE = math.sqrt(2.0)


class AdhesionLimitWarning(UserWarning):
    """The chosen adhesion limit (jkr or dmt) is outside its range of the finest-scale Tabor
    parameter (:func:`warn_outside_limit`)."""


def tabor_parameter(
    psd: object, E_star: float, work: float, interaction_range: float, zeta: ArrayLike
) -> NDArray[np.float64]:
    """Tabor parameter ``mu_T(zeta)`` [1] at magnifications ``zeta``.

    Parameters
    ----------
    psd : PowerSpectrum
        Roughness spectrum (Persson convention, m^4).
    E_star : float
        Contact modulus [Pa].
    work : float
        Work of adhesion [J/m^2].
    interaction_range : float
        Range of the attraction [m], > 0.
    zeta : array_like
        Magnifications [1].
    """
    z = np.atleast_1d(np.asarray(zeta, dtype=float))
    q = z * float(psd.q_L)
    lo = np.clip(q / _HALF_OCTAVE, psd.q_L, psd.q_1)
    hi = np.clip(q * _HALF_OCTAVE, psd.q_L, psd.q_1)
    m5 = np.asarray(psd.running_moment(5.0, hi), float) - np.asarray(
        psd.running_moment(5.0, lo), float
    )
    curv = np.sqrt(np.maximum(2.0 * math.pi * m5, 0.0))  # 1/R [1/m]
    with np.errstate(divide="ignore"):
        radius = np.where(curv > 0, 1.0 / np.where(curv > 0, curv, 1.0), np.inf)
    mu = np.cbrt(radius * work**2 / (E_star**2 * interaction_range**3))
    return np.where(np.isfinite(mu), mu, np.finfo(float).max)


def warn_outside_limit(mu_1: float, limit: str, stacklevel: int = 3) -> bool:
    """Warn when the finest-scale Tabor parameter ``mu_1`` puts the scene outside ``limit``.

    ``jkr``: ``mu_1 < JKR_MIN_TABOR``; ``dmt``: ``mu_1 > DMT_MAX_TABOR``. The finest scale
    carries the contact spots, so its Tabor parameter decides the regime (physics.md §2.3;
    docs/adhesion_bem.md). Returns True when a warning was issued.
    """
    if limit == "jkr" and mu_1 < JKR_MIN_TABOR:
        text = (
            f"below {JKR_MIN_TABOR:g}: outside the JKR limit (against the BEM referee jkr "
            "under-predicts the adhesive area several-fold at 0.6-1.6); the 'adhesive' model "
            "or the 'dmt' limit describes this scene better"
        )
    elif limit == "dmt" and mu_1 > DMT_MAX_TABOR:
        text = (
            f"above {DMT_MAX_TABOR:g}: beyond the range where dmt was verified against the BEM "
            "referee (0.6-1.6), towards the 'jkr' limit"
        )
    else:
        return False
    warnings.warn(
        f"boundary {limit!r}: the Tabor parameter at the finest scale mu_T(zeta_max) = "
        f"{mu_1:.3g} is {text} (physics.md §2.3, docs/adhesion_bem.md)",
        AdhesionLimitWarning,
        stacklevel=stacklevel,
    )
    return True
