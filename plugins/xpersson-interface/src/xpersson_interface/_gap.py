"""Mean interfacial separation, its low-load asymptote and the contact stiffness.

Implements physics.md §5.2 and §5.4 (Persson 2007 for ``gamma = 1``; the Yang-Persson 2008
correction factor ``S = gamma + (1 - gamma) P^2`` with Persson's *uncorrected* area
``P(q, p) = erf(w(q) p / E*)`` otherwise):

.. math::

    \\bar u(p) = \\sqrt{\\pi} \\int_{q_a}^{q_1} dq\\, q^2 C(q) w(q)\\, J(w(q) p / E^*),\\quad
    J(x_0) = \\int_{x_0}^\\infty \\frac{dx}{x} [\\gamma + 3(1-\\gamma)\\,\\mathrm{erf}^2 x] e^{-x^2}
           = \\frac{\\gamma}{2} E_1(x_0^2) + 3(1-\\gamma) K(x_0).

``K`` is tabulated once (cubic Hermite interpolation with its exact derivative, error < 1e-11).
The contact stiffness ``K_n = -dp/du`` uses the analytic ``du/dp`` of the same integrand. All
functions are vectorised over the loads (pure numpy/scipy, SI units).
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.interpolate import CubicHermiteSpline
from scipy.special import erf, exp1

from ._quad import QRule, gauss_legendre, q_rule

__all__ = [
    "EULER_GAMMA",
    "C3",
    "J_inner",
    "dJ_inner",
    "mean_gap",
    "dmean_gap_dp",
    "contact_stiffness",
    "gap_asymptote",
]

EULER_GAMMA = 0.5772156649015329
_X_MAX = 9.0  # J(x0) < e^-81 beyond: treated as 0


def _k_integrand(x: NDArray[np.float64]) -> NDArray[np.float64]:
    """``erf(x)^2 exp(-x^2) / x`` with its limit 0 at x = 0."""
    xs = np.where(x > 0, x, 1.0)
    return np.where(x > 0, erf(xs) ** 2 * np.exp(-xs * xs) / xs, 0.0)


@lru_cache(maxsize=1)
def _k_table() -> tuple[CubicHermiteSpline, float]:
    """Spline of ``F(x) = int_0^x erf^2 e^{-t^2} dt / t`` and ``c3 = F(inf)``."""
    x = np.linspace(0.0, _X_MAX, 3601)
    t, wt = gauss_legendre(12)
    a, b = x[:-1, None], x[1:, None]
    seg = np.sum((b - a) * wt * _k_integrand(a + (b - a) * t), axis=1)
    F = np.concatenate(([0.0], np.cumsum(seg)))
    return CubicHermiteSpline(x, F, _k_integrand(x)), float(F[-1])


C3: float = _k_table()[1]
"""``c3 = int_0^inf erf(x)^2 exp(-x^2) dx / x = 0.4071249...`` (physics.md §5.2)."""


def J_inner(x0: ArrayLike, gamma: float = 1.0) -> NDArray[np.float64]:
    """Inner integral ``J(x0) = int_x0^inf [gamma + 3(1-gamma) erf^2 x] e^{-x^2} dx/x``.

    Parameters
    ----------
    x0 : array_like
        Lower limit ``w p / E*`` [1], ``> 0``.
    gamma : float
        Correction-factor parameter [1] (1: Persson 2007).

    Returns
    -------
    ndarray
        ``J`` [1]; 0 for ``x0 > 9``.
    """
    x0 = np.asarray(x0, dtype=float)
    xc = np.minimum(x0, _X_MAX)
    out = 0.5 * gamma * exp1(xc * xc)
    if gamma != 1.0:
        spl, c3 = _k_table()
        out = out + 3.0 * (1.0 - gamma) * (c3 - spl(xc))
    return np.where(x0 >= _X_MAX, 0.0, out)


def dJ_inner(x0: ArrayLike, gamma: float = 1.0) -> NDArray[np.float64]:
    """Derivative ``dJ/dx0 = -[gamma + 3(1-gamma) erf^2 x0] exp(-x0^2) / x0`` [1]."""
    x0 = np.asarray(x0, dtype=float)
    return -(gamma + 3.0 * (1.0 - gamma) * erf(x0) ** 2) * np.exp(-x0 * x0) / x0


def _rule(psd: object, rule: QRule | None) -> QRule:
    return q_rule(psd) if rule is None else rule


def mean_gap(
    psd: object,
    E_star: float,
    p: ArrayLike,
    gamma: float = 1.0,
    *,
    rule: QRule | None = None,
) -> NDArray[np.float64]:
    """Mean interfacial separation ``u(p)`` [m] (physics.md §5.2).

    Parameters
    ----------
    psd : PowerSpectrum
        Roughness spectrum (Persson convention, m^4).
    E_star : float
        Contact modulus [Pa].
    p : array_like
        Nominal pressures [Pa], ``> 0``.
    gamma : float
        Correction-factor parameter [1]; ``1`` is Persson 2007.
    rule : QRule, optional
        Precomputed quadrature rule (e.g. for a lower cut-off ``zeta q_L``).

    Returns
    -------
    ndarray
        ``u`` [m], same shape as ``p``.
    """
    r = _rule(psd, rule)
    p = np.asarray(p, dtype=float)
    if r.q.size == 0:
        return np.zeros_like(p)
    kern = r.weights * r.q**2 * r.C * r.w  # m
    x0 = r.w[None, :] * (p.reshape(-1, 1) / E_star)
    out = math.sqrt(math.pi) * (J_inner(x0, gamma) @ kern)
    return out.reshape(p.shape)


def dmean_gap_dp(
    psd: object,
    E_star: float,
    p: ArrayLike,
    gamma: float = 1.0,
    *,
    rule: QRule | None = None,
) -> NDArray[np.float64]:
    """Analytic derivative ``du/dp`` [m/Pa] of :func:`mean_gap` (negative).

    ``du/dp = -(sqrt(pi)/p) int q^2 C w [gamma + 3(1-gamma) P^2] exp(-(w p/E*)^2) dq``.
    """
    r = _rule(psd, rule)
    p = np.asarray(p, dtype=float)
    kern = r.weights * r.q**2 * r.C * r.w
    x0 = r.w[None, :] * (p.reshape(-1, 1) / E_star)
    with np.errstate(under="ignore"):
        d = (dJ_inner(x0, gamma) * x0) @ kern  # x0 dJ/dx0 = p dJ/dp
    return (math.sqrt(math.pi) * d / p.reshape(-1)).reshape(p.shape)


def contact_stiffness(
    psd: object,
    E_star: float,
    p: ArrayLike,
    gamma: float = 1.0,
    *,
    rule: QRule | None = None,
) -> NDArray[np.float64]:
    """Normal contact stiffness per nominal area ``K = -dp/du`` [Pa/m] (physics.md §5.4)."""
    with np.errstate(divide="ignore"):
        return -1.0 / dmean_gap_dp(psd, E_star, p, gamma, rule=rule)


def gap_asymptote(
    psd: object, E_star: float, gamma: float = 1.0, *, rule: QRule | None = None
) -> tuple[float, float]:
    """Low-load asymptote ``u ~ -u0 ln(p / (beta E*))`` (physics.md §5.2).

    Returns
    -------
    u0 : float
        ``sqrt(pi) gamma int q^2 C w dq`` [m].
    beta : float
        ``exp(-<ln w> - gamma_E/2 + 3(1-gamma) c3/gamma)`` [1].
    """
    r = _rule(psd, rule)
    kern = r.weights * r.q**2 * r.C * r.w
    W = float(np.sum(kern))
    L = float(np.sum(kern * np.log(r.w)))
    u0 = math.sqrt(math.pi) * gamma * W
    ln_beta = -L / W - 0.5 * EULER_GAMMA + 3.0 * (1.0 - gamma) * C3 / gamma
    return u0, math.exp(ln_beta)
