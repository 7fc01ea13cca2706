"""Interface physics of a *solved* contact: elastic energy, mean gap, stiffness, gap distribution.

Pure numpy/scipy, SI floats, no units and no xarray. Every function takes the contact-area curve
the solve produced -- the relative areas ``A(zeta)`` on the solve's magnifications ``zeta`` for
each load -- and never re-derives the area from the spectrum, so whatever a coefficient (closure)
or boundary changed reaches every quantity below. The spectrum enters only through the weights of
the integrals (``q^2 C``, the diffusion time ``tau_c = (pi/4) E*^2 int q^3 C`` of the elastic
coefficient, the rms height of the finer scales).

Conventions (:cite:p:`persson2007,yang2008`): ``q = zeta q_L`` [1/m], ``G = tau_c / p0^2`` [1],
arrays of a curve
have shape ``(n_load, n_zeta)`` (a 1-D curve is one load), ``zeta[0] == 1``. The curve that enters
the energy is ``F = A S`` with the correction factor ``S = d tau_eff / d tau_c`` of the scene's
closure (``S = 1`` without a closure; Yang & Persson 2008 use ``S = gamma + (1 - gamma) A^2``).

API
---
full_contact_energy(psd, E_star, q_lo=None, q_hi=None)
    Elastic energy per nominal area of the roughness between ``q_lo`` and ``q_hi`` pressed fully
    flat, ``(pi E*/2) int_{q_lo}^{q_hi} q^2 C dq`` [J/m^2]; vectorised over ``q_lo`` (the
    adhesion plugin's ``U_el`` of the finer scales).
elastic_energy(psd, E_star, zeta, area, s_factor=None, non_area=None)
    ``U_el/A0 = (pi E*/2) int q^2 C A S dq`` [J/m^2] per load (:cite:p:`persson2007,yang2008`).
mean_gap(psd, E_star, p0, zeta, area, s_factor=None, non_area=None)
    Mean interfacial separation ``u(p0)`` [m] from virtual work ``p = -dU_el/du`` (§5.2).
mean_gap_slope(psd, E_star, p0, zeta, area, s_factor=None, non_area=None)
    ``du/dp0`` [m/Pa] (negative); the stiffness is ``K = -1/(du/dp0)`` (§5.4).
contact_stiffness(...)
    ``K = -dp0/du`` [Pa/m], finite and positive for ``1e-8 <= A <= 1 - 1e-12``.
detachment(psd, E_star, p0, zeta, area, s_factor=None, non_area=None, refine=1)
    Detached-area bins of the gap distribution (Almqvist et al. 2011, §5.5a): the weight, the
    separation ``u1 = d(A u)/dA`` and the finer roughness ``h`` of every bin
    (:class:`Detachment`).
gap_pdf(det, u), gap_cdf(det, u), gap_mean(det)
    Continuous part of the gap distribution [1/m], its integral [1] and its mean [m]; the
    contact fraction is the weight of ``delta(u)``. The adhesion plugin integrates its
    traction-gap law against ``gap_pdf`` / ``gap_cdf``.
critical_magnification(zeta, area, a_c)
    Magnification where the curve crosses ``a_c`` (NaN where it never does), per load.
separation_of_detaching_area(psd, E_star, p0, zeta, area, zeta_at, ...)
    ``u1 = d(A u_zeta)/dA`` at given magnifications (the critical junction of leakage, §6.1).
SolvedContact(psd, E_star, p0, zeta, area, s_factor=None, non_area=None)
    The same quantities as methods of one object that builds the curve's splines once
    (``elastic_energy()``, ``mean_gap()``, ``mean_gap_slope()``, ``contact_stiffness()``,
    ``detachment(zeta_edges)``, ``critical_magnification(a_c)``, ``separation_at(zeta)``).

Mean gap from the area curve
----------------------------
Virtual work ``u(p0) = int_{p0}^inf dp/p dU_el/dp`` needs ``U_el`` at every load above ``p0``.
When the boundary makes the area a function of ``G = tau_c/p0^2`` alone (a fixed wall at
``p = 0``: elastic contact with any of the closures), the curve of one load already samples that
universal function, and exchanging the integrals gives

    u(p0) = pi int q^2 C(q) w(q) Phi(G(q)) dq,    Phi(G) = int_0^G sqrt(G') (-dF(G')),

``w = (pi int_{q_L}^q q'^3 C)^(-1/2)``; for Persson 2001 ``Phi = E1(1/(4G)) / (2 sqrt(pi))``,
the exponential-integral form of :cite:p:`persson2007,yang2008`. Likewise
``du/dp0 = -(4/(E* p0^2)) int (tau_c/q) (-dF)``. The mean separation of the apparent contact at
magnification ``zeta`` (lower cut-off ``zeta q_L``, pressure ``p0/A(zeta)``; §5.5, §6.1) uses the
same ``Phi`` with ``tau_c`` counted from ``zeta``.

Accuracy follows the curve's sampling: the curve is interpolated by cubic splines in
``ln zeta`` (of ``ln(1 - F)``, exact near full contact); integrals use composite Gauss-Legendre
rules that remove the ``(q - q_a)^(-1/2)`` singularity of ``w``. Sample ``zeta`` densely where
``A`` changes fast (near ``zeta = 1`` at small loads): e.g. ``1 + geomspace(1e-9, zeta_1 - 1)``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._curve import (
    _Curve,
)
from ._energy import full_contact_energy
from ._gap_distribution import Detachment, gap_cdf, gap_mean, gap_pdf
from ._percolation import critical_magnification
from ._solved_contact import SolvedContact

__all__ = [
    "Detachment",
    "SolvedContact",
    "contact_stiffness",
    "critical_magnification",
    "detachment",
    "elastic_energy",
    "full_contact_energy",
    "gap_cdf",
    "gap_mean",
    "gap_pdf",
    "mean_gap",
    "mean_gap_slope",
    "separation_of_detaching_area",
]


def elastic_energy(
    psd: object,
    E_star: float,
    zeta: ArrayLike,
    area: ArrayLike,
    s_factor: ArrayLike | None = None,
    non_area: ArrayLike | None = None,
) -> NDArray[np.float64]:
    """Elastic energy per nominal area ``U_el/A0 = (pi E*/2) int q^2 C A S dq`` [J/m^2].

    Physics.md §5.1 with the solved area curve; evaluated as the full-contact energy minus
    ``(pi E*/2) int q^2 C (1 - A S) dq`` (accurate near full contact). The integral runs to the
    curve's last magnification ``zeta[-1] q_L`` (normally ``q_1``).

    Parameters
    ----------
    psd : PowerSpectrum
        Roughness spectrum (m^4).
    E_star : float
        Contact modulus [Pa].
    zeta : array_like, (n_zeta,)
        Magnifications of the curve, increasing from 1.
    area : array_like, (n_load, n_zeta)
        Contact area fraction ``A/A0`` [1] that stores elastic energy (the elastic contact area).
    s_factor : array_like, optional
        Correction factor ``S`` [1] on the same nodes (default 1).
    non_area : array_like, optional
        ``1 - A`` [1], given where it is known without cancellation.

    Returns
    -------
    ndarray, (n_load,)
    """
    cur = _Curve(zeta, area, s_factor, non_area)
    return SolvedContact(psd, E_star, np.ones(cur.n_load), cur).elastic_energy()


def mean_gap(
    psd: object,
    E_star: float,
    p0: ArrayLike,
    zeta: ArrayLike,
    area: ArrayLike,
    s_factor: ArrayLike | None = None,
    non_area: ArrayLike | None = None,
) -> NDArray[np.float64]:
    """Mean interfacial separation ``u(p0)`` [m] of the solved curve
    (:cite:p:`persson2007,yang2008`).

    Virtual work ``p = -dU_el/du`` with ``U_el`` of :func:`elastic_energy`, for a curve that is
    a function of ``G = tau_c/p0^2`` alone (see the module docstring).

    Parameters
    ----------
    psd, E_star, p0, zeta, area, s_factor, non_area
        See :class:`SolvedContact`.

    Returns
    -------
    ndarray, (n_load,)
        ``u`` [m], >= 0.
    """
    return SolvedContact(psd, E_star, p0, zeta, area, s_factor, non_area).mean_gap()


def mean_gap_slope(
    psd: object,
    E_star: float,
    p0: ArrayLike,
    zeta: ArrayLike,
    area: ArrayLike,
    s_factor: ArrayLike | None = None,
    non_area: ArrayLike | None = None,
) -> NDArray[np.float64]:
    """Load derivative ``du/dp0 = -(4/(E* p0^2)) int (tau_c/q) (-dF)`` [m/Pa] (<= 0)."""
    return SolvedContact(psd, E_star, p0, zeta, area, s_factor, non_area).mean_gap_slope()


def contact_stiffness(
    psd: object,
    E_star: float,
    p0: ArrayLike,
    zeta: ArrayLike,
    area: ArrayLike,
    s_factor: ArrayLike | None = None,
    non_area: ArrayLike | None = None,
) -> NDArray[np.float64]:
    """Normal contact stiffness per nominal area ``K = -dp0/du`` [Pa/m]
    (:cite:p:`persson2007,yang2008`).

    ``-du/dp0`` is a positive integral of ``-dF`` taken from ``ln(1 - F)``, so near full contact
    (``1 - A`` down to 1e-12 and below) ``K`` follows its asymptote ``K ~ 1/int (tau_c/q) dN``
    without cancellation; ``inf`` only when ``1 - A`` underflows to zero everywhere.
    """
    return SolvedContact(psd, E_star, p0, zeta, area, s_factor, non_area).contact_stiffness()


def detachment(
    psd: object,
    E_star: float,
    p0: ArrayLike,
    zeta: ArrayLike,
    area: ArrayLike,
    s_factor: ArrayLike | None = None,
    non_area: ArrayLike | None = None,
    *,
    zeta_edges: ArrayLike | None = None,
    refine: int = 1,
    separation: str = "almqvist",
) -> Detachment:
    """Detached-area bins of the closed-form gap distribution (:cite:p:`almqvist2011`).

    Bin ``k`` between edges ``zeta_{k-1}, zeta_k`` carries the detached area ``A_{k-1} - A_k``
    at ``u1 = (A_{k-1} u_{k-1} - A_k u_k) / (A_{k-1} - A_k)`` (finite-volume ``d(A u)/dA``), so
    the mass ``1 - A(zeta_max)`` and ``sum weight u1 = u(p0)`` hold to rounding, and the rms
    height of the finer roughness ``h`` at the bin's geometric midpoint.

    Parameters
    ----------
    psd, E_star, p0, zeta, area, s_factor, non_area
        See :class:`SolvedContact`.
    zeta_edges : array_like, optional
        Bin edges from 1 to ``zeta[-1]`` (default: the curve's own magnifications); the area
        at the edges is interpolated on the curve.
    refine : int
        Without ``zeta_edges``: split every interval of the curve into this many bins.
    separation : {"almqvist", "pressure"}
        How ``u1`` is assigned (see :meth:`SolvedContact.detachment`): Almqvist's
        ``d(A u)/dA``, or only its pressure part (no far tail at high load).

    Returns
    -------
    Detachment
    """
    sc = SolvedContact(psd, E_star, p0, zeta, area, s_factor, non_area)
    if zeta_edges is None and refine > 1:
        x, t = sc.curve.x, np.arange(int(refine)) / int(refine)
        inner = (x[:-1, None] + np.diff(x)[:, None] * t).ravel()
        zeta_edges = np.exp(np.concatenate((inner, x[-1:])))
    return sc.detachment(zeta_edges, separation)


def separation_of_detaching_area(
    psd: object,
    E_star: float,
    p0: ArrayLike,
    zeta: ArrayLike,
    area: ArrayLike,
    zeta_at: ArrayLike,
    s_factor: ArrayLike | None = None,
    non_area: ArrayLike | None = None,
    *,
    rel_step: float = 1e-3,
) -> NDArray[np.float64]:
    """``u1 = d(A u_zeta)/dA`` [m] at per-load magnifications ``zeta_at`` (NaN stays NaN).

    Central finite volume over ``zeta_at exp(+-h)``, ``h = min(rel_step, 0.01 ln zeta_at)``
    (second order; near ``zeta = 1`` the area falls on the scale of ``ln zeta`` itself), the
    area interpolated on the curve and the sub-problem mean separation of :func:`detachment`
    (:cite:p:`persson2008leak`, the critical constriction of the leakage theory).
    """
    sc = SolvedContact(psd, E_star, p0, zeta, area, s_factor, non_area)
    return sc.separation_at(zeta_at, rel_step=rel_step)
