"""Closed forms of ``dP/dtau = d2P/dp2``, ``P(p, 0) = delta(p - p0)``, between walls.

All functions are vectorised (numpy broadcasting over ``tau``, ``p`` and the wall parameters) and
free of cancellation where a quantity is tiny: ``non_area`` uses ``erfc`` / log-space normal tails,
the two-wall functions switch from the image series (small ``tau``) to the sine series (large
``tau``) at ``tau / L**2 = 0.1`` where both agree to round-off.

Units: pressures ``p``, ``p0``, wall positions in Pa; diffusion time ``tau`` in Pa^2; the wall
speed ``c`` of the linear wall in 1/Pa (``p_w = -(s0 + c tau)``); densities in 1/Pa; areas are
fractions of the nominal area (dimensionless).

At ``tau = 0`` the density is a delta function; the density functions return 0 there and the areas
return their initial values (area 1, nothing absorbed).

Families
--------
``one_wall_*``
    Absorbing wall at ``wall`` (default 0), no upper wall: mirrored Gaussian (physics.md §1.2).
``two_wall_*``
    Absorbing walls at ``lower < p0 < upper`` (physics.md §3.1: constant hardness).
``linear_wall_*``
    Absorbing lower wall ``p_w(tau) = -(s0 + c tau)``, no upper wall (physics.md §2.2).
"""

from __future__ import annotations

import functools

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.special import erf, erfc, erfcx, log_ndtr, ndtr

__all__ = [
    "one_wall_area",
    "one_wall_non_area",
    "one_wall_density",
    "one_wall_load",
    "two_wall_area",
    "two_wall_non_area",
    "two_wall_absorbed",
    "two_wall_density",
    "two_wall_load",
    "linear_wall_position",
    "linear_wall_area",
    "linear_wall_non_area",
    "linear_wall_density",
    "linear_wall_load",
    "linear_wall_absorbed_moment",
]

_SQRT2PI = np.sqrt(2.0 * np.pi)
_SWITCH = 0.1  # tau / L^2 where the two-wall functions switch from images to sines
_N_IMAGES = 8  # image pairs kept for tau / L^2 < _SWITCH  (next term ~ erfc(25))
_N_SINES = 48  # sine modes kept for tau / L^2 >= _SWITCH (next term ~ exp(-2270))

Array = NDArray[np.float64]


def _f(x: ArrayLike) -> Array:
    return np.asarray(x, dtype=float)


def _safe_sqrt_tau(tau: Array) -> Array:
    """sqrt(tau) with tau = 0 replaced by 1 (callers mask tau = 0)."""
    return np.sqrt(np.where(tau > 0, tau, 1.0))


def _gauss(p: Array, m: Array, tau: Array) -> Array:
    """Normal density N(p; m, 2 tau) [1/Pa] (tau > 0)."""
    v = 2.0 * tau
    return np.exp(-((p - m) ** 2) / (2.0 * v)) / (_SQRT2PI * np.sqrt(v))


# ---------------------------------------------------------------------------------------------
# one fixed wall
# ---------------------------------------------------------------------------------------------
def one_wall_area(tau: ArrayLike, p0: ArrayLike, wall: ArrayLike = 0.0) -> Array:
    """Contact-area fraction ``A/A0 = erf((p0 - wall) / (2 sqrt(tau)))``.

    Parameters
    ----------
    tau : array_like
        Diffusion time [Pa^2], >= 0.
    p0 : array_like
        Initial (nominal) pressure [Pa], > wall.
    wall : array_like, optional
        Absorbing wall position [Pa].

    Returns
    -------
    ndarray
        Area fraction (dimensionless), 1 at ``tau = 0``.
    """
    tau, x0 = np.broadcast_arrays(_f(tau), _f(p0) - _f(wall))
    st = _safe_sqrt_tau(tau)
    return np.where(tau > 0, erf(x0 / (2.0 * st)), 1.0)


