"""Independent reference of Persson's viscoelastic friction (physics.md §4.2, §4.4, §8.2).

Written from the formulas, sharing no code with ``xpersson`` or ``xpersson_viscoelastic``:

    G(q)    = (pi/4) / ((1 - nu^2) p0)^2 int_{q_L}^{q} q'^3 C(q') M(q') dq'
    P(q)    = erf(1 / (2 sqrt(G(q))))                           (Persson 2001)
    mu_visc = 1 / (2 (1 - nu^2) p0) int_{q_L}^{q_1} q^3 C(q) P(q) S(q) Lambda(q) dq

(``S = 1``, or ``S = gamma + (1 - gamma) P^2``)

with, for the standard linear solid ``E(w) = (E_r + i w tau E_g) / (1 + i w tau)`` and
``b = q v a_T tau`` (physics.md §4.4),

    M(q)      = (1/2pi) int_0^2pi |E(q v a_T cos phi)|^2 dphi
              = E_g^2 - (E_g^2 - E_r^2) / sqrt(1 + b^2)
    Lambda(q) = int_0^2pi cos(phi) Im E(q v a_T cos phi) dphi
              = 2 pi (E_g - E_r) (1 - 1 / sqrt(1 + b^2)) / b

and the self-affine spectrum with roll-off of §8.2 (``C_r`` from the rms slope by its closed-form
second moment). Both q-integrals are evaluated with ``scipy.integrate.quad`` (adaptive
Gauss-Kronrod) in the offset ``d = q - q_L`` (``q_L (1 + 1e-15)`` is not representable in
``q``) on explicit breakpoints: a geometric ladder in ``d`` (two per decade, from where
``G < 1e-6`` up to ``q_1``), the roll-off ``q_r``, the loss peak and the point where
``G = 1``. ``G`` at an outer node is the cumulative sum of converged quad integrals over the
ladder plus one quad from the nearest ladder point. :func:`sls_angular_quad` checks the two
angular forms against quad over ``phi`` directly.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike as ArrayLikeF
from scipy.integrate import quad
from scipy.special import erf

__all__ = [
    "RefSpectrum",
    "SLS",
    "PronyRef",
    "AngularTable",
    "prony_angular_quad",
    "arrhenius_shift",
    "wlf_shift",
    "mu_reference",
    "sls_angular_quad",
]


@dataclass(frozen=True)
class RefSpectrum:
    """Self-affine PSD with roll-off, Persson convention: ``C = C_r`` on ``[q_L, q_r)``,
    ``C_r (q/q_r)^(-2(1+H))`` on ``[q_r, q_1]`` [m^4]; built from the rms slope [1]."""

    H: float
    q_L: float
    q_r: float
    q_1: float
    rms_slope: float

    @property
    def C_r(self) -> float:
        """Plateau value [m^4] from ``<|grad h|^2> = 2 pi int q^3 C dq`` (§8.2)."""
        H, qL, qr, q1 = self.H, self.q_L, self.q_r, self.q_1
        tail = (
            qr**4 * math.log(q1 / qr)
            if H == 1.0
            else qr**4 * ((q1 / qr) ** (2 - 2 * H) - 1) / (2 - 2 * H)
        )
        m3 = (qr**4 - qL**4) / 4.0 + tail
        return self.rms_slope**2 / (2.0 * math.pi * m3)

    def C(self, q: float) -> float:
        """``C(q)`` [m^4]."""
        if q < self.q_r:
            return self.C_r
        return self.C_r * (q / self.q_r) ** (-2.0 * (1.0 + self.H))


@dataclass(frozen=True)
class SLS:
    """Standard linear solid [Pa, Pa, s]."""

    E_r: float
    E_g: float
    tau: float

    def angular(self, w: float) -> tuple[float, float]:
        """``(M, Lambda)`` [Pa^2, Pa] at ``w = q v a_T`` [rad/s] (closed forms of §4.4)."""
        b = w * self.tau
        one_minus = -math.expm1(-0.5 * math.log1p(b * b))  # 1 - (1 + b^2)^(-1/2)
        M = self.E_r**2 + (self.E_g**2 - self.E_r**2) * one_minus
        if b == 0.0:
            return M, 0.0
        if b < 1e-4:  # one_minus / b = b/2 - 3 b^3 / 8 ...
            ratio = 0.5 * b - 0.375 * b**3
        else:
            ratio = one_minus / b
        return M, 2.0 * math.pi * (self.E_g - self.E_r) * ratio

    def E(self, w: float) -> complex:
        """Complex modulus [Pa] at angular frequency ``w`` [rad/s] (``Im E >= 0`` for w > 0)."""
        x = 1j * w * self.tau
        return (self.E_r + x * self.E_g) / (1.0 + x)


@dataclass(frozen=True)
class PronyRef:
    """Generalised Maxwell solid ``E(w) = E_r + sum_k dE_k i w tau_k / (1 + i w tau_k)``
    [Pa, Pa, s] (physics.md §4.3), angular integrals by quadrature over ``phi``.

    ``M`` and ``Lambda`` are composite 24-point Gauss-Legendre sums over ``phi`` in ``[0, pi/4]``
    and over ``c = cos(phi)`` in ``[0, 1/sqrt 2]`` (4-fold symmetry), split at
    ``c w tau_k = 10^(j/2)``, ``j >= -4``, for every mode (the layers of width ``1/(w tau_k)``
    at ``phi = pi/2``, and the ``1/(c w tau_k)`` tails above): no closed form of the plugin is
    used.
    """

    E_r: float
    dE: tuple[float, ...]
    taus: tuple[float, ...]

    @property
    def E_g(self) -> float:
        """Glassy modulus [Pa]."""
        return self.E_r + sum(self.dE)

    def E(self, w: ArrayLikeF) -> np.ndarray:
        """Complex modulus [Pa] at ``w`` [rad/s] (array)."""
        w = np.asarray(w, dtype=float)[..., None]
        x = 1j * w * np.asarray(self.taus)
        return self.E_r + np.sum(np.asarray(self.dE) * x / (1.0 + x), axis=-1)

    def angular(self, w: float) -> tuple[float, float]:
        """``(M, Lambda)`` [Pa^2, Pa] at ``w = q v a_T`` [rad/s]."""
        x, wt = np.polynomial.legendre.leggauss(24)

        def rule(cuts: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            cuts = np.unique(cuts)
            mid, half = 0.5 * (cuts[1:] + cuts[:-1]), 0.5 * (cuts[1:] - cuts[:-1])
            return (mid[:, None] + half[:, None] * x).ravel(), (half[:, None] * wt).ravel()

        # phi in [0, pi/4]; then c = cos(phi) in [0, 1/sqrt 2] (dphi = dc / sqrt(1 - c^2)),
        # where the layers c ~ 1/(w tau_k) are resolved without the round-off of pi/2 - phi
        c_cut = [0.0, math.sqrt(0.5)] + [  # half decades from 1e-2 / (w tau_k) up
            c / (w * t) for t in self.taus for c in 10.0 ** (np.arange(-4, 60) / 2.0)
        ]
        c_n, c_w = rule(np.clip(c_cut, 0.0, math.sqrt(0.5)))
        p_n, p_w = rule(np.linspace(0.0, math.pi / 4, 4))
        cos = np.concatenate([np.cos(p_n), c_n])
        wts = np.concatenate([p_w, c_w / np.sqrt(1.0 - c_n**2)])
        E = self.E(w * cos)
        M = float(np.sum(wts * np.abs(E) ** 2)) * 2.0 / math.pi
        return M, float(np.sum(wts * cos * E.imag)) * 4.0


class AngularTable:
    """``(M, Lambda)`` of ``model`` tabulated for ``w`` in ``[w_lo, w_hi]`` [rad/s] (200 per
    decade) and interpolated by cubic splines of ``ln M``, ``ln Lambda`` in ``ln w`` (both smooth:
    ~1e-10 relative); makes the nested q-quadrature of a :class:`PronyRef` affordable."""

    def __init__(self, model: PronyRef, w_lo: float, w_hi: float) -> None:
        from scipy.interpolate import CubicSpline

        n = max(8, int(200 * math.log10(w_hi / w_lo)) + 1)
        u = np.linspace(math.log(w_lo) - 0.05, math.log(w_hi) + 0.05, n)
        vals = np.array([model.angular(math.exp(x)) for x in u])
        self._M = CubicSpline(u, np.log(vals[:, 0]))
        self._L = CubicSpline(u, np.log(vals[:, 1]))
        self.E_g, self.taus = model.E_g, model.taus

    def angular(self, w: float) -> tuple[float, float]:
        """``(M, Lambda)`` [Pa^2, Pa] at ``w`` [rad/s]."""
        u = math.log(w)
        return math.exp(float(self._M(u))), math.exp(float(self._L(u)))


def prony_angular_quad(model: PronyRef, w: float) -> tuple[float, float]:
    """``(M, Lambda)`` of a :class:`PronyRef` by adaptive quad (checks its rule): over ``phi`` on
    ``[0, pi/4]`` and over ``c = cos(phi)`` on ``[0, 1/sqrt 2]`` with breakpoints at the layers."""
    top = math.sqrt(0.5)
    pts = [c / (w * t) for t in model.taus for c in (0.1, 1.0, 10.0) if c / (w * t) < top] or None
    kw = {"epsabs": 0, "epsrel": 1e-13, "limit": 400}

    def both(f):  # f(cos) integrated over phi in [0, pi/2]
        a = quad(lambda p: f(math.cos(p)), 0, math.pi / 4, **kw)[0]
        b = quad(lambda c: f(c) / math.sqrt(1.0 - c * c), 0, top, points=pts, **kw)[0]
        return a + b

    M = both(lambda c: abs(complex(model.E(w * c))) ** 2)
    L = both(lambda c: c * complex(model.E(w * c)).imag)
    return M * 2.0 / math.pi, L * 4.0


def sls_angular_quad(model: SLS, w: float) -> tuple[float, float]:
    """``(M, Lambda)`` by quad over ``phi`` on ``[0, pi/2]`` (4-fold symmetry of §4.2)."""
    b = w * model.tau  # breakpoints around w cos(phi) tau = 1 (a layer of width 1/b at pi/2)
    pts = [math.acos(c / b) for c in (0.01, 0.1, 1.0, 10.0, 100.0) if c < b] or None
    M = (
        quad(
            lambda p: abs(model.E(w * math.cos(p))) ** 2,
            0,
            math.pi / 2,
            points=pts,
            epsabs=0,
            epsrel=1e-13,
            limit=400,
        )[0]
        * 2.0
        / math.pi
    )
    L = (
        quad(
            lambda p: math.cos(p) * model.E(w * math.cos(p)).imag,
            0,
            math.pi / 2,
            points=pts,
            epsabs=0,
            epsrel=1e-13,
            limit=400,
        )[0]
        * 4.0
    )
    return M, L


def wlf_shift(T: float, C1: float, C2: float, T_ref: float) -> float:
    """WLF ``a_T = 10^(-C1 (T - T_ref) / (C2 + T - T_ref))`` [1]."""
    return 10.0 ** (-C1 * (T - T_ref) / (C2 + T - T_ref))


def arrhenius_shift(T: float, E_a: float, T_ref: float) -> float:
    """Arrhenius ``a_T = exp((E_a / R)(1/T - 1/T_ref))`` [1], ``R = 8.314462618 J/(mol K)``."""
    return math.exp(E_a / 8.314462618 * (1.0 / T - 1.0 / T_ref))


def _quad(f, a: float, b: float, eps: float) -> float:
    return quad(f, a, b, epsabs=0.0, epsrel=eps, limit=500)[0]


def _ladder(
    psd: RefSpectrum, model: Any, s: float, bound: float, dG: Any, eps: float, zeta: Any
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Breakpoints in ``d = q - q_L`` [1/m], ``G`` there [1] and the offsets of ``zeta``.

    A geometric ladder (two per decade) from where ``G < 1e-6`` (``bound``: a bound of
    ``dG/dq / (q^3 C M)`` with ``M <= E_g^2``) to ``q_1 - q_L``, the roll-off, the loss peaks
    ``q s tau_k = 1`` (``s = v a_T``), the magnifications ``zeta`` and the point where ``G = 1``.
    """
    qL, q1, cG8 = psd.q_L, psd.q_1, bound
    slope = cG8 * qL**3 * psd.C(qL) * model.E_g**2  # >= dG on [qL, 2 qL]
    d0 = min(1e-2 * qL, 1e-6 / slope)
    top = q1 - qL
    ladder = np.geomspace(d0, top, max(2, int(2 * math.log10(top / d0)) + 1))
    extra = [psd.q_r - qL] if qL < psd.q_r < q1 else []
    for tau in getattr(model, "taus", None) or [model.tau]:  # the loss peaks b ~ 1
        qb = 1.0 / (s * tau) if s > 0 else 0.0
        if qL < qb < q1:
            extra.append(qb - qL)
    z_off = np.zeros(0) if zeta is None else (np.asarray(zeta, dtype=float) - 1.0) * qL
    z_off = np.minimum(z_off, top)
    ladder = np.unique(np.concatenate([[0.0], ladder, extra, z_off]))
    ladder = ladder[ladder <= top]
    ladder[-1] = top
    Gk = np.concatenate(
        [
            [0.0],
            np.cumsum([_quad(dG, a, b, eps) for a, b in zip(ladder[:-1], ladder[1:], strict=True)]),
        ]
    )
    if Gk[-1] > 1.0 and Gk[1] < 1.0:  # the point where G = 1 (P drops there)
        k = int(np.searchsorted(Gk, 1.0))
        lo, hi = ladder[k - 1], ladder[k]
        while hi - lo > 1e-6 * (hi - ladder[k - 1]):
            mid = 0.5 * (lo + hi)
            if Gk[k - 1] + _quad(dG, ladder[k - 1], mid, eps) < 1.0:
                lo = mid
            else:
                hi = mid
        ladder = np.insert(ladder, k, 0.5 * (lo + hi))
        Gk = np.insert(Gk, k, Gk[k - 1] + _quad(dG, ladder[k - 1], ladder[k], eps))
    return ladder, Gk, z_off


