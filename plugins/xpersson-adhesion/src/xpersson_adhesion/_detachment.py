"""Detachment stress sigma_a(zeta) of Persson's adhesive boundary condition (physics.md §2.1).

Model (Persson & Tosatti 2001; Persson 2002)::

    gamma_eff(zeta) A*(zeta) = dgamma A*(zeta_1) - U_el(zeta),
    sigma_a(zeta) = [c_a gamma_eff(zeta) E* q]^(1/2),   q = zeta q_L,

with ``dgamma`` the work of adhesion at the finest scale [J/m^2], ``A*(zeta)/A0`` the true
(surface) area of the roughness resolved up to ``zeta`` (exact for a Gaussian isotropic surface,
:func:`true_area_ratio`) and ``U_el(zeta)/A0`` the full-contact elastic energy of the roughness
finer than ``zeta`` [J/m^2]
(:func:`xpersson.physics.interface.full_contact_energy` of the scale band). gamma_eff is
computed top-down from zeta_1 and clipped at 0: where roughness destroys adhesion the wall sits
at p = 0 (elastic contact).

A user table ``(zeta_i, sigma_a_i)`` replaces the model; it is interpolated monotonically (PCHIP)
in diffusion time ``tau(zeta_i)``, so that a table affine in tau is an exactly linear wall.
"""

from __future__ import annotations

import hashlib
import math
from collections.abc import Callable, Hashable
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.special import erfcx

from xpersson.cache import Cache, content_key, digest, made_key
from xpersson.physics.interface import full_contact_energy

from ._wallpos import _Pchip, _SqrtPos

__all__ = [
    "true_area_ratio",
    "true_area_slope",
    "gamma_effective",
    "detachment_stress",
    "ModelLaw",
    "TableLaw",
    "check_table",
]

Array = NDArray[np.float64]


#: What ModelLaw derives from a spectrum: sigma_a^2 and its slopes at the magnifications of its
#: table in tau; the table sigma_a(tau) of a clock's samples; whether sigma_a vanishes.
_SAMPLES = Cache("adhesion.detachment_samples", scope="spectrum", maxsize=32, doc="sigma_a^2")
_TABLES = Cache("adhesion.detachment_table", scope="spectrum", maxsize=32, doc="sigma_a(tau)")
_CONSTANT = Cache("adhesion.detachment_constant", scope="spectrum", maxsize=64, doc="sigma_a = 0")


def true_area_ratio(slope2: ArrayLike) -> Array:
    """True-to-nominal area ``A*/A0 = int_0^inf e^-x (1 + xi^2 x)^(1/2) dx`` [1].

    Closed form ``1 + (sqrt(pi)/2) xi erfcx(1/xi)`` (exact for a Gaussian isotropic surface,
    whose ``|grad h|^2`` is exponentially distributed); ``~ 1 + xi^2/2`` for small ``xi``.

    Parameters
    ----------
    slope2 : array_like
        Mean-square slope ``xi^2 = <|grad h|^2>`` of the resolved roughness [1], >= 0.
    """
    s2 = np.asarray(slope2, dtype=float)
    xi = np.sqrt(np.maximum(s2, 0.0))
    with np.errstate(divide="ignore"):
        inv = np.where(xi > 0, 1.0 / np.where(xi > 0, xi, 1.0), np.inf)
    return 1.0 + 0.5 * math.sqrt(math.pi) * xi * np.where(xi > 0, erfcx(inv), 0.0)


def true_area_slope(slope2: ArrayLike) -> Array:
    """``d(A*/A0)/d(xi^2) = int_0^inf e^-x x / (2 (1 + xi^2 x)^(1/2)) dx`` [1].

    Closed form ``(sqrt(pi)/(4 xi)) [erfcx(u) (1 - 2u^2) + 2u/sqrt(pi)]``, ``u = 1/xi``; the
    series ``1/2 - a/2 + 9a^2/8 - 15a^3/4`` (``a = xi^2``) below ``a = 1e-4``.
    """
    a = np.maximum(np.asarray(slope2, dtype=float), 0.0)
    small = a < 1e-4
    xi = np.sqrt(np.where(small, 1.0, a))
    u = 1.0 / xi
    closed = (
        math.sqrt(math.pi)
        / (4.0 * xi)
        * (erfcx(u) * (1.0 - 2.0 * u * u) + 2.0 * u / math.sqrt(math.pi))
    )
    series = 0.5 - 0.5 * a + 1.125 * a * a - 3.75 * a**3
    return np.where(small, series, closed)