def one_wall(tau: ArrayLike, p0: ArrayLike, wall: ArrayLike = 0.0) -> tuple[Array, Array, Array]:
    """``(area, non_area, load)`` of the one-wall problem in one pass (broadcast inputs).

    The same closed forms as :func:`one_wall_area`, :func:`one_wall_non_area` and
    :func:`one_wall_load` (``load = p0 - wall (1 - A/A0)``, the image integrals combined), with
    ``erf``/``erfc`` evaluated once; ``tau = 0`` gives ``(1, 0, p0)``.
    """
    x0 = _f(p0) - _f(wall)
    with np.errstate(divide="ignore"):
        x = x0 / (2.0 * np.sqrt(_f(tau)))  # +inf at tau = 0 (x0 > 0)
    non = erfc(x)
    return erf(x), non, _f(p0) - _f(wall) * non


def one_wall_non_area(tau: ArrayLike, p0: ArrayLike, wall: ArrayLike = 0.0) -> Array:
    """Absorbed (non-contact) fraction ``1 - A/A0 = erfc((p0 - wall) / (2 sqrt(tau)))``.

    Parameters are those of :func:`one_wall_area`; computed without cancellation.
    """
    tau, x0 = np.broadcast_arrays(_f(tau), _f(p0) - _f(wall))
    st = _safe_sqrt_tau(tau)
    return np.where(tau > 0, erfc(x0 / (2.0 * st)), 0.0)


def one_wall_density(p: ArrayLike, tau: ArrayLike, p0: ArrayLike, wall: ArrayLike = 0.0) -> Array:
    """Mirrored-Gaussian density ``P(p, tau)`` [1/Pa], zero at and below the wall.

    ``P = N(p; p0, 2 tau) - N(p; 2 wall - p0, 2 tau)``, evaluated as
    ``N(p; p0, 2 tau) (1 - exp(-(p - wall)(p0 - wall)/tau))`` (stable near the wall).

    Parameters
    ----------
    p : array_like
        Pressure [Pa].
    tau : array_like
        Diffusion time [Pa^2] (broadcast against ``p``; 0 gives 0).
    p0, wall : array_like
        Initial pressure and wall position [Pa].
    """
    p, tau, p0, wall = np.broadcast_arrays(_f(p), _f(tau), _f(p0), _f(wall))
    ok = (tau > 0) & (p > wall)
    t = np.where(ok, tau, 1.0)
    y = np.where(ok, p - wall, 0.0)
    out = _gauss(p, p0, t) * -np.expm1(-y * (p0 - wall) / t)
    return np.where(ok, out, 0.0)


def one_wall_load(tau: ArrayLike, p0: ArrayLike, wall: ArrayLike = 0.0) -> Array:
    """Load carried by the contact, ``int p P dp`` [Pa] (``= p0 - wall * (1 - A/A0)``).

    Evaluated from the image integrals ``p0 Phi(z) - (2 wall - p0) Q(z)``, ``z = (p0 - wall)/sqrt(2
    tau)``, so that the identity ``load + wall * absorbed = p0`` is an independent check.
    """
    tau, p0, wall = np.broadcast_arrays(_f(tau), _f(p0), _f(wall))
    st = _safe_sqrt_tau(tau)
    z = (p0 - wall) / (np.sqrt(2.0) * st)
    out = p0 * ndtr(z) - (2.0 * wall - p0) * ndtr(-z)
    return np.where(tau > 0, out, p0)


# ---------------------------------------------------------------------------------------------
# two fixed walls
# ---------------------------------------------------------------------------------------------
def _two_wall_setup(tau, p0, lower, upper):
    tau, p0, lower, upper = np.broadcast_arrays(_f(tau), _f(p0), _f(lower), _f(upper))
    length = upper - lower
    x0 = p0 - lower
    small = tau < _SWITCH * length**2
    return tau, p0, lower, upper, length, x0, small


def _images_absorbed(tau, length, x0):
    """Absorbed fractions (lower, upper) from the image series (small tau)."""
    st2 = 2.0 * _safe_sqrt_tau(tau)
    ab_l = np.zeros_like(tau)
    ab_u = np.zeros_like(tau)
    for n in range(_N_IMAGES, -1, -1):  # smallest terms first
        ab_l += erfc((2 * n * length + x0) / st2) - erfc((2 * (n + 1) * length - x0) / st2)
        ab_u += erfc(((2 * n + 1) * length - x0) / st2) - erfc(((2 * n + 1) * length + x0) / st2)
    zero = tau <= 0
    return np.where(zero, 0.0, ab_l), np.where(zero, 0.0, ab_u)


