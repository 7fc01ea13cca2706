"""Elastic energy of roughness pressed fully flat: ``(pi E*/2) int q^2 C dq``
(:cite:p:`persson2007,yang2008`)."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["full_contact_energy"]


def full_contact_energy(
    psd: object, E_star: float, q_lo: ArrayLike | None = None, q_hi: float | None = None
) -> NDArray[np.float64] | float:
    """Elastic energy per nominal area of the roughness in ``[q_lo, q_hi]`` at full contact.

    ``U/A0 = (pi E*/2) int_{q_lo}^{q_hi} q^2 C(q) dq`` [J/m^2] (:cite:p:`persson2007,yang2008` with
    ``A = S = 1``): the exact linear-elastic energy of a half-space forced into the shape of
    those scales.

    Parameters
    ----------
    psd : PowerSpectrum
        Roughness spectrum (Persson convention, m^4).
    E_star : float
        Contact modulus [Pa].
    q_lo : array_like, optional
        Lower limit(s) [1/m] (default ``q_L``); vectorised.
    q_hi : float, optional
        Upper limit [1/m] (default ``q_1``).

    Returns
    -------
    float or ndarray
        Energy [J/m^2], shape of ``q_lo``.
    """
    q_L, q_1 = float(psd.q_L), float(psd.q_1)  # type: ignore[attr-defined]
    lo = np.asarray(q_L if q_lo is None else q_lo, dtype=float)
    hi = q_1 if q_hi is None else float(q_hi)
    m_hi = float(psd.running_moment(2.0, hi))  # type: ignore[attr-defined]
    m_lo = np.asarray(psd.running_moment(2.0, np.minimum(lo, hi)), dtype=float)  # type: ignore[attr-defined]
    # the integrand is >= 0: a difference of running moments below 0 is rounding (e.g.
    # -1e-16 where q_lo rounds just under q_1), not energy
    out = 0.5 * math.pi * E_star * np.maximum(m_hi - m_lo, 0.0)
    return float(out) if out.ndim == 0 else out
