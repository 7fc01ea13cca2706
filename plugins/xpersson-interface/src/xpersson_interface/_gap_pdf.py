"""Distribution of interfacial separations P(u) (physics.md §5.5a).

Closed form of Almqvist, Campana, Prodanov & Persson (2011):

.. math::

    P(u) = \\frac{A(\\zeta_1)}{A_0}\\delta(u) + \\frac{1}{A_0}\\int_1^{\\zeta_1} d\\zeta
    \\,[-A'(\\zeta)]
    \\frac{e^{-(u-u_1)^2/2h^2} + e^{-(u+u_1)^2/2h^2}}{\\sqrt{2\\pi h^2}},

``h^2(zeta) = 2 pi int_{zeta q_L}^{q_1} q C dq`` (roughness finer than the current scale),
``u_1 = d(A u)/dA`` the mean separation of the area that detaches at ``zeta``, ``u(zeta)`` the
mean separation of §5.2 with lower cut-off ``zeta q_L`` at pressure ``p0 A0/A(zeta)``.

Discretisation (:func:`detachment`): the magnification axis is cut into bins; bin ``k`` carries
the exact detached area ``A_{k-1} - A_k`` and ``u_1 = (A_{k-1} u_{k-1} - A_k u_k) / (A_{k-1} -
A_k)`` (the finite-volume form of ``d(Au)/dA``), so the total mass ``1 - A(zeta_1)`` and the
mean-gap identity ``sum (-dA) u_1 = u(p0)`` hold to rounding; ``h`` is taken at the bin's
midpoint (second order). Bins whose detached area underflows get ``u_1 = 0``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.special import erf

from ._closures import AreaLaw
from ._gap import mean_gap
from ._quad import q_rule

__all__ = ["Detachment", "detachment", "zeta_grid", "gap_pdf", "gap_cdf", "gap_mean"]

_SQRT2 = math.sqrt(2.0)


@dataclass(frozen=True)
class Detachment:
    """Detached-area bins along the magnification axis (all per load, SI units).

    Attributes
    ----------
    p0 : ndarray, (n_load,)
        Nominal pressures [Pa].
    zeta : ndarray, (n_edge,)
        Bin edges in magnification [1], from 1 to ``zeta_1``.
    area : ndarray, (n_load, n_edge)
        ``A(zeta)/A0`` at the edges [1].
    ubar : ndarray, (n_load, n_edge)
        Mean separation of the apparent contact at the edges [m].
    weight : ndarray, (n_load, n_bin)
        Detached area per bin ``A_{k-1} - A_k`` [1].
    u1 : ndarray, (n_load, n_bin)
        Mean separation of the detaching area [m].
    h : ndarray, (n_bin,)
        rms height of the roughness finer than the bin's midpoint [m].
    h_rms : float
        Total rms height [m].
    dropped_moment : ndarray, (n_load,)
        ``sum Delta(A u)`` [m] of bins whose detached area underflows (``A = 1`` to double
        precision near ``zeta = 1``): zero mass at unbounded ``u_1`` with a finite first moment,
        left out of the distribution (``sum weight u1 + dropped_moment = u(p0)``).
    """

    p0: NDArray[np.float64]
    zeta: NDArray[np.float64]
    area: NDArray[np.float64]
    ubar: NDArray[np.float64]
    weight: NDArray[np.float64]
    u1: NDArray[np.float64]
    h: NDArray[np.float64]
    h_rms: float
    dropped_moment: NDArray[np.float64]

    @property
    def contact(self) -> NDArray[np.float64]:
        """Contact-area fraction at the finest scale ``A(zeta_1)/A0`` [1], shape (n_load,)."""
        return self.area[:, -1]

    @property
    def mean_gap(self) -> NDArray[np.float64]:
        """Persson's mean separation ``u(p0)`` [m] (edge ``zeta = 1``), shape (n_load,)."""
        return self.ubar[:, 0]


def zeta_grid(zeta_1: float, n: int = 400, *, tail: int = 60) -> NDArray[np.float64]:
    """Magnification edges ``1 + logspace(-9, log10(zeta_1 - 1), n)`` refined near ``zeta_1``.

    ``tail`` extra edges at ``zeta_1 (1 - logspace)`` resolve the last bins, where the finer
    roughness ``h`` vanishes like ``sqrt(zeta_1 - zeta)``.
    """
    z = 1.0 + np.geomspace(1e-9, zeta_1 - 1.0, n)
    if tail:
        z = np.concatenate((z, zeta_1 * (1.0 - np.geomspace(1e-7, 0.05, tail))))
    return np.unique(np.concatenate(([1.0], np.clip(z, 1.0, zeta_1))))


def _h2(psd: object, q: NDArray[np.float64]) -> NDArray[np.float64]:
    q_1 = float(psd.q_1)
    return np.array([2.0 * math.pi * float(psd.moment(1.0, qq, q_1)) for qq in q])


