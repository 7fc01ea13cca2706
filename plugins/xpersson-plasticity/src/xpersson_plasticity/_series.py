"""Exact solution of the heat equation between two absorbing walls (constant hardness).

The elastoplastic contact problem with a constant penetration hardness ``Y`` (physics.md §3.1)
is, in diffusion time ``tau`` [Pa^2],

    dP/dtau = d2P/dp2 on 0 < p < Y,   P(0, tau) = P(Y, tau) = 0,   P(p, 0) = delta(p - p0).

Two equivalent closed forms are implemented:

* **image series** (fast at small ``tau``): the free-space Gaussians of variance ``2 tau``
  centred at ``p0 + 2 n Y`` minus those at ``-p0 + 2 n Y``, ``n`` in Z. Time-integrating the wall
  fluxes gives complementary error functions, so the absorbed fractions are accurate even when
  they are tiny (no cancellation);
* **sine (eigenfunction) series** (fast at large ``tau``): ``P = (2/Y) sum_n sin(n pi p0/Y)
  sin(n pi p/Y) exp(-(n pi/Y)^2 tau)``.

``method="auto"`` uses the images for ``tau/Y^2 < 0.25`` and the sine series above; both keep
enough terms to reach double precision, and they agree to ~1e-15 wherever both are evaluated.

All functions are vectorised over ``tau`` (and ``p``); ``p0`` and ``Y`` are scalars in Pa.
References: B.N.J. Persson, J. Chem. Phys. 115, 3840 (2001), doi:10.1063/1.1388626;
B.N.J. Persson, Surf. Sci. Rep. 61, 201 (2006), doi:10.1016/j.surfrep.2006.04.001.
"""

from __future__ import annotations

from typing import Literal, NamedTuple

import numpy as np
from scipy.special import erfc, ndtr

__all__ = [
    "TwoWallAreas",
    "two_wall_areas",
    "two_wall_pdf",
    "three_gaussian_areas",
    "three_gaussian_pdf",
    "SWITCH",
]

Method = Literal["auto", "images", "sine"]

SWITCH = 0.25
"""Crossover ``tau / Y**2`` between the image series (below) and the sine series (above)."""

_ERFC_CUT = 6.5  # erfc(6.5) ~ 4e-20: images further away than this contribute nothing
_EXP_CUT = 46.0  # exp(-46) ~ 1e-20: sine modes decaying faster than this contribute nothing
_MAX_TERMS = 100_000


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


def _images(t: np.ndarray, x: float) -> tuple[np.ndarray, np.ndarray]:
    """Absorbed fractions (plastic, non-contact) from the image series, t = tau/Y^2, x = p0/Y."""
    tmax = float(t.max(initial=0.0))
    n_terms = int(np.ceil(_ERFC_CUT * np.sqrt(tmax))) + 2
    n = np.arange(n_terms, dtype=float)[:, None]
    s = 2.0 * np.sqrt(t)[None, :]
    with np.errstate(divide="ignore"):
        # erfc(a / s) with s = 0 -> erfc(inf) = 0 for every a > 0 (all shifts are > 0 here).
        def e(a: np.ndarray) -> np.ndarray:
            return erfc(np.where(s > 0, a / np.where(s > 0, s, 1.0), np.inf))

        plastic = np.sum(e((2 * n + 1) - x) - e((2 * n + 1) + x), axis=0)
        non = np.sum(e(2 * n + x), axis=0) - np.sum(e(2 * n[1:] - x), axis=0)
    return plastic, non


