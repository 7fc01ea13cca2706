"""Closed forms of ``dP/dtau = d2P/dp2``, ``P(p, 0) = delta(p - p0)``, between walls.

All functions are vectorised (numpy broadcasting over ``tau``, ``p`` and the wall parameters) and
free of cancellation where a quantity is tiny: ``non_area`` uses ``erfc`` / log-space normal tails,
the two-wall functions switch from the image series (small ``tau``) to the sine series (large
``tau``) at ``tau / L**2 = 0.1`` where both agree to round-off (``series=`` forces one; each
keeps as many terms as double precision needs at the tau it is given).  This module is the one
home of these closed forms: the elastic built-in, the plasticity plugin and
``xpersson.testing`` call it.  It stays one module (over the 500-line limit) on purpose: the
three families share their tail helpers and series switches, and a reader checks each closed
form against its source (the theory pages, the bibliography) in one place.

Units: pressures ``p``, ``p0``, wall positions in Pa; diffusion time ``tau`` in Pa^2; the wall
speed ``c`` of the linear wall in 1/Pa (``p_w = -(s0 + c tau)``); densities in 1/Pa; areas are
fractions of the nominal area (dimensionless).

At ``tau = 0`` the density is a delta function; the density functions return 0 there and the areas
return their initial values (area 1, nothing absorbed).

Families
--------
``one_wall_*``
    Absorbing wall at ``wall`` (default 0), no upper wall: mirrored Gaussian
    (:cite:p:`persson2001`).
``two_wall_*``
    Absorbing walls at ``lower < p0 < upper`` (:cite:p:`persson2006`: constant hardness).
``linear_wall_*``
    Absorbing lower wall ``p_w(tau) = -(s0 + c tau)``, no upper wall
    (:doc:`/theory/03_absorbing_wall`).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.special import erf, erfc, erfcx, log_ndtr, ndtr

from ..cache import memoize

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
    "two_wall",
    "linear_wall_position",
    "linear_wall_area",
    "linear_wall_non_area",
    "linear_wall_density",
    "linear_wall_load",
    "linear_wall_absorbed_moment",
]

_SQRT2PI = np.sqrt(2.0 * np.pi)
_SWITCH = 0.1  # tau / L^2 where the two-wall functions switch from images to sines

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
    area, non = one_wall_area_non(tau, p0, wall)
    load = np.multiply(non, -_f(wall))
    load += _f(p0)
    if np.ndim(non) == 0:  # scalar inputs: scalars out, as erf gives
        non, load = non[()], load[()]
    return area, non, load


def one_wall_area_non(tau: ArrayLike, p0: ArrayLike, wall: ArrayLike = 0.0) -> tuple[Array, Array]:
    """``(area, non_area)`` of the one-wall problem (:func:`one_wall` without the load)."""
    x0 = _f(p0) - _f(wall)
    t = _f(tau)
    shape = np.broadcast_shapes(x0.shape, t.shape)
    if (
        t.ndim == 2
        and t.strides[0] == 0
        and np.broadcast_shapes(x0.shape, (1, t.shape[1])) == (shape)
    ):  # one tau row broadcast over loads: sqrt it once
        t = t[:1]
    with np.errstate(divide="ignore"):
        x = np.asarray(x0 / (2.0 * np.sqrt(t)))  # +inf at tau = 0 (x0 > 0)
    # erf for the area and erfc for the absorbed fraction, each once over the whole array:
    # both keep their full relative accuracy (1 - erfc or 1 - erf would lose it at one end),
    # and two unmasked passes cost less than splitting the array by boolean masks
    # (large temporaries are reused: each fresh 0.4 MB array of a 1000 x 51 batch costs about
    # as much in page faults as the special function itself)
    return _erf_erfc(x)


#: ``erf(x)`` is exactly 1 for every ``x >= 6.5`` and ``erfc(x)`` exactly +0 for every
#: ``x >= 28`` (``erfc(6.5) = 3.8e-20``, ``erfc(28) = 6e-343``: scipy's, as any faithful one).
_ERF_ONE, _ERFC_ZERO = 6.5, 28.0


def _erf_erfc(x: Array) -> tuple[Array, Array]:
    """``(erf(x), erfc(x))``, the second into ``x``: the leading columns (last axis) where
    every ``x`` is beyond :data:`_ERF_ONE` / :data:`_ERFC_ZERO` (near ``tau = 0``: about half
    the loads' dense grid) set to those values, not evaluated, and ``erf = 1 - erfc`` where
    ``x > 1`` (the same bits)."""
    if x.ndim < 2 or x.size <= _SMALL:  # (the cut's bookkeeping costs more than it saves)
        return erf(x), erfc(x, out=x)
    low = np.min(x, axis=tuple(range(x.ndim - 1)))  # (NaN: never beyond)
    j1, j2 = (int(np.argmin(low >= c)) if not np.all(low >= c) else low.size for c in _CUTS)
    area = np.empty_like(x)
    area[..., :j1] = 1.0
    # scipy's erf is ``1 - erfc(x)`` for every x > 1 (cephes' ndtr.c; tests/engine check the
    # bits): there it is taken from the erfc evaluated anyway (two thirds of a dense grid's
    # values on the speed design: ~0.15 ms of a 100-load re-solve), the rest evaluated
    xb, ab = x[..., j1:], area[..., j1:]
    rest = ~(xb > 1.0)  # |x| <= 1, x < -1, NaN: erf's own evaluation
    lo = erf(xb[rest])
    x[..., :j2] = 0.0
    erfc(x[..., j2:], out=x[..., j2:])
    np.subtract(1.0, xb, out=ab)
    ab[rest] = lo
    return area, x


_CUTS = (_ERF_ONE, _ERFC_ZERO)
_SMALL = 4096
"""Arrays of at most this many values are evaluated whole (one load's 51 values: ~1.4 us
against ~16 us with the cut; still faster at 100 x 51)."""


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
_ERFC_CUT = 6.5  # erfc(6.5) ~ 4e-20: images farther away than this contribute nothing
_EXP_CUT = 46.0  # exp(-46) ~ 1e-20: sine modes decaying faster than this contribute nothing
_MAX_TERMS = 100_000
SERIES = ("auto", "images", "sine")


def _use_images(t: Array, series: str) -> Array:
    """Where the image series is used (``t = tau / L^2``)."""
    if series == "auto":
        return t < _SWITCH
    if series == "images":
        return np.ones(t.shape, dtype=bool)
    if series == "sine":
        return np.zeros(t.shape, dtype=bool)
    raise ValueError(f"series must be one of {SERIES}; got {series!r}")


def _n_images(t: Array) -> int:
    """Image pairs needed for ``t = tau / L^2`` up to ``max(t)`` (next term < erfc(6.5))."""
    return int(np.ceil(_ERFC_CUT * np.sqrt(float(np.max(t, initial=0.0))))) + 2


def _n_sines(t: Array) -> int:
    """Sine modes needed down to ``min(t)`` (next mode decays below exp(-46))."""
    tmin = float(np.min(t, initial=np.inf))
    if not np.isfinite(tmin):
        return 0
    if not tmin > 0:
        raise ValueError("the sine series needs tau > 0; use series='images' or 'auto'")
    n = int(np.ceil(np.sqrt(_EXP_CUT / (np.pi**2 * tmin)))) + 2
    if n > _MAX_TERMS:
        raise ValueError(
            f"tau/L^2 = {tmin:g} is too small for the sine series ({n} terms); use "
            "series='images' or 'auto'"
        )
    return n


def _two_wall_setup(tau, p0, lower, upper):
    tau, p0, lower, upper = np.broadcast_arrays(_f(tau), _f(p0), _f(lower), _f(upper))
    length = upper - lower
    return tau, p0, lower, upper, length, p0 - lower


def _images_absorbed(tau, length, x0):
    """Absorbed fractions (lower, upper) from the image series (1-D arrays, tau > 0)."""
    st2 = 2.0 * np.sqrt(tau)
    ab_l = np.zeros_like(tau)
    ab_u = np.zeros_like(tau)
    for n in range(_n_images(tau / length**2), -1, -1):  # smallest terms first
        ab_l += erfc((2 * n * length + x0) / st2) - erfc((2 * (n + 1) * length - x0) / st2)
        ab_u += erfc(((2 * n + 1) * length - x0) / st2) - erfc(((2 * n + 1) * length + x0) / st2)
    return ab_l, ab_u


def _sine_sums(tau, length, x0):
    """(area, x-moment) from the sine series (1-D arrays, tau > 0)."""
    area = np.zeros_like(tau)
    xmom = np.zeros_like(tau)
    for n in range(_n_sines(tau / length**2), 0, -1):
        k = n * np.pi / length
        e = np.exp(-(k**2) * tau) * np.sin(k * x0)
        if n % 2:
            area += 4.0 / (n * np.pi) * e
        xmom += 2.0 * length * (-1.0) ** (n + 1) / (n * np.pi) * e
    return area, xmom


def _two_wall_parts(tau, p0, lower, upper, series):
    """(area, absorbed_lower, absorbed_upper, shape) with each series used only where chosen."""
    tau, p0, lower, upper, length, x0 = _two_wall_setup(tau, p0, lower, upper)
    shape = tau.shape
    t, L, x = tau.ravel(), length.ravel(), x0.ravel()
    pos = t > 0
    img = _use_images(np.where(pos, t, 0.0) / L**2, series) & pos
    sin = ~img & pos
    area = np.ones(t.size)
    ab_l = np.zeros(t.size)
    ab_u = np.zeros(t.size)
    if img.any():
        il, iu = _images_absorbed(t[img], L[img], x[img])
        ab_l[img], ab_u[img] = il, iu
        area[img] = 1.0 - (il + iu)
    if sin.any():
        a, xm = _sine_sums(t[sin], L[sin], x[sin])
        su = x[sin] / L[sin] - xm / L[sin]
        area[sin], ab_u[sin] = a, su
        ab_l[sin] = 1.0 - a - su
    return area.reshape(shape), ab_l.reshape(shape), ab_u.reshape(shape)


def two_wall_absorbed(
    tau: ArrayLike, p0: ArrayLike, lower: ArrayLike, upper: ArrayLike, series: str = "auto"
) -> tuple[Array, Array]:
    """Probability absorbed at the lower and at the upper wall up to ``tau``.

    For the elastoplastic problem (lower = 0, upper = sigma_Y) these are the non-contact area and
    the plastic area ``A_pl/A0``.  The image series (complementary error functions of the
    time-integrated wall fluxes, accurate when tiny) is used for ``tau < 0.1 (upper - lower)^2``
    and the sine series above (``series="auto"``); ``"images"`` / ``"sine"`` force one (both
    keep enough terms for double precision at any tau, and agree to ~1e-15).

    Parameters
    ----------
    tau : array_like
        Diffusion time [Pa^2].
    p0 : array_like
        Initial pressure [Pa], ``lower < p0 < upper``.
    lower, upper : array_like
        Absorbing wall positions [Pa].
    series : {"auto", "images", "sine"}
        Which series to evaluate.

    Returns
    -------
    (ndarray, ndarray)
        ``absorbed_lower``, ``absorbed_upper`` (dimensionless).
    """
    _, ab_l, ab_u = _two_wall_parts(tau, p0, lower, upper, series)
    return ab_l, ab_u


def two_wall_non_area(
    tau: ArrayLike, p0: ArrayLike, lower: ArrayLike, upper: ArrayLike, series: str = "auto"
) -> Array:
    """``1 - A_el/A0``: total probability absorbed at both walls (no cancellation at small tau)."""
    _, ab_l, ab_u = _two_wall_parts(tau, p0, lower, upper, series)
    return ab_l + ab_u


def two_wall_area(
    tau: ArrayLike, p0: ArrayLike, lower: ArrayLike, upper: ArrayLike, series: str = "auto"
) -> Array:
    """Area fraction between two absorbing walls (:cite:p:`persson2006` ``A_el/A0``).

    Image series for ``tau < 0.1 (upper - lower)^2``, sine series
    ``sum_{n odd} 4/(n pi) sin(n pi x0/L) exp(-(n pi/L)^2 tau)`` above (see
    :func:`two_wall_absorbed` for ``series``).

    Parameters
    ----------
    tau : array_like
        Diffusion time [Pa^2].
    p0 : array_like
        Initial pressure [Pa].
    lower, upper : array_like
        Wall positions [Pa].
    series : {"auto", "images", "sine"}
        Which series to evaluate.
    """
    return _two_wall_parts(tau, p0, lower, upper, series)[0]


def two_wall(
    tau: ArrayLike, p0: ArrayLike, lower: ArrayLike, upper: ArrayLike, series: str = "auto"
) -> tuple[Array, Array, Array]:
    """``(area, absorbed_lower, absorbed_upper)`` in one evaluation (see the functions above)."""
    return _two_wall_parts(tau, p0, lower, upper, series)


def two_wall_load(tau: ArrayLike, p0: ArrayLike, lower: ArrayLike, upper: ArrayLike) -> Array:
    """Load carried between the walls, ``int p P dp`` [Pa].

    Sine series of the first moment for large tau; for small tau the image integrals
    ``sum_n [m Phi-window + sqrt(2 tau) phi-window]`` of every image term (independent of the
    absorbed fractions, so that the load identity is a check).
    """
    tau, p0, lower, upper, length, x0 = _two_wall_setup(tau, p0, lower, upper)
    shape = tau.shape
    t, L, x, lo, pp = (a.ravel() for a in (tau, length, x0, lower, p0))
    pos = t > 0
    img = (t < _SWITCH * L**2) & pos
    sin = ~img & pos
    out = pp.astype(float).copy()
    if sin.any():
        area, xmom = _sine_sums(t[sin], L[sin], x[sin])
        out[sin] = lo[sin] * area + xmom
    if img.any():
        ti, Li, xi, li = t[img], L[img], x[img], lo[img]
        st = np.sqrt(2.0 * ti)
        acc = np.zeros_like(ti)
        n_img = _n_images(ti / Li**2)
        for n in range(n_img, -n_img - 1, -1):
            for sign, m in ((1.0, xi + 2 * n * Li), (-1.0, -xi + 2 * n * Li)):
                za = (0.0 - m) / st
                zb = (Li - m) / st
                # int_0^L (x + lower) N(x; m, 2 tau) dx
                mass = ndtr(zb) - ndtr(za)
                mom = m * mass + st * (np.exp(-(za**2) / 2) - np.exp(-(zb**2) / 2)) / _SQRT2PI
                acc += sign * (mom + li * mass)
        out[img] = acc
    return out.reshape(shape)


def two_wall_density(
    p: ArrayLike,
    tau: ArrayLike,
    p0: ArrayLike,
    lower: ArrayLike,
    upper: ArrayLike,
    series: str = "auto",
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
    series : {"auto", "images", "sine"}
        Which series to evaluate (see :func:`two_wall_absorbed`).
    """
    p, tau, p0, lower, upper = np.broadcast_arrays(_f(p), _f(tau), _f(p0), _f(lower), _f(upper))
    shape = p.shape
    L = (upper - lower).ravel()
    x0 = (p0 - lower).ravel()
    x = (p - lower).ravel()
    t = tau.ravel()
    ok = (t > 0) & (x > 0) & (x < L)
    img = _use_images(np.where(ok, t, 0.0) / np.where(L > 0, L, 1.0) ** 2, series) & ok
    sin = ~img & ok
    out = np.zeros(t.size)
    if img.any():
        ti, Li, xi, x0i = t[img], L[img], x[img], x0[img]
        acc = np.zeros_like(ti)
        n_img = _n_images(ti / Li**2)
        for n in range(n_img, -n_img - 1, -1):
            acc += _gauss(xi, x0i + 2 * n * Li, ti) - _gauss(xi, -x0i + 2 * n * Li, ti)
        out[img] = acc
    if sin.any():
        ts, Ls, xs, x0s = t[sin], L[sin], x[sin], x0[sin]
        acc = np.zeros_like(ts)
        for n in range(_n_sines(ts / Ls**2), 0, -1):
            k = n * np.pi / Ls
            acc += np.sin(k * x0s) * np.sin(k * xs) * np.exp(-(k**2) * ts)
        out[sin] = 2.0 / Ls * acc
    return out.reshape(shape)


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


@memoize("engine.gauss_legendre01", scope="process", maxsize=8)
def _gauss_legendre01(nodes: int) -> tuple[Array, Array]:
    """Gauss-Legendre nodes and weights on [0, 1] (read-only; computed once per node count)."""
    u, w = np.polynomial.legendre.leggauss(nodes)
    return 0.5 * (u + 1.0), 0.5 * w


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