def gamma_effective(
    psd: object, E_star: float, work: float, zeta: ArrayLike
) -> tuple[Array, Array, Array, Array]:
    """Effective interfacial energy gamma_eff(zeta) [J/m^2] (top-down from zeta_1).

    Parameters
    ----------
    psd : PowerSpectrum
        Roughness spectrum (Persson convention, m^4; ``q_L``, ``q_1`` in 1/m).
    E_star : float
        Contact modulus [Pa].
    work : float
        Work of adhesion at the finest scale ``dgamma`` [J/m^2], >= 0.
    zeta : array_like
        Magnifications [1].

    Returns
    -------
    gamma : ndarray
        ``max(gamma_eff, 0)`` [J/m^2].
    raw : ndarray
        ``gamma_eff`` before clipping [J/m^2] (negative where roughness destroys adhesion).
    true_area : ndarray
        ``A*(zeta)/A0`` [1].
    energy : ndarray
        ``U_el(zeta)/A0`` [J/m^2], full-contact elastic energy of the scales finer than zeta.
    """
    raw, a_star, energy, _ = _gamma_parts(psd, E_star, work, zeta)
    return np.maximum(raw, 0.0), raw, a_star, energy


def _gamma_parts(
    psd: object, E_star: float, work: float, zeta: ArrayLike
) -> tuple[Array, Array, Array, Array]:
    """Unclipped gamma_eff [J/m^2], ``A*/A0`` [1], ``U_el/A0`` [J/m^2] and the mean-square
    slope ``xi^2`` [1] of the resolved roughness at magnifications ``zeta`` (element-wise)."""
    z = np.asarray(zeta, dtype=float)
    q_L, q_1 = float(psd.q_L), float(psd.q_1)  # type: ignore[attr-defined]
    slope2 = 2.0 * math.pi * np.asarray(psd.I3(z * q_L), dtype=float)  # type: ignore[attr-defined]
    a_star = true_area_ratio(slope2)
    a_star_1 = float(true_area_ratio(2.0 * math.pi * float(psd.I3(q_1))))  # type: ignore[attr-defined]
    energy = np.asarray(full_contact_energy(psd, E_star, z * q_L), dtype=float)
    raw = (work * a_star_1 - energy) / a_star
    return raw, a_star, energy, slope2


def detachment_stress(gamma: ArrayLike, E_star: float, q: ArrayLike, c_a: float) -> Array:
    """``sigma_a = [c_a gamma E* q]^(1/2)`` [Pa] (gamma [J/m^2], q [1/m], E* [Pa])."""
    g = np.maximum(np.asarray(gamma, dtype=float), 0.0)
    return np.sqrt(c_a * g * E_star * np.asarray(q, dtype=float))