def mu_reference(
    psd: RefSpectrum,
    model: SLS,
    nu: float,
    p0: float,
    v: float,
    aT: float = 1.0,
    eps: float = 1e-11,
    gamma: float | None = None,
    zeta: np.ndarray | None = None,
) -> dict[str, Any]:
    """``mu_visc`` [1] and ``P(q_1)`` [1] of Persson 2001 by nested adaptive quad.

    With ``zeta`` [1] (magnifications in ``[1, q_1/q_L]``) also the profiles there (arrays):
    ``G`` [1], ``area_fraction`` [1], ``loss_integral``
    ``L = int_{q_L}^{zeta q_L} q^3 C Lambda dq / (1 - nu^2)`` [Pa], ``mu_visc_cumulative`` [1]
    (the friction from the scales up to ``zeta``), ``effective_modulus`` ``sqrt(M)/(1 - nu^2)``
    [Pa] and ``loss_angular_integral`` ``Lambda/(1 - nu^2)`` [Pa].

    Parameters
    ----------
    psd, model
        Spectrum and SLS modulus.
    nu : float
        Poisson ratio [1].
    p0 : float
        Nominal pressure [Pa].
    v : float
        Sliding speed [m/s].
    aT : float
        Shift factor [1].
    eps : float
        Relative tolerance of every quad.
    gamma : float, optional
        With a value, ``P`` in the friction integral is multiplied by
        ``S = gamma + (1 - gamma) P^2``.
    """
    fnu = 1.0 - nu * nu
    s = v * aT
    cG = (math.pi / 4.0) / (fnu * p0) ** 2
    qL = psd.q_L

    # all integrals in the offset d = q - q_L (q_L (1 + 1e-15) is not representable in q)
    def dG(d: float) -> float:
        q = qL + d
        return cG * q**3 * psd.C(q) * model.angular(q * s)[0]

    ladder, Gk, z_off = _ladder(psd, model, s, cG * 8.0, dG, eps, zeta)

    def G_at(d: float, j: int) -> float:
        return Gk[j] + _quad(dG, ladder[j], d, eps) if d > ladder[j] else Gk[j]

    def P(G: float) -> float:
        return 1.0 if G <= 0.0 else float(erf(0.5 / math.sqrt(G)))

    mu_k, L_k = [0.0], [0.0]
    for j in range(ladder.size - 1):

        def dmu(d: float, j: int = j) -> float:
            q = qL + d
            a = P(G_at(d, j))
            S = 1.0 if gamma is None else gamma + (1.0 - gamma) * a * a
            return q**3 * psd.C(q) * a * S * model.angular(q * s)[1]

        mu_k.append(_quad(dmu, ladder[j], ladder[j + 1], eps))
        if zeta is not None:

            def dL(d: float) -> float:
                q = qL + d
                return q**3 * psd.C(q) * model.angular(q * s)[1]

            L_k.append(_quad(dL, ladder[j], ladder[j + 1], eps))
    mu_run = np.cumsum(mu_k) / (2.0 * fnu * p0)
    out: dict[str, Any] = {"mu_visc": float(mu_run[-1]), "area_fraction": P(Gk[-1])}
    if zeta is not None:
        i = np.searchsorted(ladder, z_off)
        ang = np.array([model.angular((qL + d) * s) for d in z_off]).reshape(-1, 2)
        out["profiles"] = {
            "G": Gk[i],
            "area_fraction": np.array([P(g) for g in Gk[i]]),
            "loss_integral": np.cumsum(L_k)[i] / fnu,
            "mu_visc_cumulative": mu_run[i],
            "effective_modulus": np.sqrt(ang[:, 0]) / fnu,
            "loss_angular_integral": ang[:, 1] / fnu,
        }
    return out
