"""Full-contact elastic energy of a band of scales (physics.md §5.1) used by gamma_eff.

``U_el(q_a)/A0 = (pi E*/2) int_{q_a}^{q_1} q^2 C(q) dq`` [J/m^2]: the energy needed to make the
solids conform to the roughness finer than ``q_a`` (full contact at those scales).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["band_energy"]


def band_energy(psd: object, E_star: float, q_lower: ArrayLike) -> NDArray[np.float64]:
    """Full-contact elastic energy per nominal area of the scales ``q > q_lower`` [J/m^2].

    Parameters
    ----------
    psd : PowerSpectrum
        Roughness spectrum (Persson convention, m^4).
    E_star : float
        Contact modulus [Pa].
    q_lower : array_like
        Lower end(s) of the band [1/m] (the band ends at ``psd.q_1``).
    """
    q = np.asarray(q_lower, dtype=float)
    total = float(psd.moment(2.0))
    below = np.asarray(psd.running_moment(2.0, q), dtype=float)
    return 0.5 * math.pi * float(E_star) * np.maximum(total - below, 0.0)