def _sine_sums(tau, length, x0):
    """(area, x-moment) from the sine series (large tau)."""
    area = np.zeros_like(tau)
    xmom = np.zeros_like(tau)
    lsafe = np.where(length > 0, length, 1.0)
    for n in range(_N_SINES, 0, -1):
        k = n * np.pi / lsafe
        e = np.exp(-(k**2) * tau) * np.sin(k * x0)
        if n % 2:
            area += 4.0 / (n * np.pi) * e
        xmom += 2.0 * lsafe * (-1.0) ** (n + 1) / (n * np.pi) * e
    return area, xmom


def two_wall_absorbed(
    tau: ArrayLike, p0: ArrayLike, lower: ArrayLike, upper: ArrayLike
) -> tuple[Array, Array]:
    """Probability absorbed at the lower and at the upper wall up to ``tau``.

    For the elastoplastic problem (lower = 0, upper = sigma_Y) these are the non-contact area and
    the plastic area ``A_pl/A0``.

    Parameters
    ----------
    tau : array_like
        Diffusion time [Pa^2].
    p0 : array_like
        Initial pressure [Pa], ``lower < p0 < upper``.
    lower, upper : array_like
        Absorbing wall positions [Pa].

    Returns
    -------
    (ndarray, ndarray)
        ``absorbed_lower``, ``absorbed_upper`` (dimensionless).
    """
    tau, p0, lower, upper, length, x0, small = _two_wall_setup(tau, p0, lower, upper)
    il, iu = _images_absorbed(tau, length, x0)
    area, xmom = _sine_sums(tau, length, x0)
    lsafe = np.where(length > 0, length, 1.0)
    su = x0 / lsafe - xmom / lsafe
    sl = 1.0 - area - su
    return np.where(small, il, sl), np.where(small, iu, su)


def two_wall_non_area(
    tau: ArrayLike, p0: ArrayLike, lower: ArrayLike, upper: ArrayLike
) -> Array:
    """``1 - A_el/A0``: total probability absorbed at both walls (no cancellation at small tau)."""
    ab_l, ab_u = two_wall_absorbed(tau, p0, lower, upper)
    return ab_l + ab_u


def two_wall_area(tau: ArrayLike, p0: ArrayLike, lower: ArrayLike, upper: ArrayLike) -> Array:
    """Area fraction between two absorbing walls (physics.md §3.1 ``A_el/A0``).

    Image series for ``tau < 0.1 (upper - lower)^2``, sine series
    ``sum_{n odd} 4/(n pi) sin(n pi x0/L) exp(-(n pi/L)^2 tau)`` above.

    Parameters
    ----------
    tau : array_like
        Diffusion time [Pa^2].
    p0 : array_like
        Initial pressure [Pa].
    lower, upper : array_like
        Wall positions [Pa].
    """
    tau, p0, lower, upper, length, x0, small = _two_wall_setup(tau, p0, lower, upper)
    il, iu = _images_absorbed(tau, length, x0)
    area, _ = _sine_sums(tau, length, x0)
    return np.where(small, 1.0 - (il + iu), area)


def two_wall_load(tau: ArrayLike, p0: ArrayLike, lower: ArrayLike, upper: ArrayLike) -> Array:
    """Load carried between the walls, ``int p P dp`` [Pa].

    Sine series of the first moment for large tau; for small tau the image integrals
    ``sum_n [m Phi-window + sqrt(2 tau) phi-window]`` of every image term.
    """
    tau, p0, lower, upper, length, x0, small = _two_wall_setup(tau, p0, lower, upper)
    area, xmom = _sine_sums(tau, length, x0)
    big = lower * area + xmom
    st = np.sqrt(2.0) * _safe_sqrt_tau(tau)
    img = np.zeros_like(tau)
    for n in range(_N_IMAGES, -_N_IMAGES - 1, -1):
        for sign, m in ((1.0, x0 + 2 * n * length), (-1.0, -x0 + 2 * n * length)):
            za = (0.0 - m) / st
            zb = (length - m) / st
            # int_0^L (x + lower) N(x; m, 2 tau) dx
            mass = ndtr(zb) - ndtr(za)
            mom = m * mass + st * (np.exp(-za**2 / 2) - np.exp(-zb**2 / 2)) / _SQRT2PI
            img += sign * (mom + lower * mass)
    out = np.where(small, img, big)
    return np.where(tau > 0, out, p0)


