"""Complex modulus models E(omega) = E'(omega) + i E''(omega) [Pa] and their angular integrals.

Convention (physics.md §4.1): ``E''(omega) >= 0`` for ``omega > 0`` and ``E(-omega) = E(omega)*``.
Every model provides, for the sliding problem of Persson (2001), the two angular integrals over
the directions ``phi`` of a wavevector ``q`` relative to the sliding velocity, as functions of
``w = q v a_T`` [rad/s] (the largest angular frequency seen at that scale):

* ``mean_sq(w) = (1/2pi) int_0^2pi |E(w cos phi)|^2 dphi``            [Pa^2]
* ``loss(w)    =         int_0^2pi cos(phi) Im E(w cos phi) dphi``     [Pa]

Prony series (and the standard linear solid, a one-mode Prony series) have exact,
cancellation-free closed forms (derived below); tabulated master curves use Gauss-Legendre in
``phi`` on ``[0, pi/2]`` (the integrands are even about 0 and pi).

Prony closed forms. With ``E = E_g - sum_k dE_k / (1 + i w tau_k cos phi)`` and
``b_k = w tau_k``, ``u(b) = 1 - (1 + b^2)^(-1/2)``:

* ``loss = 2 pi sum_k dE_k u(b_k) / b_k``  (physics.md §4.4 per mode);
* ``mean_sq = E_r^2 + 2 sum_j dE_j c_j u(b_j)``, ``c_j = E_r + sum_k dE_k tau_k/(tau_j + tau_k)``.

The second follows from ``(2/pi) int_0^{pi/2} dphi / (1 + a cos^2 phi) = (1 + a)^(-1/2)`` and the
partial fractions ``(1 + b_j b_k c)/((1 + b_j^2 c)(1 + b_k^2 c)) = [b_j/(1 + b_j^2 c) +
b_k/(1 + b_k^2 c)] / (b_j + b_k)`` (``c = cos^2 phi``); every term is non-negative, so there
is no cancellation at small ``b`` (``u`` is evaluated as ``b^2 / (s (1 + s))``,
``s = sqrt(1 + b^2)``). For one mode it reduces to ``E_g^2 - (E_g^2 - E_r^2)(1 + b^2)^(-1/2)``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from xpersson.cache import dataclass_key

__all__ = [
    "ModulusModel",
    "Prony",
    "MasterCurve",
    "sls",
    "synthetic_tread",
    "u_of_b",
    "u_over_b",
]

Array = NDArray[np.float64]


def _ratio(b: Array) -> Array:
    """``u(b) / b = b / (s (1 + s))``, ``s = sqrt(1 + b^2)`` for ``b >= 0`` (``inf`` -> 0)."""
    huge = b > 1e150  # b^2 would overflow: there u/b = 1/b to double precision
    bb = np.where(huge, 1.0, b) if huge.any() else b
    s = bb * bb
    s += 1.0
    np.sqrt(s, out=s)
    den = s + 1.0
    den *= s
    out = np.divide(bb, den)
    if huge.any():
        out[huge] = 1.0 / b[huge]
    return out


#: Frequencies per pass of :meth:`Prony.parts`: its (frequencies x modes) temporaries then stay
#: in cache (a stacked block's grids hold ~1e5 nodes: one pass of 40 modes allocated ~40 MB
#: arrays afresh, page faults included, on every call). The passes share three work arrays
#: allocated once per call (fresh ~1.3 MB temporaries per pass were returned to the system
#: and page-faulted again on every pass: 3x the arithmetic's time in a fresh process).
_PARTS_CHUNK = 4096


def _small_ratio(b: Array, work: Array | None = None) -> Array:
    """:func:`_ratio` where every ``b <= 1e150`` (no overflow check: the same arithmetic);
    ``work`` (2, *b.shape): arrays to compute in (else fresh ones)."""
    s = b * b if work is None else np.multiply(b, b, out=work[0])
    s += 1.0
    np.sqrt(s, out=s)
    den = s + 1.0 if work is None else np.add(s, 1.0, out=work[1])
    den *= s
    np.divide(b, den, out=den)
    return den


def u_of_b(b: ArrayLike) -> Array:
    """``u(b) = 1 - (1 + b^2)^(-1/2)`` without cancellation (``b >= 0``, may be ``inf``)."""
    b = np.asarray(b, dtype=float)
    r = _ratio(np.atleast_1d(b))
    with np.errstate(invalid="ignore"):  # inf * 0 at b = inf, replaced by u = 1
        u = np.where(np.isinf(np.atleast_1d(b)), 1.0, np.atleast_1d(b) * r)
    return u.reshape(b.shape)


def u_over_b(b: ArrayLike) -> Array:
    """``u(b) / b = b / (s (1 + s))``, ``s = sqrt(1 + b^2)``; 0 at ``b = 0`` and ``b = inf``.

    This is the single-scale velocity factor of physics.md §4.4 (peak 0.30028 at b = 1.2720).
    """
    b = np.asarray(b, dtype=float)
    return _ratio(np.atleast_1d(b)).reshape(b.shape)


class ModulusModel:
    """A linear viscoelastic modulus at the reference temperature.

    Attributes
    ----------
    E_r : float
        Rubbery (omega -> 0) modulus [Pa].
    E_g : float
        Glassy (omega -> infinity) modulus [Pa].
    """

    E_r: float
    E_g: float

    def modulus(self, omega: ArrayLike) -> NDArray[np.complex128]:
        """Complex modulus ``E(omega)`` [Pa] at angular frequencies ``omega`` [rad/s] (any sign)."""
        raise NotImplementedError

    def angular(self, w: ArrayLike) -> tuple[Array, Array]:
        """``(mean_sq, loss)`` at ``w = q v a_T`` [rad/s] (see the module docstring)."""
        raise NotImplementedError

    def excess_mean_sq(self, w: ArrayLike) -> Array:
        """``mean_sq(w) - E_r^2`` [Pa^2] (without cancellation where the model allows)."""
        return self.angular(w)[0] - self.E_r**2

    def cache_key(self) -> bytes:
        """The model's content for :mod:`xpersson.cache`: a digest of its defining (init)
        fields, computed once (:func:`xpersson.cache.dataclass_key`)."""
        return dataclass_key(self)

    def breakpoints(self) -> Array:
        """Frequencies ``w`` [rad/s] where the angular integrals are not smooth (none)."""
        return np.empty(0)

    def parts(self, w: ArrayLike) -> tuple[Array, Array]:
        """``(mean_sq - E_r^2, loss)`` at ``w`` in one pass."""
        mean_sq, loss = self.angular(w)
        return mean_sq - self.E_r**2, loss


@dataclass(frozen=True)
class Prony(ModulusModel):
    """Generalized Maxwell (Prony) model ``E = E_r + sum dE_k i w tau_k / (1 + i w tau_k)``.

    Parameters
    ----------
    E_r : float
        Rubbery modulus [Pa], > 0.
    delta_E : array_like
        Mode strengths ``dE_k`` [Pa], >= 0 (all zero: a purely elastic solid, ``E'' = 0``).
    tau : array_like
        Relaxation times ``tau_k`` [s], > 0.
    """

    E_r: float
    delta_E: Array
    tau: Array
    E_g: float = field(init=False)
    _c: Array = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        dE = np.atleast_1d(np.asarray(self.delta_E, dtype=float))
        tau = np.atleast_1d(np.asarray(self.tau, dtype=float))
        if dE.ndim != 1 or dE.shape != tau.shape or dE.size == 0:
            raise ValueError("delta_E and tau must be 1-D arrays of the same non-zero length")
        if not (np.isfinite(self.E_r) and self.E_r > 0):
            raise ValueError(f"E_r must be a finite modulus > 0 Pa, got {self.E_r!r}")
        if not np.all(np.isfinite(dE) & (dE >= 0)):
            raise ValueError("delta_E: mode strengths must be finite and >= 0 Pa")
        if not np.all(np.isfinite(tau) & (tau > 0)):
            raise ValueError("tau: relaxation times must be finite and > 0 s")
        object.__setattr__(self, "delta_E", dE)
        object.__setattr__(self, "tau", tau)
        object.__setattr__(self, "E_r", float(self.E_r))
        object.__setattr__(self, "E_g", float(self.E_r + dE.sum()))
        ratio = tau[None, :] / (tau[:, None] + tau[None, :])  # tau_k / (tau_j + tau_k)
        object.__setattr__(self, "_c", self.E_r + ratio @ dE)

    def modulus(self, omega: ArrayLike) -> NDArray[np.complex128]:
        x = 1j * np.asarray(omega, dtype=float)[..., None] * self.tau
        return self.E_r + np.sum(self.delta_E * x / (1.0 + x), axis=-1)

    def angular(self, w: ArrayLike) -> tuple[Array, Array]:
        excess, loss = self.parts(w)
        return self.E_r**2 + excess, loss

    def excess_mean_sq(self, w: ArrayLike) -> Array:
        return self.parts(w)[0]

    def parts(self, w: ArrayLike) -> tuple[Array, Array]:
        w = np.asarray(w, dtype=float)
        flat = w.reshape(-1)
        n = flat.size
        if n == 0:
            return np.zeros(w.shape), np.zeros(w.shape)
        excess, loss = np.empty(n), np.empty(n)
        work = np.empty((3, min(_rows4(n), _PARTS_CHUNK), self.tau.size))  # every pass's
        for a in range(0, n, _PARTS_CHUNK):  # each frequency on its own: the same arithmetic
            part = flat[a : a + _PARTS_CHUNK]
            excess[a : a + part.size], loss[a : a + part.size] = self._parts(part, work)
        return excess.reshape(w.shape), loss.reshape(w.shape)

    def _parts(self, w: Array, work: Array) -> tuple[Array, Array]:
        """``parts`` of the 1-D ``w`` in one pass, computed in ``work`` (3, >= w.size rounded
        up to a multiple of 4, n_modes). The mode sums run over a multiple of 4 rows (zero
        padded): BLAS then takes every row through the same kernel, so each frequency's value
        does not depend on where it sits in the call (a stacked block equals its points)."""
        m = w.size
        m4 = _rows4(m)
        b = work[0, :m4]
        np.multiply(w[:, None], self.tau, out=b[:m])
        b[m:] = 0.0
        # every b = w tau_k <= max(w) max(tau) (rounding is monotone): one check on w only
        small = float(np.max(w)) * float(self.tau.max()) <= 1e150
        small = small and float(np.min(w)) > -np.inf  # (nan fails the first test)
        r = _small_ratio(b, work[1:, :m4]) if small else _ratio(b)  # u(b) / b
        loss = (2.0 * np.pi) * (r @ self.delta_E)[:m]
        with np.errstate(invalid="ignore"):
            r *= b  # u(b) (b = inf gives nan here: u = 1)
        if not small and np.isinf(b).any():
            r[np.isinf(b)] = 1.0
        excess = 2.0 * (r @ (self.delta_E * self._c))[:m]
        return excess, loss


def _rows4(n: int) -> int:
    """``n`` rounded up to a multiple of 4."""
    return -(-n // 4) * 4


def sls(E_r: float, E_g: float, relaxation_time: float) -> Prony:
    """Standard linear solid (Zener) ``E = (E_r + i w tau E_g) / (1 + i w tau)`` (§4.3).

    Parameters
    ----------
    E_r, E_g : float
        Rubbery and glassy moduli [Pa], ``0 < E_r <= E_g``.
    relaxation_time : float
        ``tau`` [s], > 0.
    """
    if not E_g >= E_r:
        raise ValueError(f"E_g must be >= E_r (got E_g = {E_g:g} Pa, E_r = {E_r:g} Pa)")
    return Prony(E_r, np.array([E_g - E_r]), np.array([relaxation_time]))


def synthetic_tread(
    E_r: float = 3e6,
    E_g: float = 3e9,
    n_modes: int = 40,
    tau_min: float = 1e-10,
    tau_max: float = 1e2,
    exponent: float = 0.5,
) -> Prony:
    """The synthetic tread-like Prony default of physics.md §4.3 (illustrative, not measured).

    ``n_modes`` log-spaced ``tau_k`` in ``[tau_min, tau_max]`` [s] with
    ``dE_k ∝ tau_k^(-exponent)`` and ``sum dE_k = E_g - E_r`` (gives ``E'' ∝ omega^exponent``
    in the transition). Defaults: ``E_r = 3 MPa``, ``E_g = 3 GPa``, 40 modes in
    ``[1e-10, 1e2] s``, exponent 1/2.
    """
    if not E_g >= E_r:
        raise ValueError(f"E_g must be >= E_r (got E_g = {E_g:g} Pa, E_r = {E_r:g} Pa)")
    tau = np.geomspace(tau_min, tau_max, int(n_modes))
    w = tau ** (-float(exponent))
    return Prony(E_r, (E_g - E_r) * w / w.sum(), tau)


@dataclass(frozen=True)
class MasterCurve(ModulusModel):
    """Tabulated master curve ``(omega, E', E'')`` with log-log interpolation.

    Outside the table ``E'`` is held constant and ``E''`` follows the terminal laws of any
    causal solid: ``E'' ∝ omega`` below the first and ``∝ 1/omega`` above the last frequency.
    ``E(-omega) = conj E(omega)``. Angular integrals by Gauss-Legendre in ``phi`` on
    ``[0, pi/2]`` (§4.6), split where ``w cos(phi)`` crosses a table frequency, with
    ``phi_nodes`` nodes per piece (the interpolant is a power law of ``cos(phi)`` on each
    piece: 6 nodes integrate it to ~1e-10).

    Parameters
    ----------
    omega : array_like
        Strictly increasing angular frequencies [rad/s], > 0.
    storage, loss_modulus : array_like
        ``E' > 0`` and ``E'' >= 0`` [Pa] (a zero ``E''`` column is allowed: elastic solid).
    phi_nodes : int
        Gauss-Legendre nodes in ``phi`` per piece between table frequencies.
    """

    omega: Array
    storage: Array
    loss_modulus: Array
    phi_nodes: int = 6
    E_r: float = field(init=False)
    E_g: float = field(init=False)

    def __post_init__(self) -> None:
        w = np.asarray(self.omega, dtype=float)
        e1 = np.asarray(self.storage, dtype=float)
        e2 = np.asarray(self.loss_modulus, dtype=float)
        if not (w.ndim == 1 and w.shape == e1.shape == e2.shape and w.size >= 2):
            raise ValueError("a master curve needs at least two rows of (omega, E', E'')")
        if not (np.all(w > 0) and np.all(np.diff(w) > 0)):
            raise ValueError("master curve frequencies must be > 0 and strictly increasing")
        if not (np.all(e1 > 0) and np.all(e2 >= 0) and np.all(np.isfinite(e1 + e2))):
            raise ValueError("master curve: E' must be > 0 Pa and E'' >= 0 Pa")
        for name, val in (("omega", w), ("storage", e1), ("loss_modulus", e2)):
            object.__setattr__(self, name, val)
        object.__setattr__(self, "E_r", float(e1[0]))
        object.__setattr__(self, "E_g", float(e1[-1]))

    def _parts(self, omega: Array) -> tuple[Array, Array]:
        a = np.abs(omega)
        la = np.log(np.clip(a, self.omega[0], self.omega[-1]))
        lw = np.log(self.omega)
        e1 = np.exp(np.interp(la, lw, np.log(self.storage)))
        pos = self.loss_modulus > 0
        if np.all(pos):
            e2 = np.exp(np.interp(la, lw, np.log(self.loss_modulus)))
        else:  # zeros in the table: interpolate linearly in log omega (keeps exact zeros)
            e2 = np.interp(la, lw, self.loss_modulus)
        with np.errstate(divide="ignore", invalid="ignore"):
            low = a < self.omega[0]
            high = a > self.omega[-1]
            e2 = np.where(low, self.loss_modulus[0] * a / self.omega[0], e2)
            e2 = np.where(high, self.loss_modulus[-1] * self.omega[-1] / np.where(high, a, 1), e2)
        return e1, np.sign(omega) * e2

    def modulus(self, omega: ArrayLike) -> NDArray[np.complex128]:
        e1, e2 = self._parts(np.asarray(omega, dtype=float))
        return e1 + 1j * e2

    def angular(self, w: ArrayLike) -> tuple[Array, Array]:
        w = np.asarray(w, dtype=float)
        flat = w.ravel()
        sq, loss = np.empty(flat.shape), np.empty(flat.shape)
        block = max(1, 200_000 // ((self.omega.size + 1) * int(self.phi_nodes)))
        for i in range(0, flat.size, block):
            sq[i : i + block], loss[i : i + block] = self._angular_block(flat[i : i + block])
        return sq.reshape(w.shape), loss.reshape(w.shape)

    def breakpoints(self) -> Array:
        """The table frequencies: the angular integrals have ``sqrt``-type kinks there."""
        return self.omega.copy()

    def _angular_block(self, W: Array) -> tuple[Array, Array]:
        # phi split where w cos(phi) crosses a table frequency: the interpolant is a power law
        # of cos(phi) on each piece, so a few Gauss-Legendre nodes per piece are exact to ~1e-10
        x, wt = np.polynomial.legendre.leggauss(int(self.phi_nodes))
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.clip(self.omega[None, :] / np.abs(W)[:, None], 0.0, 1.0)
        t = np.where(np.isfinite(t), t, 0.0)
        cuts = np.sort(
            np.concatenate(
                [np.arccos(t), np.zeros((W.size, 1)), np.full((W.size, 1), 0.5 * np.pi)], axis=1
            ),
            axis=1,
        )
        mid, half = 0.5 * (cuts[:, 1:] + cuts[:, :-1]), 0.5 * (cuts[:, 1:] - cuts[:, :-1])
        phi = mid[..., None] + half[..., None] * x
        cos = np.cos(phi)
        with np.errstate(invalid="ignore"):
            arg = np.where(W[:, None, None] == 0, 0.0, W[:, None, None] * cos)
        e1, e2 = self._parts(arg)
        ww = half[..., None] * wt
        mean_sq = (2.0 / np.pi) * np.sum(ww * (e1 * e1 + e2 * e2), axis=(1, 2))
        loss = 4.0 * np.sum(ww * cos * e2, axis=(1, 2))
        return mean_sq, loss