def detachment(
    psd: object,
    E_star: float,
    p0: ArrayLike,
    gamma: float = 1.0,
    law: AreaLaw | None = None,
    *,
    zeta: ArrayLike | None = None,
    n_zeta: int = 400,
) -> Detachment:
    """Compute the detached-area bins of the gap distribution.

    Parameters
    ----------
    psd : PowerSpectrum
        Roughness spectrum (Persson convention, m^4).
    E_star : float
        Contact modulus [Pa].
    p0 : array_like
        Nominal pressures [Pa].
    gamma : float
        Correction-factor parameter of the mean separation (§5.2) [1].
    law : AreaLaw, optional
        Contact-area law (default Persson 2001).
    zeta : array_like, optional
        Bin edges (default :func:`zeta_grid` with ``n_zeta`` points).
    n_zeta : int
        Number of log-spaced edges when ``zeta`` is not given.

    Returns
    -------
    Detachment
    """
    law = AreaLaw() if law is None else law
    p0 = np.atleast_1d(np.asarray(p0, dtype=float))
    q_L, q_1 = float(psd.q_L), float(psd.q_1)
    z = zeta_grid(q_1 / q_L, n_zeta) if zeta is None else np.asarray(zeta, dtype=float)
    I3 = np.asarray(psd.I3(z * q_L), dtype=float)
    G = 0.25 * math.pi * (E_star / p0[:, None]) ** 2 * I3[None, :]
    A = law.area(G)
    A[:, 0] = 1.0
    N = law.non_area(G)  # 1 - A, accurate near full contact
    N[:, 0] = 0.0
    ubar = np.zeros_like(A)
    for j, zj in enumerate(z):
        rule = q_rule(psd, zj * q_L)
        if rule.q.size:
            ubar[:, j] = mean_gap(psd, E_star, p0 / np.maximum(A[:, j], 1e-300), gamma, rule=rule)
    dA = N[:, 1:] - N[:, :-1]
    dAu = A[:, :-1] * ubar[:, :-1] - A[:, 1:] * ubar[:, 1:]
    ok = dA > 0
    u1 = np.where(ok, dAu / np.where(ok, dA, 1.0), 0.0)
    zm = np.sqrt(z[:-1] * z[1:])
    h = np.sqrt(np.maximum(_h2(psd, zm * q_L), 0.0))
    h_rms = math.sqrt(2.0 * math.pi * float(psd.moment(1.0)))
    dropped = np.sum(np.where(ok, 0.0, dAu), axis=1)
    return Detachment(p0, z, A, ubar, np.where(ok, dA, 0.0), np.maximum(u1, 0.0), h, h_rms, dropped)


def _pairs(det: Detachment, u: NDArray[np.float64]) -> tuple[NDArray, NDArray, NDArray]:
    h = np.maximum(det.h, 1e-300)[None, :, None]
    return u[None, None, :], det.u1[:, :, None], h


def gap_pdf(det: Detachment, u: ArrayLike) -> NDArray[np.float64]:
    """Continuous part ``rho(u)`` of the gap distribution [1/m], shape (n_load, n_u).

    Parameters
    ----------
    det : Detachment
        Output of :func:`detachment`.
    u : array_like
        Separations [m], ``>= 0``.
    """
    u = np.asarray(u, dtype=float)
    uu, u1, h = _pairs(det, u)
    with np.errstate(under="ignore", over="ignore"):
        g = (np.exp(-0.5 * ((uu - u1) / h) ** 2) + np.exp(-0.5 * ((uu + u1) / h) ** 2)) / (
            math.sqrt(2.0 * math.pi) * h
        )
        return np.einsum("lk,lku->lu", det.weight, g)


def gap_cdf(det: Detachment, u: ArrayLike) -> NDArray[np.float64]:
    """Integral of the continuous part ``int_0^u rho du'`` [1], shape (n_load, n_u)."""
    u = np.asarray(u, dtype=float)
    uu, u1, h = _pairs(det, u)
    c = 0.5 * (erf((uu - u1) / (_SQRT2 * h)) + erf((uu + u1) / (_SQRT2 * h)))
    return np.einsum("lk,lku->lu", det.weight, c)


def gap_mean(det: Detachment) -> NDArray[np.float64]:
    """Mean separation ``<u>`` of the closed form (mirror term included) [m], (n_load,).

    ``<u> = sum w [u1 erf(u1/(sqrt2 h)) + h sqrt(2/pi) exp(-u1^2/(2h^2))]``; exceeds Persson's
    ``u(p0)`` (physics.md §5.5).
    """
    h = np.maximum(det.h, 1e-300)[None, :]
    u1 = det.u1
    with np.errstate(under="ignore", over="ignore"):
        m = u1 * erf(u1 / (_SQRT2 * h)) + h * math.sqrt(2.0 / math.pi) * np.exp(
            -0.5 * (u1 / h) ** 2
        )
    return np.sum(det.weight * m, axis=1)
