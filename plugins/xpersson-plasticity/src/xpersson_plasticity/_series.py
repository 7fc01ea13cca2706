"""Exact solution of the heat equation between two absorbing walls (constant hardness).

The elastoplastic contact problem with a constant penetration hardness ``Y`` (physics.md §3.1)
is, in diffusion time ``tau`` [Pa^2],

    dP/dtau = d2P/dp2 on 0 < p < Y,   P(0, tau) = P(Y, tau) = 0,   P(p, 0) = delta(p - p0).

The closed forms (image series at small ``tau``, sine series at large ``tau``) have one home,
:mod:`xpersson.engine.exact` (``two_wall_*``); this module gives them the plasticity
vocabulary (elastic / plastic / non-contact area, walls at 0 and ``Y``) and adds the
three-Gaussian approximation of Xu, Li & Mulvihill.

All functions are vectorised over ``tau`` (and ``p``); ``p0`` and ``Y`` are scalars in Pa.
References: B.N.J. Persson, J. Chem. Phys. 115, 3840 (2001), doi:10.1063/1.1388626;
B.N.J. Persson, Surf. Sci. Rep. 61, 201 (2006), doi:10.1016/j.surfrep.2006.04.001.
"""

from __future__ import annotations

from typing import Literal, NamedTuple

import numpy as np
from scipy.special import ndtr

__all__ = [
    "TwoWallAreas",
    "two_wall_areas",
    "two_wall_pdf",
    "three_gaussian_areas",
]

Method = Literal["auto", "images", "sine"]


class TwoWallAreas(NamedTuple):
    """Area fractions of the two-wall problem (dimensionless, shape of ``tau``).

    Attributes
    ----------
    elastic : numpy.ndarray
        Probability still inside ``(0, Y)``: elastic contact area A_el/A0.
    plastic : numpy.ndarray
        Probability absorbed at the yield wall ``p = Y``: plastic contact area A_pl/A0.
    non_contact : numpy.ndarray
        Probability absorbed at ``p = 0``: non-contact area A_non/A0.
    load : numpy.ndarray
        Load carried elastically, ``int_0^Y p P dp`` [Pa]; equals ``p0 - Y * plastic``.
    """

    elastic: np.ndarray
    plastic: np.ndarray
    non_contact: np.ndarray
    load: np.ndarray


def _check(p0: float, Y: float) -> tuple[float, float]:
    p0, Y = float(p0), float(Y)
    if not (np.isfinite(p0) and np.isfinite(Y) and 0.0 < p0 < Y):
        raise ValueError(
            f"the two-wall series needs 0 < p0 < Y (nominal pressure below the hardness); "
            f"got p0 = {p0:g} Pa, Y = {Y:g} Pa"
        )
    return p0, Y


def _tau(tau: np.ndarray | float) -> np.ndarray:
    t = np.asarray(tau, dtype=float)
    if np.any(~np.isfinite(t)) or np.any(t < 0):
        raise ValueError("diffusion time tau [Pa^2] must be finite and >= 0")
    return t


def two_wall_areas(
    tau: np.ndarray | float, p0: float, Y: float, method: Method = "auto"
) -> TwoWallAreas:
    """Exact area fractions between absorbing walls at ``p = 0`` and ``p = Y``.

    Parameters
    ----------
    tau : array_like
        Diffusion time(s) [Pa^2], >= 0 (``tau = G p0^2``, physics.md §1.2).
    p0 : float
        Nominal pressure [Pa], ``0 < p0 < Y``.
    Y : float
        Penetration hardness (yield wall) [Pa].
    method : {"auto", "images", "sine"}
        Series to use; ``"auto"`` picks images for ``tau/Y^2 < 0.1``, sines otherwise.

    Returns
    -------
    TwoWallAreas
        Elastic, plastic and non-contact area fractions [1] and the elastic load [Pa].
    """
    from xpersson.engine import exact

    p0, Y = _check(p0, Y)
    tau_arr = _tau(tau)
    if method not in exact.SERIES:
        raise ValueError(f"method must be 'auto', 'images' or 'sine', got {method!r}")
    el, non, pl = exact.two_wall(tau_arr, p0, 0.0, Y, series=method)
    return TwoWallAreas(el, pl, non, p0 - Y * pl)


