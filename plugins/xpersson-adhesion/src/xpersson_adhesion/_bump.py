"""Finite-size floor of ``adhesive``: the nominal area's highest bumps in DMT contact.

Below the mean field's stickiness (small-load ratio ``k0 < 1``) no tensile load holds contact
in the mean field, yet a finite nominal area of side ``L`` keeps its highest bumps in contact
until their own pull-off. A bump at magnification ``zeta`` is the surface smoothed at
``q = zeta q_L``: a sphere of radius ``R(zeta) = 1/kappa(zeta)``,
``kappa(zeta)^2 = 2 pi int_{q_L}^{zeta q_L} q^5 C dq`` (the rms curvature of the resolved
roughness), whose interface carries Persson and Tosatti's effective interfacial energy
``gamma_eff(zeta)`` (the work of adhesion less the full-contact elastic energy of the finer
roughness, physics.md §2.1; :func:`._detachment.gamma_effective`). In DMT contact
(Derjaguin, Muller, Toporov 1975) its pull-off force is ``2 pi gamma_eff(zeta) R(zeta)``; the
floor takes the scale that holds best,

    ``F = max_{zeta in [ZETA_MIN, zeta_1]} 2 pi gamma_eff(zeta) R(zeta)``,

over the scales whose Derjaguin interaction zone fits the bump (``sqrt(2 R h_f) <= pi/(2 zeta
q_L)``, ``h_f`` the rms height of the finer roughness, the rough interface's range). On the
BEM's scenes the unconstrained best scale sits at 0.88-1.2 of that bound (0.88-0.97 in the
fitted cases, Tabor <= 1, where it does not bind); it keeps ``R`` finite where a rolled-off
spectrum's plateau would otherwise send the best scale to ``ZETA_MIN`` with ``R >> L``. The
best scale is at ``zeta_1`` the smooth highest summit (``gamma_eff = dgamma``, ``R = 1/kappa_rms``)
and at ``zeta ~ 2-20`` the long-wavelength bump. :data:`BUMPS` such bumps hold (the one
calibrated constant: the earlier referee's cells held 2.6-2.8x one bump's force on H = 0.8;
the validation campaign's calibration pull-offs, Tabor 0.1-1.0, 1.25x; docs/adhesion_bem.md).
Per nominal area the pull-off stress is ``BUMPS F / L^2``: a finite-size effect that vanishes
as ``L^-2`` for nominal areas larger than the roughness'
longest wavelength. ``adhesive`` adds it to the mean field's attraction where it exceeds the
mean field's own pull-off (:meth:`.adhesive.AdhesiveBoundary.floor_shift`).
"""

from __future__ import annotations

import math

import numpy as np

from ._detachment import gamma_effective

__all__ = ["Bump", "BUMPS", "ZETA_MIN", "N_SCALES"]

#: Smallest magnification of a bump [1]: a bump is at least one octave of roughness
#: (``q_L .. 2 q_L``); below, ``R -> inf`` and the "bump" is the flat nominal area (the mean
#: field's job). Not active in the verified cases (their best scales: zeta 3-32).
ZETA_MIN = 2.0
#: Bumps holding at pull-off [1]: the one calibrated constant of the floor, fitted on the
#: validation campaign's calibration pull-offs (Tabor 0.1-1.0, ``benchmarks/adhesion_fit.py``;
#: 2.7 before, fitted on the earlier referee's H = 0.8 cell). 1 is the single bump.
BUMPS = 1.25
#: Magnifications scanned for the best bump (log-spaced, ``zeta_1`` included) [1].
N_SCALES = 48


class Bump:
    """The highest bump of a nominal area of side ``side`` in DMT contact (SI units).

    Parameters
    ----------
    psd : PowerSpectrum
        Roughness spectrum (Persson convention, m^4).
    E_star : float
        Contact modulus [Pa].
    work : float
        Work of adhesion [J/m^2], >= 0.
    side : float
        Side of the nominal area [m], > 0 (the BEM's periodic cell: ``2 pi / q_L``).
    """

    def __init__(self, psd: object, E_star: float, work: float, side: float) -> None:
        q_L, q_1 = float(psd.q_L), float(psd.q_1)  # type: ignore[attr-defined]
        z1 = q_1 / q_L
        z = np.geomspace(min(ZETA_MIN, z1), z1, N_SCALES)
        z[-1] = z1
        gamma = gamma_effective(psd, E_star, work, z)[0]
        m5 = np.asarray(psd.running_moment(5.0, z * q_L), dtype=float)  # type: ignore[attr-defined]
        radius = 1.0 / np.sqrt(np.maximum(2.0 * math.pi * m5, 1e-300))
        # Derjaguin's approximation needs the interaction zone sqrt(2 R h_f) (h_f the rms
        # height of the finer roughness, the rough interface's range) inside a quarter
        # wavelength of the bump's scale; zeta_1 (h_f = 0) always qualifies
        m1 = np.asarray(psd.running_moment(1.0, z * q_L), dtype=float)  # type: ignore[attr-defined]
        h_f = np.sqrt(np.maximum(2.0 * math.pi * (m1[-1] - m1), 0.0))
        fits = np.sqrt(2.0 * radius * h_f) <= math.pi / (2.0 * z * q_L) * (1.0 + 1e-9)
        force = np.where(fits, 2.0 * math.pi * gamma * radius, 0.0)
        i = int(np.argmax(force))
        self.zeta = float(z[i])
        self.radius = float(radius[i])
        self.gamma = float(gamma[i])
        #: pull-off force of one bump [N]
        self.force = float(force[i])
        self.cell = float(side) ** 2

    @property
    def pull_off(self) -> float:
        """Pull-off stress of the :data:`BUMPS` bumps over the nominal area [Pa]."""
        return BUMPS * self.force / self.cell
