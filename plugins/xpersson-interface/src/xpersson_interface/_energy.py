"""Elastic energy stored at the interface versus load (physics.md §5.1, §1.5).

.. math::

    U_{el}/A_0 = \\frac{\\pi E^*}{2} \\int_{q_L}^{q_1} q^2 C(q)\\, P(q)\\, S(q)\\, dq
    \\quad [\\mathrm{J/m^2}]

with ``P(q) = A(zeta = q/q_L)/A0`` and the correction factor ``S`` of the closure
(:mod:`._closures`): ``S = 1`` for Persson 2007. With ``uncorrected_area=True`` the area is
Persson's ``erf(w p / E*)`` while ``S`` is the closure's (the Yang-Persson form that is
consistent with :func:`._gap.mean_gap`, ``dU_el/du = -p``). The Xu 2024 closure adds, as in the
authors' code, the "hybrid" term ``((1 - gamma)/E*) int A V_c / q dA`` along the magnification
path (``V_c = 2 tau`` the complete-contact pressure variance).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.special import erf

from ._closures import AreaLaw
from ._quad import QRule, q_rule

__all__ = ["elastic_energy", "full_contact_energy"]


def full_contact_energy(psd: object, E_star: float) -> float:
    """Elastic energy per nominal area at full contact ``(pi E*/2) int q^2 C dq`` [J/m^2]."""
    return 0.5 * math.pi * E_star * float(psd.moment(2.0))


def elastic_energy(
    psd: object,
    E_star: float,
    p: ArrayLike,
    law: AreaLaw | None = None,
    *,
    uncorrected_area: bool = False,
    hybrid: bool = True,
    rule: QRule | None = None,
) -> NDArray[np.float64]:
    """Elastic energy per nominal area ``U_el/A0`` [J/m^2] at nominal pressures ``p``.

    Parameters
    ----------
    psd : PowerSpectrum
        Roughness spectrum (Persson convention, m^4).
    E_star : float
        Contact modulus [Pa].
    p : array_like
        Nominal pressures [Pa], ``> 0``.
    law : AreaLaw, optional
        Area closure (default Persson 2001: ``S = 1``).
    uncorrected_area : bool
        Use Persson's area ``erf(w p/E*)`` with the closure's ``S`` (Yang-Persson form).
    hybrid : bool
        Add the Xu 2024 hybrid term (only for the ``xu24`` closure with its own area).
    rule : QRule, optional
        Precomputed quadrature rule.

    Returns
    -------
    ndarray
        ``U_el/A0`` [J/m^2], same shape as ``p``.
    """
    law = AreaLaw() if law is None else law
    r = q_rule(psd) if rule is None else rule
    p = np.asarray(p, dtype=float)
    x0 = r.w[None, :] * (p.reshape(-1, 1) / E_star)  # w p / E*
    G = 0.25 / (x0 * x0)
    A = erf(x0) if uncorrected_area else law.area(G)
    kern = r.weights * r.q**2 * r.C
    U = 0.5 * math.pi * E_star * ((A * law.S(A)) @ kern)
    if hybrid and law.closure == "xu24" and not uncorrected_area:
        Vc = 0.5 * (E_star / r.w) ** 2  # V_c = (pi/2) E*^2 I3 [Pa^2]
        dGdq = 0.25 * math.pi * (E_star / p.reshape(-1, 1)) ** 2 * (r.q**3 * r.C)[None, :]
        dA = law.darea_dG(G) * dGdq
        U = U + (1.0 - law.gamma) / E_star * ((A * Vc[None, :] / r.q[None, :] * dA) @ r.weights)
    return U.reshape(p.shape)