def _sine(t: np.ndarray, x: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(elastic, plastic, non-contact) from the sine series, t = tau/Y^2 > 0, x = p0/Y."""
    tmin = float(t.min(initial=np.inf))
    if not tmin > 0:
        raise ValueError("the sine series needs tau > 0; use method='images' or 'auto'")
    n_terms = int(np.ceil(np.sqrt(_EXP_CUT / (np.pi**2 * tmin)))) + 2
    if n_terms > _MAX_TERMS:
        raise ValueError(
            f"tau/Y^2 = {tmin:g} is too small for the sine series ({n_terms} terms); "
            "use method='images' or 'auto'"
        )
    n = np.arange(1, n_terms + 1, dtype=float)[:, None]
    decay = np.exp(-((n * np.pi) ** 2) * t[None, :])
    s = np.sin(n * np.pi * x) / (n * np.pi)
    sign = np.where(n % 2 == 1, 1.0, -1.0)
    odd = n % 2 == 1
    elastic = np.sum(np.where(odd, 4.0 * s, 0.0) * decay, axis=0)
    plastic = x - np.sum(2.0 * sign * s * decay, axis=0)
    non = (1.0 - x) - np.sum(2.0 * s * decay, axis=0)
    return elastic, plastic, non


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
        Series to use; ``"auto"`` picks images for ``tau/Y^2 < 0.25``, sines otherwise.

    Returns
    -------
    TwoWallAreas
        Elastic, plastic and non-contact area fractions [1] and the elastic load [Pa].
    """
    p0, Y = _check(p0, Y)
    tau_arr = _tau(tau)
    t = np.atleast_1d(tau_arr / Y**2).ravel()
    x = p0 / Y
    el = np.empty_like(t)
    pl = np.empty_like(t)
    non = np.empty_like(t)
    if method == "images":
        use_img = np.ones(t.shape, dtype=bool)
    elif method == "sine":
        use_img = np.zeros(t.shape, dtype=bool)
    elif method == "auto":
        use_img = t < SWITCH
    else:
        raise ValueError(f"method must be 'auto', 'images' or 'sine', got {method!r}")
    if use_img.any():
        pl_i, non_i = _images(t[use_img], x)
        pl[use_img], non[use_img] = pl_i, non_i
        el[use_img] = 1.0 - pl_i - non_i
    if (~use_img).any():
        el[~use_img], pl[~use_img], non[~use_img] = _sine(t[~use_img], x)
    shape = tau_arr.shape
    load = p0 - Y * pl
    return TwoWallAreas(
        el.reshape(shape), pl.reshape(shape), non.reshape(shape), load.reshape(shape)
    )


def _gauss(p: np.ndarray, mean: np.ndarray | float, tau: np.ndarray) -> np.ndarray:
    """Normal density of variance ``2 tau`` [1/Pa]."""
    return np.exp(-((p - mean) ** 2) / (4.0 * tau)) / np.sqrt(4.0 * np.pi * tau)


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
    p0, Y = _check(p0, Y)
    t = np.atleast_1d(_tau(tau)).ravel()
    if np.any(t <= 0):
        raise ValueError("two_wall_pdf needs tau > 0 (the initial condition is a delta)")
    pp = np.atleast_1d(np.asarray(p, dtype=float)).ravel()
    out = np.zeros((t.size, pp.size))
    inside = (pp > 0) & (pp < Y)
    q = pp[inside][None, :]
    for i, ti in enumerate(t):
        img = method == "images" or (method == "auto" and ti / Y**2 < SWITCH)
        if img:
            n_terms = int(np.ceil(_ERFC_CUT * np.sqrt(ti) / Y)) + 2
            n = np.arange(-n_terms, n_terms + 1, dtype=float)[:, None]
            val = np.sum(_gauss(q, p0 + 2 * n * Y, ti) - _gauss(q, -p0 + 2 * n * Y, ti), axis=0)
        elif method in ("auto", "sine"):
            k_max = int(np.ceil(np.sqrt(_EXP_CUT / (np.pi**2 * ti / Y**2)))) + 2
            if k_max > _MAX_TERMS:
                raise ValueError(f"tau/Y^2 = {ti / Y**2:g} too small for the sine series")
            k = np.arange(1, k_max + 1, dtype=float)[:, None] * np.pi / Y
            val = (2.0 / Y) * np.sum(np.sin(k * p0) * np.sin(k * q) * np.exp(-(k**2) * ti), axis=0)
        else:
            raise ValueError(f"method must be 'auto', 'images' or 'sine', got {method!r}")
        out[i, inside] = val
    return out


def three_gaussian_pdf(p: np.ndarray, tau: np.ndarray | float, p0: float, Y: float) -> np.ndarray:
    """Three-Gaussian truncation ``N(p; p0) - N(p; -p0) - N(p; 2Y - p0)`` [1/Pa].

    The approximation of Xu, Li & Mulvihill (arXiv:2208.02665): the first image pair of the
    zero-pressure wall plus the first image of the yield wall, variance ``2 tau``. Valid only
    while ``sqrt(2 tau) << Y - p0``; it violates ``P(0) = 0`` by ``-N(0; 2Y - p0)``.

    Returns
    -------
    numpy.ndarray
        Shape ``(n_tau, n_p)``; not clipped to ``[0, Y]`` so that the defect stays visible.
    """
    p0, Y = _check(p0, Y)
    t = np.atleast_1d(_tau(tau)).ravel()[:, None]
    q = np.atleast_1d(np.asarray(p, dtype=float)).ravel()[None, :]
    return _gauss(q, p0, t) - _gauss(q, -p0, t) - _gauss(q, 2 * Y - p0, t)


def _segment(m: float, sd: np.ndarray, a: float, b: float) -> tuple[np.ndarray, np.ndarray]:
    """Mass and first moment of a normal(m, sd^2) density on [a, b]."""
    alpha, beta = (a - m) / sd, (b - m) / sd
    mass = ndtr(beta) - ndtr(alpha)
    phi = (np.exp(-0.5 * alpha**2) - np.exp(-0.5 * beta**2)) / np.sqrt(2 * np.pi)
    return mass, m * mass + sd * phi


def three_gaussian_areas(tau: np.ndarray | float, p0: float, Y: float) -> TwoWallAreas:
    """Area fractions of the three-Gaussian approximation (Xu, Li & Mulvihill 2022).

    ``elastic = int_0^Y P3 dp``; ``plastic = (p0 - int_0^Y p P3 dp) / Y`` (force balance);
    ``non_contact = 1 - elastic - plastic``. Exact to the truncation error only while
    ``sqrt(2 tau) << Y - p0`` (see :func:`three_gaussian_pdf`).

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