class ModelLaw:
    """sigma_a(zeta) [Pa] of the gamma_eff model (picklable, vectorised)."""

    def __init__(self, psd: object, E_star: float, work: float, c_a: float) -> None:
        self.psd = psd
        self.E_star = float(E_star)
        self.work = float(work)
        self.c_a = float(c_a)

    def gamma(self, zeta: ArrayLike) -> Array:
        """Clipped gamma_eff(zeta) [J/m^2]."""
        return gamma_effective(self.psd, self.E_star, self.work, zeta)[0]

    def __call__(self, zeta: ArrayLike) -> Array:
        z = np.asarray(zeta, dtype=float)
        q = z * float(self.psd.q_L)
        return detachment_stress(self.gamma(z), self.E_star, q, self.c_a)

    def sigma2_and_slope(self, zeta: ArrayLike) -> tuple[Array, Array]:
        """Unclipped ``c_a gamma_eff E* q`` [Pa^2] and its derivative in zeta [Pa^2].

        Smooth across the zero of gamma_eff (``sigma_a^2`` is its positive part).
        """
        psd, E = self.psd, self.E_star
        z = np.asarray(zeta, dtype=float)
        q_L = float(psd.q_L)
        q = z * q_L
        C = np.asarray(psd.C(q), dtype=float)  # type: ignore[attr-defined]
        raw, a_star, _, s2 = _gamma_parts(psd, E, self.work, z)
        da_star = true_area_slope(s2) * 2.0 * math.pi * q**3 * C * q_L
        du = -0.5 * math.pi * E * q**2 * C * q_L
        dgamma = (-du - raw * da_star) / a_star
        return self.c_a * E * q * raw, self.c_a * E * (q_L * raw + q * dgamma)

    def in_tau(self, clock: object, per_decade: int = 200) -> _Pchip:
        """sigma_a as a function of tau [Pa^2 -> Pa]: a piecewise cubic Hermite table.

        ``sigma_a^2`` (unclipped) is interpolated in tau with its exact slope
        ``d(sigma^2)/dzeta / f(zeta)`` on ``per_decade`` log-spaced magnifications, split at
        the spectrum's breakpoints (one-sided slopes there); ``sigma_a`` is the square root of
        its positive part. Relative error ~1e-10 of max sigma_a (tested); evaluating it costs a
        spline call instead of the clock's inverse and the spectrum moments.
        """
        return self.table_and_key(clock, per_decade)[0]

    def table_and_key(self, clock: object, per_decade: int = 200) -> tuple[_Pchip, Hashable]:
        """:meth:`in_tau`'s table and its content key (``("model", d)``: equal keys, equal
        tables; the jkr wall compares by it). ``d`` is made of the law's numbers, the clock's
        ``zeta_max`` and the clock's content key (``clock.key``, when it has one: the clock is
        then sampled only when the table is not kept), else a 128-bit digest of those numbers
        and the clock's samples tau [Pa^2] and f [Pa^2] at the table's magnifications (a
        digest is keyed and compared without walking the key's parts)."""
        zmax = float(clock.zeta_max)  # type: ignore[attr-defined]
        head = (self.psd, *self._key(), zmax, per_decade)
        by_clock = getattr(clock, "key", None)
        if by_clock is not None:
            ck = ("model", made_key((*head, by_clock)))  # (made once: keyed as it is)
            return _TABLES.get(ck, lambda: self._fit(*self._clock_samples(clock, head))), ck
        parts = self._clock_samples(clock, head)
        text = repr(content_key(head)).encode()
        ck = ("model", hashlib.blake2b(text + digest(*parts[2:4]), digest_size=16).digest())
        return _TABLES.get(ck, lambda: self._fit(*parts)), ck

    def _clock_samples(self, clock: object, head: tuple[Any, ...]) -> tuple[Array, ...]:
        """``sigma_a^2`` [Pa^2], its slope in zeta [Pa^2] (cached per spectrum), the clock's
        tau [Pa^2] and f [Pa^2] at the table's magnifications; ``head``: the law's key."""
        z_all, zo_all, cut, s2_nodes, ds2_nodes = self._samples(*head[-2:])
        t_nodes = np.asarray(clock.tau_of_zeta(z_all), dtype=float)  # type: ignore[attr-defined]
        f_nodes = np.asarray(clock.f(zo_all), dtype=float)  # type: ignore[attr-defined]
        return s2_nodes, ds2_nodes, t_nodes, f_nodes, cut

    def _key(self) -> tuple[Any, ...]:
        """What the law depends on besides its spectrum (cache keys)."""
        return (self.E_star, self.work, self.c_a)

    def _samples(self, zmax: float, per_decade: int) -> tuple[Array, Array, Array, Array, Array]:
        """The magnifications of :meth:`in_tau`'s table (nodes, and nodes with the pieces'
        ends moved inside: one-sided slopes), the cuts between pieces, ``sigma_a^2`` at the
        nodes [Pa^2] and its one-sided slopes in zeta [Pa^2] (cached per spectrum)."""
        key = (self.psd, *self._key(), zmax, per_decade)
        return _SAMPLES.get(key, lambda: self._sample(zmax, per_decade))

    def _sample(self, zmax: float, per_decade: int) -> tuple[Array, Array, Array, Array, Array]:
        q_L = float(self.psd.q_L)  # type: ignore[attr-defined]
        brk = np.asarray(self.psd.nodes(), dtype=float) / q_L  # type: ignore[attr-defined]
        brk = np.unique(np.concatenate(([1.0], brk[(brk > 1.0) & (brk < zmax)], [zmax])))
        zs_, ends = [], []
        for a, b in zip(brk[:-1], brk[1:], strict=True):
            n = max(4, int(math.ceil(per_decade * math.log10(b / a))) + 1)
            z = np.geomspace(a, b, n)
            z[0], z[-1] = a, b
            zs_.append(z)
            ends += [a * (1 + 1e-12), b * (1 - 1e-12)]  # one-sided: slopes from inside the piece
        # every piece in one call of the model and of the clock (the calls' fixed cost dominated);
        # the slopes differ from the values' nodes only at the pieces' ends: evaluated there only
        sizes = np.array([z.size for z in zs_])
        cut = np.cumsum(sizes)[:-1]
        first = np.concatenate(([0], cut))
        at_ends = np.column_stack((first, first + sizes - 1)).ravel()
        z_all = np.concatenate(zs_)
        zo_all = z_all.copy()
        zo_all[at_ends] = ends
        s2_nodes, ds2_nodes = self.sigma2_and_slope(np.concatenate([z_all, ends]))
        ds2_one_sided = ds2_nodes[: z_all.size].copy()
        ds2_one_sided[at_ends] = ds2_nodes[z_all.size :]
        return z_all, zo_all, cut, s2_nodes[: z_all.size].copy(), ds2_one_sided

    def _fit(self, s2_nodes: Array, ds2_nodes: Array, t: Array, f: Array, cut: Array) -> _Pchip:
        """The table of :meth:`in_tau` from its samples (``sigma_a^2`` [Pa^2], its slope in
        zeta [Pa^2], tau [Pa^2] and f = dtau/dzeta [Pa^2]), split into pieces at ``cut``."""
        from scipy.interpolate import PPoly

        pieces = (np.split(a, cut) for a in (s2_nodes, ds2_nodes, t, f))
        xs, cs = [], []
        for s2, ds2, t, f in zip(*pieces, strict=True):
            keep = np.concatenate(([True], np.diff(t) > 0))
            if keep.sum() < 2:
                continue
            tk = t[keep]
            xs.append(tk if not xs else tk[1:])
            cs.append(_hermite(tk, s2[keep], (ds2 / f)[keep]))
        if not xs:
            value = float(self(np.array([1.0]))[0])
            return lambda tt: np.full(np.shape(tt), value)  # type: ignore[return-value]
        x = np.concatenate(xs)
        poly = PPoly(np.concatenate(cs, axis=1), x, extrapolate=False)
        return _Pchip(_SqrtPos(poly), float(x[0]), float(x[-1]))

    def is_constant(self, zeta_max: float, sigma_end: Callable[[], float] | None = None) -> bool:
        """True when sigma_a vanishes on the whole range (then the wall is the elastic one).

        ``sigma_end`` (optional) gives ``self([zeta_max])[0]`` [Pa] from values at hand.
        """
        if self.work == 0.0:
            return True
        key = (self.psd, *self._key(), float(zeta_max))
        return _CONSTANT.get(key, lambda: self._is_constant(zeta_max, sigma_end))

    def _is_constant(self, zeta_max: float, sigma_end: Callable[[], float] | None) -> bool:
        z_end = max(zeta_max, 1.0)
        end = sigma_end() if sigma_end is not None and z_end == zeta_max else None
        if end is None:
            end = self(np.array([z_end]))[0]
        if end != 0.0:  # the last of the samples below: not constant
            return False
        z = np.geomspace(1.0, z_end, 257)
        return bool(np.all(self(z) == 0.0))