def two_wall_density(
    p: ArrayLike, tau: ArrayLike, p0: ArrayLike, lower: ArrayLike, upper: ArrayLike
) -> Array:
    """Density between two absorbing walls [1/Pa] (image series / sine series).

    Parameters
    ----------
    p : array_like
        Pressure [Pa]; zero outside ``(lower, upper)``.
    tau : array_like
        Diffusion time [Pa^2] (0 gives 0: the delta is not represented).
    p0, lower, upper : array_like
        Initial pressure and wall positions [Pa].
    """
    p, tau, p0, lower, upper = np.broadcast_arrays(_f(p), _f(tau), _f(p0), _f(lower), _f(upper))
    length = upper - lower
    x0 = p0 - lower
    x = p - lower
    ok = (tau > 0) & (x > 0) & (x < length)
    t = np.where(ok, tau, 1.0)
    lsafe = np.where(length > 0, length, 1.0)
    small = t < _SWITCH * lsafe**2
    img = np.zeros_like(t)
    for n in range(_N_IMAGES, -_N_IMAGES - 1, -1):
        img += _gauss(x, x0 + 2 * n * lsafe, t) - _gauss(x, -x0 + 2 * n * lsafe, t)
    sin = np.zeros_like(t)
    for n in range(_N_SINES, 0, -1):
        k = n * np.pi / lsafe
        sin += np.sin(k * x0) * np.sin(k * x) * np.exp(-(k**2) * t)
    sin *= 2.0 / lsafe
    out = np.where(small, img, sin)
    return np.where(ok, out, 0.0)


# ---------------------------------------------------------------------------------------------
# linearly moving wall p_w = -(s0 + c tau)
# ---------------------------------------------------------------------------------------------
def linear_wall_position(tau: ArrayLike, s0: ArrayLike, c: ArrayLike) -> Array:
    """Wall position ``p_w(tau) = -(s0 + c tau)`` [Pa] (``s0`` in Pa, ``c`` in 1/Pa)."""
    return -(_f(s0) + _f(c) * _f(tau))


def _linear_terms(tau, p0, s0, c):
    """(z1, z2, y0, T1 = Phi(z1), T2 = exp(-c y0) Phi(z2)) with no overflow."""
    tau, p0, s0, c = np.broadcast_arrays(_f(tau), _f(p0), _f(s0), _f(c))
    y0 = p0 + s0
    st = np.sqrt(2.0) * _safe_sqrt_tau(tau)
    z1 = (y0 + c * tau) / st
    z2 = (c * tau - y0) / st
    # exp(-c y0) phi(z2) = phi(z1)  ->  T2 = phi(z1) * Mills(-z2) when z2 < 0 (overflow-free)
    phi1 = np.exp(-0.5 * z1**2) / _SQRT2PI
    mills = np.sqrt(np.pi / 2.0) * erfcx(np.where(z2 < 0, -z2, 0.0) / np.sqrt(2.0))
    expo = np.where(z2 >= 0, -c * y0 + log_ndtr(z2), 0.0)
    t2 = np.where(z2 < 0, phi1 * mills, np.exp(expo))
    return tau, p0, s0, c, y0, z1, z2, phi1, t2


def linear_wall_area(tau: ArrayLike, p0: ArrayLike, s0: ArrayLike, c: ArrayLike) -> Array:
    """Area fraction for the linearly moving absorbing wall ``p_w = -(s0 + c tau)`` (§2.2).

    ``A/A0 = Phi((y0 + c tau)/sqrt(2 tau)) - exp(-c y0) Phi((c tau - y0)/sqrt(2 tau))``,
    ``y0 = p0 + s0 > 0``; for ``z1 < 0`` evaluated as a difference of scaled complementary error
    functions (no overflow, reduced cancellation when the wall runs into the mass, ``c < 0``).

    Parameters
    ----------
    tau : array_like
        Diffusion time [Pa^2].
    p0 : array_like
        Initial pressure [Pa].
    s0 : array_like
        Initial wall offset [Pa] (wall starts at ``-s0``).
    c : array_like
        Wall speed [1/Pa] (``c > 0``: wall recedes; ``c < 0``: wall advances into the mass).
    """
    tau, p0, s0, c, y0, z1, z2, phi1, t2 = _linear_terms(tau, p0, s0, c)
    r2 = np.sqrt(2.0)
    neg = z1 < 0
    zz1 = np.where(neg, -z1, 0.0) / r2
    zz2 = np.where(neg, -z2, 0.0) / r2
    a_neg = phi1 * np.sqrt(np.pi / 2.0) * (erfcx(zz1) - erfcx(zz2))
    a_pos = 1.0 - (ndtr(-z1) + t2)
    out = np.where(neg, a_neg, a_pos)
    return np.where(tau > 0, out, 1.0)


