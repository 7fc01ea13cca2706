"""Leak rate of a static seal (physics.md §6): critical junction and effective medium.

*Critical junction* (Persson & Yang 2008; Lorenz & Persson 2009): the non-contact channels
percolate at the magnification ``zeta_c`` where ``A(zeta_c)/A0 = a_c`` (default 0.42); the flow
is limited by the critical constrictions of height ``u1(zeta_c) = d(A u)/dA`` and

    Q = (L_y / L_x) u1^3 dP_eff / (12 eta)          [m^3/s]

(``L_x`` seal width along the flow, ``L_y`` length across it). *Effective medium* (Bruggeman,
Lorenz & Persson 2010): the local conductance ``sigma(u) = u^3/(12 eta)`` is averaged over the gap
distribution (contact as a ``delta(u)`` weight with ``sigma = 0``) by the 2-D condition
``int P(u) (sigma - sigma_eff)/(sigma + sigma_eff) du = 0``. Plain 2-D Bruggeman percolates at a
contact weight of 1/2; the option ``rescale_to=a_c`` multiplies the contact weight by
``0.5/a_c`` (a documented design choice, not from the papers) so both theories seal together.

For an ideal gas at constant temperature the laminar flow gives the volume flow at the reference
pressure ``p_ref`` with ``dP_eff = (p_in^2 - p_out^2) / (2 p_ref)`` (no slip correction).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import brentq

from ._closures import AreaLaw
from ._gap import mean_gap
from ._gap_pdf import Detachment, gap_cdf
from ._quad import q_rule

__all__ = [
    "critical_junction",
    "bruggeman",
    "bruggeman_gap",
    "effective_pressure_drop",
    "leak_rate",
]


def critical_junction(
    psd: object,
    E_star: float,
    p0: ArrayLike,
    a_c: float = 0.42,
    gamma: float = 1.0,
    law: AreaLaw | None = None,
    *,
    rel_step: float = 1e-3,
) -> dict[str, NDArray[np.float64]]:
    """Percolation magnification and critical gap per load.

    Parameters
    ----------
    psd : PowerSpectrum
        Roughness spectrum (m^4).
    E_star : float
        Contact modulus [Pa].
    p0 : array_like
        Nominal pressures [Pa].
    a_c : float
        Percolation threshold of the contact area [1].
    gamma : float
        Correction-factor parameter of the mean separation [1].
    law : AreaLaw, optional
        Contact-area law (default Persson 2001).
    rel_step : float
        Half-width in ``ln zeta`` of the bin used for ``u1 = d(A u)/dA`` (second order).

    Returns
    -------
    dict
        ``zeta_c`` [1] (NaN when sealed), ``u1`` [m] (0 when sealed), ``sealed`` (bool),
        ``area_final`` ``A(zeta_1)/A0`` [1].
    """
    law = AreaLaw() if law is None else law
    p0 = np.atleast_1d(np.asarray(p0, dtype=float))
    q_L, q_1 = float(psd.q_L), float(psd.q_1)
    I3_1 = float(psd.I3(q_1))
    G_c = law.G_of_area(a_c)
    I3_c = 4.0 * G_c * p0**2 / (math.pi * E_star**2)
    sealed = I3_c >= I3_1
    zeta_c = np.full(p0.size, np.nan)
    u1 = np.zeros(p0.size)
    G1 = 0.25 * math.pi * (E_star / p0) ** 2 * I3_1
    for i in np.flatnonzero(~sealed):
        lq = brentq(
            lambda x, t=I3_c[i]: float(psd.I3(math.exp(x))) - t,
            math.log(q_L),
            math.log(q_1),
            xtol=1e-13,
        )
        zc = math.exp(lq) / q_L
        zeta_c[i] = zc
        za = max(1.0, zc * math.exp(-rel_step))
        zb = min(q_1 / q_L, zc * math.exp(rel_step))
        Gab = 0.25 * math.pi * (E_star / p0[i]) ** 2 * np.asarray(psd.I3(np.array([za, zb]) * q_L))
        A = law.area(Gab)
        N = law.non_area(Gab)
        ub = [
            float(mean_gap(psd, E_star, p0[i] / A[j], gamma, rule=q_rule(psd, zz * q_L)))
            for j, zz in enumerate((za, zb))
        ]
        u1[i] = (A[0] * ub[0] - A[1] * ub[1]) / (N[1] - N[0])
    return {"zeta_c": zeta_c, "u1": u1, "sealed": sealed, "area_final": law.area(G1)}


def bruggeman(contact: float, masses: ArrayLike, sigma: ArrayLike, *, rtol: float = 1e-12) -> float:
    """2-D Bruggeman effective conductance of a mixture with a non-conducting contact weight.

    Solves ``-contact + sum m_k (s_k - s)/(s_k + s) = 0`` for ``s > 0`` (``s_k = inf`` allowed).

    Parameters
    ----------
    contact : float
        Weight of the contact (``sigma = 0``) [1].
    masses : array_like
        Weights of the open elements [1] (``contact + sum(masses) = 1``).
    sigma : array_like
        Their conductances (any unit; the result has the same unit), ``> 0``.

    Returns
    -------
    float
        ``sigma_eff``; 0 when the contact weight reaches the percolation value 1/2.
    """
    m = np.asarray(masses, dtype=float)
    s = np.asarray(sigma, dtype=float)
    use = m > 0
    m, s = m[use], s[use]
    if m.size == 0 or contact >= 0.5 * (contact + m.sum()):
        return 0.0
    fin = np.isfinite(s)

    def f(ls: float) -> float:
        se = math.exp(ls)
        return -contact + float(np.sum(m[fin] * (s[fin] - se) / (s[fin] + se))) + m[~fin].sum()

    hi = math.log(float(np.max(s[fin]))) if np.any(fin) else 0.0
    lo = hi - 10.0
    while f(lo) < 0:
        lo -= 10.0
    while f(hi) > 0:
        hi += 10.0
    return math.exp(brentq(f, lo, hi, rtol=rtol, xtol=1e-14))


def bruggeman_gap(
    det: Detachment,
    *,
    a_c: float | None = None,
    n_u: int = 2000,
    u_max: float | None = None,
) -> NDArray[np.float64]:
    """Effective ``<u^3>_EMT`` [m^3] over the closed-form gap distribution, per load.

    ``sigma_eff = result / (12 eta)``. Cells on ``[0, u_max]`` (geometric from ``1e-7 h_rms``)
    carry the exact closed-form mass (analytic CDF) at their midpoint conductance; the mass
    beyond ``u_max`` is one element of infinite conductance.

    Parameters
    ----------
    det : Detachment
        Gap-distribution bins (:func:`._gap_pdf.detachment`).
    a_c : float, optional
        When given, rescale the contact weight by ``0.5 / a_c`` so that the effective medium
        seals at ``A/A0 = a_c`` (open weights rescaled to keep unit total).
    n_u : int
        Number of cells.
    u_max : float, optional
        Upper end of the cells [m] (default ``max(u(p0)) + 10 h_rms``).
    """
    umax = float(np.max(det.mean_gap)) + 10.0 * det.h_rms if u_max is None else u_max
    edges = np.concatenate(([0.0], np.geomspace(1e-7 * det.h_rms, umax, n_u)))
    cdf = gap_cdf(det, edges)
    out = np.zeros(det.p0.size)
    for i in range(det.p0.size):
        a = float(det.contact[i])
        m = np.concatenate((np.diff(cdf[i]), [max(1.0 - a - cdf[i, -1], 0.0)]))
        if a_c is not None:
            a_new = min(1.0, a * 0.5 / a_c)
            m = m * ((1.0 - a_new) / (1.0 - a) if a < 1.0 else 0.0)
            a = a_new
        sig = np.concatenate((0.5 * (edges[:-1] + edges[1:]), [np.inf])) ** 3
        out[i] = bruggeman(a, m, sig)
    return out


def effective_pressure_drop(
    fluid: str,
    pressure_drop: float = 0.0,
    p_in: float = 0.0,
    p_out: float = 0.0,
    p_ref: float | None = None,
) -> float:
    """Pressure difference [Pa] driving the laminar flow.

    ``liquid``: ``pressure_drop``; ``gas`` (ideal, isothermal): ``(p_in^2 - p_out^2)/(2 p_ref)``
    so that the result times the conductance is the volume flow at ``p_ref`` (default ``p_out``).
    """
    if fluid == "liquid":
        return float(pressure_drop)
    if fluid == "gas":
        ref = p_out if p_ref is None else p_ref
        if not ref > 0:
            raise ValueError("gas leakage needs a positive reference pressure (p_out or p_ref)")
        return (p_in**2 - p_out**2) / (2.0 * ref)
    raise ValueError(f"fluid must be 'liquid' or 'gas', got {fluid!r}")


def leak_rate(
    u3: ArrayLike, seal_width: float, seal_length: float, dp_eff: float, viscosity: float
) -> NDArray[np.float64]:
    """Volume leak rate ``Q = (L_y/L_x) u3 dP_eff / (12 eta)`` [m^3/s].

    Parameters
    ----------
    u3 : array_like
        ``u1^3`` (critical junction) or ``<u^3>_EMT`` [m^3].
    seal_width : float
        ``L_x`` along the flow [m].
    seal_length : float
        ``L_y`` across the flow [m].
    dp_eff : float
        Effective pressure drop [Pa].
    viscosity : float
        Dynamic viscosity [Pa s].
    """
    return (seal_length / seal_width) * np.asarray(u3, dtype=float) * dp_eff / (12.0 * viscosity)
