"""Persson (2001) elastic contact theory: closed forms (pure numpy, SI units).

Implements :cite:p:`persson2001`. The pressure distribution obeys the diffusion equation
``dP/dzeta = f(zeta) d^2P/dp^2`` with ``P(p, 1) = delta(p - p0)`` and the absorbing boundary
``P(0, zeta) = 0``. In the diffusion "time"

.. math:: \\tau(\\zeta) = \\int_1^\\zeta f\\, d\\zeta' = \\frac{\\pi}{4} E^{*2} I_3(\\zeta q_L)
          \\quad [\\mathrm{Pa^2}]

the solution is the mirrored Gaussian of variance ``V = 2 tau`` and the contact area is
``A/A0 = erf(p0 / (2 sqrt(tau)))``.

Conventions: pressures in Pa (compressive positive), ``E_star = E/(1 - nu^2)`` in Pa, PSD in
Persson's convention (see :mod:`xpersson.physics.psd`), ``zeta = q/q_L`` with
``q_L = psd.q_L``.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.special import erfc

from .psd import PowerSpectrum

__all__ = [
    "KAPPA",
    "kappa",
    "e_star",
    "coefficient_f",
    "diffusion_time",
    "G_of_zeta",
    "area_fraction",
    "pressure_pdf",
    "load_integral",
    "second_moment",
    "full_contact_std",
    "small_load_area",
    "rayleigh_pdf",
]

#: Small-load prefactor ``A/A0 ~ kappa p0 / (E* h'_rms)``, ``kappa = sqrt(8/pi)``.
KAPPA: float = math.sqrt(8.0 / math.pi)
kappa: float = KAPPA

FloatOrArray = float | NDArray[np.float64]


def _out(x: NDArray[np.float64]) -> FloatOrArray:
    x = np.asarray(x, dtype=float)
    return float(x) if x.ndim == 0 else x


def e_star(E: ArrayLike, nu: ArrayLike) -> FloatOrArray:
    """Plane-strain (contact) modulus ``E* = E / (1 - nu^2)`` [Pa].

    Parameters
    ----------
    E : array_like
        Young's modulus [Pa], > 0.
    nu : array_like
        Poisson ratio, ``-1 < nu <= 1/2``.

    Returns
    -------
    float or ndarray
        ``E*`` [Pa] (rigid rough substrate against an elastic block).
    """
    E_arr = np.asarray(E, dtype=float)
    nu_arr = np.asarray(nu, dtype=float)
    if np.any(~(E_arr > 0)):
        raise ValueError("e_star: E must be > 0")
    if np.any(~((nu_arr > -1.0) & (nu_arr <= 0.5))):
        raise ValueError("e_star: nu must satisfy -1 < nu <= 0.5")
    return _out(E_arr / (1.0 - nu_arr**2))


def coefficient_f(psd: PowerSpectrum, E_star: float, zeta: ArrayLike) -> FloatOrArray:
    """Diffusion coefficient ``f(zeta) = (pi/4) E*^2 q_L q^3 C(q)``, ``q = zeta q_L`` [Pa^2].

    Parameters
    ----------
    psd : PowerSpectrum
        Roughness PSD (Persson convention); ``q_L = psd.q_L``.
    E_star : float
        Contact modulus [Pa].
    zeta : array_like
        Magnification(s) ``zeta = q / q_L`` (dimensionless).

    Returns
    -------
    float or ndarray
        ``f(zeta)`` [Pa^2] (per unit zeta), same shape as ``zeta``.
    """
    z = np.asarray(zeta, dtype=float)
    q = z * psd.q_L
    return _out(0.25 * np.pi * E_star**2 * psd.q_L * q**3 * np.asarray(psd.C(q)))


def diffusion_time(psd: PowerSpectrum, E_star: float, zeta: ArrayLike) -> FloatOrArray:
    """Diffusion time ``tau(zeta) = (pi/4) E*^2 I3(zeta q_L)`` [Pa^2] (exact).

    ``tau(1) = 0``; the complete-contact pressure variance is ``V_c = 2 tau``.

    Parameters
    ----------
    psd : PowerSpectrum
        Roughness PSD (Persson convention).
    E_star : float
        Contact modulus [Pa].
    zeta : array_like
        Magnification(s), dimensionless.

    Returns
    -------
    float or ndarray
        ``tau`` [Pa^2], same shape as ``zeta``.
    """
    z = np.asarray(zeta, dtype=float)
    return _out(0.25 * np.pi * E_star**2 * np.asarray(psd.I3(z * psd.q_L)))


def G_of_zeta(psd: PowerSpectrum, E_star: float, p0: ArrayLike, zeta: ArrayLike) -> FloatOrArray:
    """Persson's ``G(zeta) = tau(zeta) / p0^2`` (dimensionless).

    Ordinary numpy broadcasting of ``p0`` against ``tau(zeta)``: pass ``p0`` with shape
    ``(n_load, 1)`` and ``zeta`` with shape ``(n_zeta,)`` to get ``(n_load, n_zeta)``.

    Parameters
    ----------
    psd : PowerSpectrum
        Roughness PSD.
    E_star : float
        Contact modulus [Pa].
    p0 : array_like
        Nominal pressure(s) [Pa], > 0.
    zeta : array_like
        Magnification(s).

    Returns
    -------
    float or ndarray
        ``G``, broadcast shape of ``p0`` and ``zeta``.
    """
    p = np.asarray(p0, dtype=float)
    if np.any(~(p > 0)):
        raise ValueError("G_of_zeta: p0 must be > 0")
    tau = np.asarray(diffusion_time(psd, E_star, zeta))
    return _out(tau / p**2)


def _check_p0_tau(p0: ArrayLike, tau: ArrayLike) -> tuple[NDArray, NDArray]:
    p = np.asarray(p0, dtype=float)
    t = np.asarray(tau, dtype=float)
    if np.any(~(p > 0)) or np.any(~np.isfinite(p)):
        raise ValueError("p0 must be finite and > 0")
    if np.any(~(t >= 0)) or np.any(~np.isfinite(t)):
        raise ValueError("tau must be finite and >= 0")
    return p, t


def area_fraction(p0: ArrayLike, tau: ArrayLike) -> tuple[FloatOrArray, FloatOrArray]:
    """Relative contact area ``A/A0 = erf(p0 / (2 sqrt(tau)))`` and its complement.

    Parameters
    ----------
    p0 : array_like
        Nominal pressure [Pa], > 0.
    tau : array_like
        Diffusion time (or effective time of a closure) [Pa^2], >= 0. Broadcast with ``p0``.

    Returns
    -------
    A : float or ndarray
        ``A/A0`` (dimensionless); exactly 1 for ``tau = 0``.
    one_minus_A : float or ndarray
        ``1 - A/A0`` computed with ``erfc`` (no cancellation near full contact); exactly 0 for
        ``tau = 0``.
    """
    from ..engine import exact  # the one home of the single-wall closed form

    p, t = _check_p0_tau(p0, tau)
    area, non, _ = exact.one_wall(t, p, 0.0)
    return _out(area), _out(non)


def pressure_pdf(p: ArrayLike, p0: ArrayLike, tau: ArrayLike) -> FloatOrArray:
    """Mirrored-Gaussian pressure distribution ``P(p, zeta)`` [1/Pa] (:cite:p:`persson2001`).

    ``P = [exp(-(p-p0)^2/(4 tau)) - exp(-(p+p0)^2/(4 tau))] / sqrt(4 pi tau)``, evaluated stably
    as ``N(p - p0) * (-expm1(-p p0 / tau))`` with ``N`` the Gaussian of variance ``2 tau``.
    ``int_0^inf P dp = A/A0``. Zero for ``p <= 0``.

    For ``tau = 0`` the distribution is ``delta(p - p0)``, which has no pointwise
    representation: zeros are returned there (the delta's weight is ``A = 1``).

    Parameters
    ----------
    p : array_like
        Local pressure(s) [Pa].
    p0 : array_like
        Nominal pressure [Pa], > 0.
    tau : array_like
        Diffusion time [Pa^2], >= 0 (``V = 2 tau``).

    Returns
    -------
    float or ndarray
        ``P`` [1/Pa], broadcast shape of the inputs.
    """
    from ..engine import exact  # the one home of the single-wall closed form

    p0_arr, t = _check_p0_tau(p0, tau)
    return _out(exact.one_wall_density(p, t, p0_arr, 0.0))


def load_integral(p0: ArrayLike, tau: ArrayLike) -> FloatOrArray:
    """Closed-form ``int_0^inf p P(p) dp`` [Pa]; equals ``p0`` exactly (load conservation).

    Parameters
    ----------
    p0 : array_like
        Nominal pressure [Pa], > 0.
    tau : array_like
        Diffusion time [Pa^2], >= 0.

    Returns
    -------
    float or ndarray
        ``p0`` broadcast against ``tau``.
    """
    p, t = _check_p0_tau(p0, tau)
    return _out(np.broadcast_to(p, np.broadcast_shapes(p.shape, t.shape)).copy())


def second_moment(p0: ArrayLike, tau: ArrayLike) -> FloatOrArray:
    """Closed-form ``int_0^inf p^2 P(p) dp`` [Pa^2] of the mirrored Gaussian.

    With ``V = 2 tau``, ``s = sqrt(V)``, ``a = p0/s``:
    ``p0^2 + V - 2 V [(1 + a^2) Phi(-a) - a phi(a)]`` (``Phi``, ``phi``: standard normal CDF/PDF).
    Tends to ``p0^2 + V`` in full contact. The mean contact pressure is ``p0 / A``.

    Parameters
    ----------
    p0 : array_like
        Nominal pressure [Pa], > 0.
    tau : array_like
        Diffusion time [Pa^2], >= 0.

    Returns
    -------
    float or ndarray
        Second moment [Pa^2].
    """
    p, t = _check_p0_tau(p0, tau)
    V = 2.0 * t
    with np.errstate(divide="ignore", invalid="ignore"):
        a = p / np.sqrt(V)
        tail = (1.0 + a**2) * 0.5 * erfc(a / math.sqrt(2.0)) - a * np.exp(-0.5 * a**2) / math.sqrt(
            2.0 * math.pi
        )
        out = p**2 + V - 2.0 * V * tail
    out = np.where(V > 0, out, p**2)
    return _out(out)


def full_contact_std(E_star: float, rms_slope: float) -> float:
    """Full-contact pressure standard deviation ``sqrt(V) = E* h'_rms / 2`` [Pa].

    Parameters
    ----------
    E_star : float
        Contact modulus [Pa].
    rms_slope : float
        rms 2-D gradient ``h'_rms`` (dimensionless).
    """
    return 0.5 * float(E_star) * float(rms_slope)


def small_load_area(p0: ArrayLike, E_star: float, rms_slope: float) -> FloatOrArray:
    """Small-load (linear) asymptote ``A/A0 ~ kappa p0 / (E* h'_rms)``, ``kappa = sqrt(8/pi)``.

    Parameters
    ----------
    p0 : array_like
        Nominal pressure [Pa].
    E_star : float
        Contact modulus [Pa].
    rms_slope : float
        rms 2-D gradient ``h'_rms`` (dimensionless).
    """
    return _out(KAPPA * np.asarray(p0, dtype=float) / (E_star * rms_slope))


def rayleigh_pdf(p: ArrayLike, V: ArrayLike) -> FloatOrArray:
    """Small-load conditional pressure PDF ``(p/V) exp(-p^2/(2V))`` [1/Pa], zero for ``p < 0``.

    This is the load-independent limit of ``P(p)/(A/A0)`` for ``p0 << sqrt(V)``
    (:cite:p:`persson2001`); its mean is ``sqrt(pi V / 2)``.

    Parameters
    ----------
    p : array_like
        Pressure [Pa].
    V : array_like
        Variance ``V = 2 tau`` [Pa^2], > 0.
    """
    p_arr = np.asarray(p, dtype=float)
    V_arr = np.asarray(V, dtype=float)
    return _out(np.where(p_arr > 0, p_arr / V_arr * np.exp(-(p_arr**2) / (2.0 * V_arr)), 0.0))