def linear_wall_non_area(tau: ArrayLike, p0: ArrayLike, s0: ArrayLike, c: ArrayLike) -> Array:
    """``1 - A/A0`` for the linear wall: ``Phi(-z1) + exp(-c y0) Phi(z2)`` (both terms >= 0)."""
    tau, p0, s0, c, y0, z1, z2, phi1, t2 = _linear_terms(tau, p0, s0, c)
    return np.where(tau > 0, ndtr(-z1) + t2, 0.0)


def linear_wall_density(
    p: ArrayLike, tau: ArrayLike, p0: ArrayLike, s0: ArrayLike, c: ArrayLike
) -> Array:
    """Density for the linear wall [1/Pa]: ``N(p; p0, 2 tau) (1 - exp(-y0 (p - p_w)/tau))``.

    Equal to ``N(p; p0, 2tau) - exp(-c y0) N(p; -p0 - 2 s0, 2tau)`` for ``p > p_w(tau)``, else 0.
    """
    p, tau, p0, s0, c = np.broadcast_arrays(_f(p), _f(tau), _f(p0), _f(s0), _f(c))
    pw = -(s0 + c * tau)
    ok = (tau > 0) & (p > pw)
    t = np.where(ok, tau, 1.0)
    y = np.where(ok, p - pw, 0.0)
    out = _gauss(p, p0, t) * -np.expm1(-(p0 + s0) * y / t)
    return np.where(ok, out, 0.0)


def linear_wall_load(tau: ArrayLike, p0: ArrayLike, s0: ArrayLike, c: ArrayLike) -> Array:
    """Load ``int_{p_w}^inf p P dp = p0 Phi(z1) + (p0 + 2 s0) exp(-c y0) Phi(z2)`` [Pa]."""
    tau, p0, s0, c, y0, z1, z2, phi1, t2 = _linear_terms(tau, p0, s0, c)
    return np.where(tau > 0, p0 * ndtr(z1) + (p0 + 2.0 * s0) * t2, p0)


@functools.lru_cache(maxsize=8)
def _gauss_legendre01(nodes: int) -> tuple[Array, Array]:
    """Gauss-Legendre nodes and weights on [0, 1] (computed once per node count)."""
    u, w = np.polynomial.legendre.leggauss(nodes)
    u, w = 0.5 * (u + 1.0), 0.5 * w
    u.setflags(write=False)
    w.setflags(write=False)
    return u, w


def linear_wall_absorbed_moment(
    tau: ArrayLike, p0: ArrayLike, s0: ArrayLike, c: ArrayLike, nodes: int = 64
) -> Array:
    """``int_0^tau p_w(s) d absorbed(s)`` [Pa], the wall term of the load identity.

    By parts: ``p_w(tau) absorbed(tau) + c int_0^tau absorbed(s) ds``; the last integral by
    Gauss-Legendre in ``u = sqrt(s/tau)`` (the integrand is smooth in u).  The load identity is
    ``load + int p_w d absorbed = p0``.
    """
    tau, p0, s0, c = np.broadcast_arrays(_f(tau), _f(p0), _f(s0), _f(c))
    u, w = _gauss_legendre01(nodes)
    s = tau[..., None] * u**2
    ab = linear_wall_non_area(s, p0[..., None], s0[..., None], c[..., None])
    integral = tau * np.sum(ab * 2.0 * u * w, axis=-1)
    ab_t = linear_wall_non_area(tau, p0, s0, c)
    return linear_wall_position(tau, s0, c) * ab_t + c * integral