def _hermite(x: Array, y: Array, dydx: Array) -> Array:
    """Power-basis coefficients (4, n - 1) of the cubic Hermite interpolant of ``(x, y, dydx)``
    (``scipy.interpolate.CubicHermiteSpline(x, y, dydx).c`` without its input checks: ``x``
    strictly increasing and finite here by construction)."""
    h = np.diff(x)
    slope = np.diff(y) / h
    t = (dydx[:-1] + dydx[1:] - 2 * slope) / h
    return np.stack((t / h, (slope - dydx[:-1]) / h - t, dydx[:-1], y[:-1]))


def check_table(zeta: ArrayLike, sigma: ArrayLike) -> tuple[Array, Array]:
    """Validate a detachment table; raise ValueError naming parameter, unit and range."""
    z = np.atleast_1d(np.asarray(zeta, dtype=float))
    s = np.atleast_1d(np.asarray(sigma, dtype=float))
    if z.ndim != 1 or s.ndim != 1 or z.size != s.size:
        raise ValueError(
            f"boundary.sigma_a_zeta [1] and boundary.sigma_a [Pa] must be 1-D arrays of the "
            f"same length; got {z.size} and {s.size} values"
        )
    if z.size < 1:
        raise ValueError("boundary.sigma_a [Pa]: give at least one value (a constant wall)")
    if not (np.all(np.isfinite(z)) and np.all(np.isfinite(s))):
        raise ValueError("boundary.sigma_a_zeta [1] and boundary.sigma_a [Pa] must be finite")
    if np.any(s < 0):
        raise ValueError(
            f"boundary.sigma_a = {float(s.min()):g} Pa is outside the allowed range [0, inf] Pa "
            "(a detachment stress is tensile: the wall sits at p = -sigma_a <= 0)"
        )
    if np.any(z < 1):
        raise ValueError(
            f"boundary.sigma_a_zeta = {float(z.min()):g} is outside the allowed range [1, inf) "
            "(magnification zeta = q/q_L, dimensionless)"
        )
    if np.any(np.diff(z) <= 0):
        i = int(np.argmax(np.diff(z) <= 0))
        raise ValueError(
            f"boundary.sigma_a_zeta [1] must be strictly increasing (sorted in zeta); "
            f"zeta[{i}] = {z[i]:g} >= zeta[{i + 1}] = {z[i + 1]:g}"
        )
    return z, s


