"""Transport across a solved rough contact: numpy-only formulas (SI units throughout).

* Barber's analogy (Proc. R. Soc. Lond. A 459 (2003) 53): for an elastic contact the
  constriction conductance ``g`` and the incremental normal stiffness ``K`` of the same contact
  solve the same mixed boundary-value problem, so ``g = c K`` with

  - electrical: ``c_e = 2 / ((rho_1 + rho_2) E*)``  [S m-2 per Pa m-1 = S Pa-1 m-1],
  - thermal:    ``c_t = 2 kappa_s / E*`` with ``1/kappa_s = 1/kappa_1 + 1/kappa_2``.

  Check with one circular (Hertz/Holm) contact of radius ``a`` between two half-spaces: its
  stiffness is ``2 a E*`` (flat punch) and its conductance ``4 a / (rho_1 + rho_2)`` (Holm:
  ``R = rho_1/(4a) + rho_2/(4a)``), whose ratio is ``c_e``.
* Holm's spots: the contact seen at magnification ``zeta`` as non-interacting circular spots of
  radius ``r = c_r / q`` covering the area fraction ``A(zeta)``: per nominal area
  ``K_H = 2 E* A / (pi r)`` and ``g_H = c K_H``.
* Gas in the gaps (temperature-jump form): a gap ``u`` conducts ``kappa_g / (u + Lambda)``,
  ``Lambda = [(2 - a_1)/a_1 + (2 - a_2)/a_2] (2 gamma / (gamma + 1)) lambda / Pr``; averaged
  over the gap distribution by exact product integration of the piecewise-linear density.
* Film in series: a film of resistivity ``rho_f`` and thickness ``d`` on the real contact area
  ``A_c``: ``g_f = A_c / (rho_f d)`` (thermal: ``A_c kappa_f / d``); ``1/g = 1/g_c + 1/g_f``.
* Full contact (``contact_stiffness`` NaN, ``contact_stiffness_status`` 1): the interface is
  rigid at the solve's resolution, so there is no constriction: its resistance is 0 and a
  conductance per area is unbounded (NaN, never ``inf``) unless a finite part (a film) is in
  series with it (:func:`with_full_contact`, :func:`resistance`).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "SIGMA_SB",
    "series_conductivity",
    "electrical_factor",
    "thermal_factor",
    "holm_stiffness",
    "closest_to_one",
    "jump_length",
    "gas_gap_conductance",
    "radiation_conductance",
    "film_conductance",
    "in_series",
    "with_full_contact",
    "resistance",
    "RIGID_FULL_CONTACT",
]

#: ``contact_stiffness_status`` of a load at full contact (its flag ``rigid_full_contact``).
RIGID_FULL_CONTACT = 1

#: Stefan-Boltzmann constant [W m-2 K-4] (CODATA 2018, exact in the SI).
SIGMA_SB = 5.670374419e-8


def series_conductivity(k1: ArrayLike, k2: ArrayLike) -> NDArray[np.float64]:
    """``kappa_s = (1/kappa_1 + 1/kappa_2)^-1`` [W m-1 K-1] (both positive)."""
    k1, k2 = np.asarray(k1, dtype=float), np.asarray(k2, dtype=float)
    return k1 * k2 / (k1 + k2)


def electrical_factor(rho1: float, rho2: float, E_star: float) -> float:
    """Barber's constant ``g/K = 2 / ((rho_1 + rho_2) E*)`` [S m-2 / (Pa m-1)].

    Parameters
    ----------
    rho1, rho2 : float
        Electrical resistivities of the two bodies [ohm m].
    E_star : float
        Contact modulus ``1/E* = (1-nu_1^2)/E_1 + (1-nu_2^2)/E_2`` [Pa].
    """
    return 2.0 / ((rho1 + rho2) * E_star)


def thermal_factor(k1: float, k2: float, E_star: float) -> float:
    """Barber's constant ``g/K = 2 kappa_s / E*`` [W m-2 K-1 / (Pa m-1)].

    Parameters
    ----------
    k1, k2 : float
        Thermal conductivities of the two bodies [W m-1 K-1].
    E_star : float
        Contact modulus [Pa].
    """
    return 2.0 * float(series_conductivity(k1, k2)) / E_star


def holm_stiffness(
    area: ArrayLike, q: ArrayLike, E_star: float, c_r: float = math.pi / 2
) -> NDArray[np.float64]:
    """Stiffness per nominal area of non-interacting circular spots (Holm's picture) [Pa m-1].

    Parameters
    ----------
    area : array_like
        Contact area fraction ``A(zeta)`` [1] (any shape broadcasting with ``q``).
    q : array_like
        Wavevector ``zeta q_L`` of the magnification [m-1].
    E_star : float
        Contact modulus [Pa].
    c_r : float
        Spot radius ``r = c_r / q`` [1]; default ``pi/2`` (diameter half a wavelength).

    Returns
    -------
    ndarray
        ``K_H = 2 E* A / (pi r)``: each spot of radius ``r`` adds the flat-punch ``2 r E*``,
        ``A / (pi r^2)`` spots per unit nominal area.
    """
    r = c_r / np.asarray(q, dtype=float)
    return 2.0 * E_star * np.asarray(area, dtype=float) / (math.pi * r)


def closest_to_one(
    x: NDArray[np.float64], y: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Per row of ``y``: where it equals 1, else where it comes closest to 1 (in ``ln y``).

    Parameters
    ----------
    x : ndarray, shape (n,)
        Increasing positive abscissa (magnifications).
    y : ndarray, shape (m, n)
        Positive ratios.

    Returns
    -------
    x_star, y_star : ndarray, shape (m,)
        The first crossing of 1 (log-log interpolation between the bracketing points, ``y_star
        = 1``) or, without a crossing, the grid point of smallest ``|ln y|`` and its ``y``.
    """
    x = np.asarray(x, dtype=float)
    y = np.atleast_2d(np.asarray(y, dtype=float))
    ly, lx = np.log(y), np.log(x)
    k = np.argmin(np.abs(ly), axis=1)
    xs, ys = x[k], y[np.arange(y.shape[0]), k]
    cross = np.signbit(ly[:, :-1]) != np.signbit(ly[:, 1:])
    has = cross.any(axis=1)
    j = np.argmax(cross, axis=1)[has]
    l0, l1 = ly[has, j], ly[has, j + 1]
    t = np.where(l1 != l0, -l0 / np.where(l1 != l0, l1 - l0, 1.0), 0.0)
    xs[has] = np.exp(lx[j] + t * (lx[j + 1] - lx[j]))
    ys[has] = 1.0
    return xs, ys


def jump_length(
    mean_free_path: float,
    accommodation_1: float = 1.0,
    accommodation_2: float = 1.0,
    heat_capacity_ratio: float = 1.4,
    prandtl: float = 0.71,
) -> float:
    """Sum of the two walls' temperature-jump distances ``Lambda`` [m].

    ``Lambda = [(2 - a_1)/a_1 + (2 - a_2)/a_2] (2 gamma/(gamma + 1)) lambda / Pr``: a gap of
    width ``u`` conducts as a continuum layer of width ``u + Lambda``. ``lambda = 0`` (continuum
    gas) gives 0.

    Parameters
    ----------
    mean_free_path : float
        Gas mean free path ``lambda`` at the interface's pressure and temperature [m].
    accommodation_1, accommodation_2 : float
        Thermal accommodation coefficients of the two walls, in (0, 1] [1].
    heat_capacity_ratio : float
        ``gamma = c_p / c_v`` of the gas [1].
    prandtl : float
        Prandtl number of the gas [1].
    """
    walls = (2.0 - accommodation_1) / accommodation_1 + (2.0 - accommodation_2) / accommodation_2
    g = heat_capacity_ratio
    return walls * (2.0 * g / (g + 1.0)) * mean_free_path / prandtl


def gas_gap_conductance(
    u: ArrayLike, pdf: ArrayLike, kappa_gas: float, jump: float
) -> NDArray[np.float64]:
    """Gas conductance per nominal area ``int pdf(u) kappa_g / (u + Lambda) du`` [W m-2 K-1].

    The density is taken piecewise linear between the grid points and the integral of each
    piece against ``1/(u + Lambda)`` is done exactly, so the result is right for any
    ``Lambda >= 0`` however small against the grid spacing (with ``Lambda = 0`` it is finite only
    if ``pdf(u_0 = 0) = 0``; else ``inf``, the logarithmic divergence of the continuum form).

    Parameters
    ----------
    u : array_like, shape (n,)
        Increasing separations ``>= 0`` [m].
    pdf : array_like, shape (..., n)
        Gap density (continuous part) on ``u`` [m-1].
    kappa_gas : float
        Gas thermal conductivity [W m-1 K-1] (0: vacuum, result 0).
    jump : float
        Temperature-jump length ``Lambda`` [m] (:func:`jump_length`).
    """
    u = np.asarray(u, dtype=float)
    f = np.asarray(pdf, dtype=float)
    if kappa_gas == 0.0:
        return np.zeros(f.shape[:-1])
    b = u[:-1] + jump  # distance of each piece's left end from the pole at -Lambda
    du = np.diff(u)
    f0, f1 = f[..., :-1], f[..., 1:]
    slope = (f1 - f0) / du
    with np.errstate(divide="ignore", invalid="ignore"):
        # int_0^du (f0 + s t)/(b + t) dt = s du + (f0 - s b) ln(1 + du/b)
        log_term = np.where(b > 0, np.log1p(du / np.where(b > 0, b, 1.0)), np.inf)
        coef = f0 - slope * b
        piece = slope * du + np.where(coef == 0.0, 0.0, coef * log_term)
    return kappa_gas * piece.sum(axis=-1)


def radiation_conductance(temperature: float, emissivity_1: float, emissivity_2: float) -> float:
    """Far-field radiative conductance of two gray parallel surfaces [W m-2 K-1].

    ``4 sigma_SB T^3 / (1/eps_1 + 1/eps_2 - 1)`` (0 if either emissivity is 0); linearised
    about the interface temperature ``T`` [K]. The near-field (evanescent-wave) enhancement at
    gaps below the thermal wavelength is not included.
    """
    if emissivity_1 <= 0.0 or emissivity_2 <= 0.0:
        return 0.0
    eps = 1.0 / (1.0 / emissivity_1 + 1.0 / emissivity_2 - 1.0)
    return 4.0 * SIGMA_SB * temperature**3 * eps


def film_conductance(
    contact_fraction: ArrayLike, film_resistivity: float, thickness: float
) -> NDArray[np.float64]:
    """Conductance per nominal area of a film on the real contact area [S m-2 or W m-2 K-1].

    ``g_f = A_c / (rho_f d)`` (thermal: pass ``1/kappa_f`` as ``film_resistivity``);
    ``inf`` for no film (``thickness = 0``).
    """
    a = np.asarray(contact_fraction, dtype=float)
    r = film_resistivity * thickness
    if r == 0.0:
        return np.full(a.shape, np.inf)
    return a / r


def in_series(g1: ArrayLike, g2: ArrayLike) -> NDArray[np.float64]:
    """``(1/g_1 + 1/g_2)^-1`` with ``inf`` meaning no resistance (0 if either is 0)."""
    g1, g2 = np.asarray(g1, dtype=float), np.asarray(g2, dtype=float)
    with np.errstate(divide="ignore"):
        return 1.0 / (1.0 / g1 + 1.0 / g2)


def with_full_contact(g: ArrayLike, g_series: ArrayLike, full: ArrayLike) -> NDArray[np.float64]:
    """A conductance per area ``g`` with the constriction in series, at full contact.

    Where ``full`` the constriction has no resistance: the value is the part in series
    ``g_series`` (a film) if finite, else NaN (unbounded); elsewhere ``g`` unchanged.
    """
    g_s = np.asarray(g_series, dtype=float)
    at_full = np.where(np.isfinite(g_s), g_s, np.nan)
    return np.where(full, at_full, np.asarray(g, dtype=float))


def resistance(g: ArrayLike, area: float, full: ArrayLike) -> NDArray[np.float64]:
    """``1 / (g A0)`` [ohm or K/W] of the nominal area ``A0`` [m^2]; 0 where ``full`` and ``g``
    is unbounded (NaN: full contact without a finite part in series)."""
    g = np.asarray(g, dtype=float)
    with np.errstate(invalid="ignore"):
        return np.where(np.asarray(full) & np.isnan(g), 0.0, 1.0 / (g * area))