def two_wall_pdf(
    p: np.ndarray, tau: np.ndarray | float, p0: float, Y: float, method: Method = "auto"
) -> np.ndarray:
    """Exact pressure distribution ``P(p, tau)`` [1/Pa] between walls at 0 and ``Y``.

    Parameters
    ----------
    p : array_like
        Pressures [Pa]; values outside ``[0, Y]`` give 0.
    tau : array_like
        Diffusion times [Pa^2], > 0.
    p0, Y : float
        Nominal pressure and hardness [Pa], ``0 < p0 < Y``.
    method : {"auto", "images", "sine"}
        As in :func:`two_wall_areas`.

    Returns
    -------
    numpy.ndarray
        Shape ``(n_tau, n_p)`` (``tau`` and ``p`` flattened).
    """
    from xpersson.engine import exact

    p0, Y = _check(p0, Y)
    t = np.atleast_1d(_tau(tau)).ravel()
    if np.any(t <= 0):
        raise ValueError("two_wall_pdf needs tau > 0 (the initial condition is a delta)")
    if method not in exact.SERIES:
        raise ValueError(f"method must be 'auto', 'images' or 'sine', got {method!r}")
    pp = np.atleast_1d(np.asarray(p, dtype=float)).ravel()
    return exact.two_wall_density(pp[None, :], t[:, None], p0, 0.0, Y, series=method)


def _segment(m: float, sd: np.ndarray, a: float, b: float) -> tuple[np.ndarray, np.ndarray]:
    """Mass and first moment of a normal(m, sd^2) density on [a, b]."""
    alpha, beta = (a - m) / sd, (b - m) / sd
    mass = ndtr(beta) - ndtr(alpha)
    phi = (np.exp(-0.5 * alpha**2) - np.exp(-0.5 * beta**2)) / np.sqrt(2 * np.pi)
    return mass, m * mass + sd * phi


def three_gaussian_areas(tau: np.ndarray | float, p0: float, Y: float) -> TwoWallAreas:
    """Area fractions of the three-Gaussian approximation (Xu, Li & Mulvihill 2022).

    ``P3(p) = N(p; p0) - N(p; -p0) - N(p; 2Y - p0)`` (variance ``2 tau``): the first image
    pair of the zero-pressure wall plus the first image of the yield wall (arXiv:2208.02665).
    ``elastic = int_0^Y P3 dp``; ``plastic = (p0 - int_0^Y p P3 dp) / Y`` (force balance);
    ``non_contact = 1 - elastic - plastic``. Exact to the truncation error only while
    ``sqrt(2 tau) << Y - p0``; beyond, ``P3`` violates ``P(0) = 0`` by ``-N(0; 2Y - p0)`` and
    the areas turn unphysical.

    Parameters
    ----------
    tau : array_like
        Diffusion time(s) [Pa^2], >= 0.
    p0, Y : float
        Nominal pressure and hardness [Pa], ``0 < p0 < Y``.
    """
    p0, Y = _check(p0, Y)
    tau_arr = _tau(tau)
    sd = np.sqrt(2.0 * np.maximum(tau_arr, 1e-300 * Y**2))
    mass = np.zeros_like(sd)
    first = np.zeros_like(sd)
    for sign, m in ((1.0, p0), (-1.0, -p0), (-1.0, 2 * Y - p0)):
        ms, fm = _segment(m, sd, 0.0, Y)
        mass += sign * ms
        first += sign * fm
    plastic = (p0 - first) / Y
    return TwoWallAreas(mass, plastic, 1.0 - mass - plastic, first)