class TableLaw:
    """A user table ``(zeta_i, sigma_a_i)``: PCHIP in diffusion time tau(zeta_i).

    A single value is a constant wall. Outside the table the end values are held (the range
    is checked against the scene's magnifications by the boundary).
    """

    def __init__(self, zeta: ArrayLike, sigma: ArrayLike) -> None:
        self.zeta, self.sigma = check_table(zeta, sigma)

    @property
    def is_constant(self) -> bool:
        return bool(np.all(self.sigma == self.sigma[0]))

    def in_tau(self, tau_of_zeta: Callable[[Array], Array]) -> Callable[[Array], Array]:
        """sigma_a as a function of diffusion time [Pa^2] -> [Pa] for a given clock."""
        return self.table_and_key(tau_of_zeta)[0]

    def table_and_key(
        self, tau_of_zeta: Callable[[Array], Array]
    ) -> tuple[Callable[[Array], Array], Hashable]:
        """:meth:`in_tau`'s function and its content key (the table and the clock's tau at
        its magnifications): equal keys, equal functions."""
        if self.is_constant:
            value = float(self.sigma[0])
            return lambda t: np.full(np.shape(t), value), ("table", value)
        from scipy.interpolate import PchipInterpolator

        t_nodes = np.asarray(tau_of_zeta(self.zeta), dtype=float)
        keep = np.concatenate(([True], np.diff(t_nodes) > 0))  # f = 0 bands: same tau
        table = _Pchip(
            PchipInterpolator(t_nodes[keep], self.sigma[keep], extrapolate=False),
            float(t_nodes[keep][0]),
            float(t_nodes[keep][-1]),
        )
        return table, ("table", digest(self.zeta, self.sigma, t_nodes))

    def check_range(self, zeta_max: float) -> None:
        """Raise ValueError unless the table covers ``[1, zeta_max]``."""
        lo, hi = float(self.zeta[0]), float(self.zeta[-1])
        if self.zeta.size > 1 and (lo > 1.0 + 1e-12 or hi < zeta_max * (1.0 - 1e-12)):
            raise ValueError(
                f"boundary.sigma_a_zeta covers zeta in [{lo:g}, {hi:g}] but the scene needs "
                f"[1, {zeta_max:g}]: the table must span every output magnification"
            )
