"""Interface physics of a *solved* contact: elastic energy, mean gap, stiffness, gap distribution.

Pure numpy/scipy, SI floats, no units and no xarray. Every function takes the contact-area curve
the solve produced -- the relative areas ``A(zeta)`` on the solve's magnifications ``zeta`` for
each load -- and never re-derives the area from the spectrum, so whatever a coefficient (closure)
or boundary changed reaches every quantity below. The spectrum enters only through the weights of
the integrals (``q^2 C``, the diffusion time ``tau_c = (pi/4) E*^2 int q^3 C`` of the elastic
coefficient, the rms height of the finer scales).

Conventions (physics.md §5): ``q = zeta q_L`` [1/m], ``G = tau_c / p0^2`` [1], arrays of a curve
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
    ``U_el/A0 = (pi E*/2) int q^2 C A S dq`` [J/m^2] per load (physics.md §5.1).
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
the exponential-integral form of physics.md §5.2. Likewise
``du/dp0 = -(4/(E* p0^2)) int (tau_c/q) (-dF)``. The mean separation of the apparent contact at
magnification ``zeta`` (lower cut-off ``zeta q_L``, pressure ``p0/A(zeta)``; §5.5, §6.1) uses the
same ``Phi`` with ``tau_c`` counted from ``zeta``.

Accuracy follows the curve's sampling: the curve is interpolated by cubic splines in
``ln zeta`` (of ``ln(1 - F)``, exact near full contact); integrals use composite Gauss-Legendre
rules that remove the ``(q - q_a)^(-1/2)`` singularity of ``w``. Sample ``zeta`` densely where
``A`` changes fast (near ``zeta = 1`` at small loads): e.g. ``1 + geomspace(1e-9, zeta_1 - 1)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.interpolate import CubicSpline
from scipy.special import erf

from ._curve import (
    _TINY,
    _Curve,
    _edges,
    _h2,
    _loads,
    _Phi,
    _q_max,
    _q_rule,
    _sub_mean_gap,
    _tau_c,
)

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

_SQRT2 = math.sqrt(2.0)


# -- energy -------------------------------------------------------------------------------------
def full_contact_energy(
    psd: object, E_star: float, q_lo: ArrayLike | None = None, q_hi: float | None = None
) -> NDArray[np.float64] | float:
    """Elastic energy per nominal area of the roughness in ``[q_lo, q_hi]`` at full contact.

    ``U/A0 = (pi E*/2) int_{q_lo}^{q_hi} q^2 C(q) dq`` [J/m^2] (physics.md §5.1 with
    ``A = S = 1``): the exact linear-elastic energy of a half-space forced into the shape of
    those scales.

    Parameters
    ----------
    psd : PowerSpectrum
        Roughness spectrum (Persson convention, m^4).
    E_star : float
        Contact modulus [Pa].
    q_lo : array_like, optional
        Lower limit(s) [1/m] (default ``q_L``); vectorised.
    q_hi : float, optional
        Upper limit [1/m] (default ``q_1``).

    Returns
    -------
    float or ndarray
        Energy [J/m^2], shape of ``q_lo``.
    """
    q_L, q_1 = float(psd.q_L), float(psd.q_1)  # type: ignore[attr-defined]
    lo = np.asarray(q_L if q_lo is None else q_lo, dtype=float)
    hi = q_1 if q_hi is None else float(q_hi)
    m_hi = float(psd.running_moment(2.0, hi))  # type: ignore[attr-defined]
    m_lo = np.asarray(psd.running_moment(2.0, np.minimum(lo, hi)), dtype=float)  # type: ignore[attr-defined]
    out = 0.5 * math.pi * E_star * (m_hi - m_lo)
    return float(out) if out.ndim == 0 else out


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
    """Mean interfacial separation ``u(p0)`` [m] of the solved curve (physics.md §5.2).

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
    """Normal contact stiffness per nominal area ``K = -dp0/du`` [Pa/m] (physics.md §5.4).

    ``-du/dp0`` is a positive integral of ``-dF`` taken from ``ln(1 - F)``, so near full contact
    (``1 - A`` down to 1e-12 and below) ``K`` follows its asymptote ``K ~ 1/int (tau_c/q) dN``
    without cancellation; ``inf`` only when ``1 - A`` underflows to zero everywhere.
    """
    return SolvedContact(psd, E_star, p0, zeta, area, s_factor, non_area).contact_stiffness()


@dataclass(frozen=True)
class Detachment:
    """Detached-area bins of the gap distribution (SI units, per load).

    Attributes
    ----------
    p0 : ndarray, (n_load,)
        Nominal pressures [Pa].
    zeta : ndarray, (n_edge,)
        Bin edges [1] (the curve's magnifications, optionally refined).
    area : ndarray, (n_load, n_edge)
        Contact area fraction at the edges [1].
    ubar : ndarray, (n_load, n_edge)
        Mean separation of the apparent contact at the edges [m] (``ubar[:, 0] = u(p0)``).
    weight : ndarray, (n_load, n_bin)
        Detached area per bin ``A_{k-1} - A_k`` [1].
    u1 : ndarray, (n_load, n_bin)
        Mean separation of the area detaching in the bin [m].
    h : ndarray, (n_bin,)
        rms height of the roughness finer than the bin's (geometric) midpoint [m].
    h_rms : float
        rms height of the roughness up to the last edge [m].
    """

    p0: NDArray[np.float64]
    zeta: NDArray[np.float64]
    area: NDArray[np.float64]
    ubar: NDArray[np.float64]
    weight: NDArray[np.float64]
    u1: NDArray[np.float64]
    h: NDArray[np.float64]
    h_rms: float

    @property
    def contact(self) -> NDArray[np.float64]:
        """Contact fraction at the last edge [1] (weight of ``delta(u)``), (n_load,)."""
        return self.area[:, -1]

    @property
    def mean_gap(self) -> NDArray[np.float64]:
        """Persson's mean separation ``u(p0)`` [m], (n_load,)."""
        return self.ubar[:, 0]


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
) -> Detachment:
    """Detached-area bins of the closed-form gap distribution (physics.md §5.5a).

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

    Returns
    -------
    Detachment
    """
    sc = SolvedContact(psd, E_star, p0, zeta, area, s_factor, non_area)
    if zeta_edges is None and refine > 1:
        x, t = sc.curve.x, np.arange(int(refine)) / int(refine)
        inner = (x[:-1, None] + np.diff(x)[:, None] * t).ravel()
        zeta_edges = np.exp(np.concatenate((inner, x[-1:])))
    return sc.detachment(zeta_edges)


def gap_pdf(det: Detachment, u: ArrayLike) -> NDArray[np.float64]:
    """Continuous part ``rho(u)`` of the gap distribution [1/m], shape (n_load, n_u).

    ``rho = sum_k weight_k [N(u; u1_k, h_k^2) + N(u; -u1_k, h_k^2)]`` for ``u >= 0`` (the mirror
    term keeps detached area out of contact); ``int_0^inf rho = 1 - A(zeta_max)``.
    """
    u = np.asarray(u, dtype=float)
    inv_h = 1.0 / np.maximum(det.h, _TINY)  # (n_bin,)
    with np.errstate(under="ignore", over="ignore", invalid="ignore"):
        a = np.minimum(det.u1 * inv_h, 1e150)[:, :, None]  # (n_load, n_bin, 1), finite
        b = np.minimum(u[None, :] * inv_h[:, None], 1e150)[None]  # (1, n_bin, n_u)
        d = b - a
        d *= d
        d *= -0.5
        e = np.exp(d, out=d)  # mirror pair: N(u - u1) (1 + exp(-2 u u1 / h^2))
        m = b * a
        m *= -2.0
        e *= 1.0 + np.exp(m, out=m)
    return np.einsum("lk,lku->lu", det.weight * inv_h / math.sqrt(2.0 * math.pi), e)


def gap_cdf(det: Detachment, u: ArrayLike) -> NDArray[np.float64]:
    """``int_0^u rho du'`` [1], shape (n_load, n_u) (add the contact weight for the full CDF)."""
    u = np.asarray(u, dtype=float)
    inv = 1.0 / (_SQRT2 * np.maximum(det.h, _TINY))
    with np.errstate(over="ignore", invalid="ignore"):
        a = np.minimum(det.u1 * inv, 1e150)[:, :, None]  # no inf - inf below
        b = np.minimum(u[None, :] * inv[:, None], 1e150)[None]
        lo = erf(b - a)
        lo += erf(b + a)
    return 0.5 * np.einsum("lk,lku->lu", det.weight, lo)


def gap_mean(det: Detachment) -> NDArray[np.float64]:
    """Mean of the gap distribution (mirror term included) [m], (n_load,).

    ``sum w [u1 erf(u1/(sqrt2 h)) + h sqrt(2/pi) exp(-u1^2/(2h^2))]``; exceeds ``u(p0)``
    (physics.md §5.5a).
    """
    h = np.maximum(det.h, _TINY)[None, :]
    u1 = det.u1
    with np.errstate(under="ignore", over="ignore"):
        m = u1 * erf(u1 / (_SQRT2 * h)) + h * math.sqrt(2.0 / math.pi) * np.exp(
            -0.5 * (u1 / h) ** 2
        )
    return np.sum(det.weight * m, axis=1)


# -- percolation --------------------------------------------------------------------------------
def critical_magnification(zeta: ArrayLike, area: ArrayLike, a_c: float) -> NDArray[np.float64]:
    """Magnification [1] where the area curve crosses ``a_c`` (NaN where it stays above).

    The crossing interval is found on the nodes; inside it the cubic spline of ``A`` in
    ``ln zeta`` is solved by safeguarded Newton steps (exact at the nodes).
    """
    z = np.asarray(zeta, dtype=float)
    A = np.atleast_2d(np.asarray(area, dtype=float))
    if not 0.0 < a_c < 1.0:
        raise ValueError(f"a_c must lie in (0, 1), got {a_c!r}")
    x = np.log(z)
    below = A <= a_c
    crossed = below.any(axis=1)
    j = np.where(crossed, np.argmax(below, axis=1), 1)  # first node at or below a_c
    j = np.clip(j, 1, z.size - 1)
    out = np.full(A.shape[0], np.nan)
    if not crossed.any():
        return out
    spl = CubicSpline(x, A, axis=1) if z.size > 2 else None
    rows = np.arange(A.shape[0])
    lo, hi = x[j - 1], x[j]
    a_lo, a_hi = A[rows, j - 1], A[rows, j]
    t = (a_lo - a_c) / np.where(a_lo > a_hi, a_lo - a_hi, 1.0)
    xc = lo + np.clip(t, 0.0, 1.0) * (hi - lo)
    if spl is not None:
        c = spl.c  # (4, n_int, n_load)
        k = j - 1
        for _ in range(60):
            d = xc - x[k]
            f = ((c[0][k, rows] * d + c[1][k, rows]) * d + c[2][k, rows]) * d + c[3][k, rows]
            df = (3.0 * c[0][k, rows] * d + 2.0 * c[1][k, rows]) * d + c[2][k, rows]
            r = f - a_c
            lo = np.where(r > 0, xc, lo)
            hi = np.where(r <= 0, xc, hi)
            step = np.where(df < 0, r / np.where(df < 0, df, -1.0), 0.0)
            xn = xc - step
            bad = ~((xn > lo) & (xn < hi))
            xn = np.where(bad, 0.5 * (lo + hi), xn)
            if np.all(np.abs(xn - xc) <= 1e-15 * np.maximum(1.0, np.abs(xc))):
                xc = xn
                break
            xc = xn
    out[crossed] = np.exp(xc[crossed])
    return out


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

    Central finite volume over ``zeta_at exp(+-rel_step)`` (second order) with the area
    interpolated on the curve and the sub-problem mean separation of :func:`detachment`
    (physics.md §6.1, the critical constriction of the leakage theory).
    """
    sc = SolvedContact(psd, E_star, p0, zeta, area, s_factor, non_area)
    return sc.separation_at(zeta_at, rel_step=rel_step)


class SolvedContact:
    """The solved contact of every load: one area curve, every interface quantity (cached).

    The functions of this module are thin wrappers; build one :class:`SolvedContact` when
    several quantities of the same curve are needed (the curve's splines and ``Phi`` are built
    once).

    Parameters
    ----------
    psd : PowerSpectrum
        Roughness spectrum (m^4).
    E_star : float
        Contact modulus [Pa].
    p0 : array_like, (n_load,)
        Nominal pressures [Pa].
    zeta, area, s_factor, non_area
        The curve, as in :func:`elastic_energy` (``zeta`` may also be a prepared curve object).
    """

    def __init__(
        self,
        psd: object,
        E_star: float,
        p0: ArrayLike,
        zeta: ArrayLike | _Curve,
        area: ArrayLike | None = None,
        s_factor: ArrayLike | None = None,
        non_area: ArrayLike | None = None,
    ) -> None:
        self.psd = psd
        self.E_star = float(E_star)
        self.curve = zeta if isinstance(zeta, _Curve) else _Curve(zeta, area, s_factor, non_area)
        self.p0 = _loads(p0, self.curve.n_load)
        self.q_L = float(psd.q_L)  # type: ignore[attr-defined]
        self.q_hi = _q_max(psd, self.curve.zeta)
        self._phi: _Phi | None = None
        self._u: NDArray[np.float64] | None = None

    @property
    def phi(self) -> _Phi:
        if self._phi is None:
            self._phi = _Phi(self.psd, self.E_star, self.p0, self.curve)
        return self._phi

    def elastic_energy(self) -> NDArray[np.float64]:
        """``U_el/A0`` [J/m^2], (n_load,) (see :func:`elastic_energy`)."""
        r = _q_rule(self.psd, self.q_L, self.q_hi)
        deficit = self.curve.nf(np.log(r.q / self.q_L)) @ (r.weights * r.q**2 * r.C)
        full = full_contact_energy(self.psd, self.E_star, self.q_L, self.q_hi)
        return full - 0.5 * math.pi * self.E_star * deficit

    def mean_gap(self) -> NDArray[np.float64]:
        """``u(p0)`` [m], (n_load,) (see :func:`mean_gap`)."""
        if self._u is None:
            r = _q_rule(self.psd, self.q_L, self.q_hi)
            vals = self.phi.at_tau(0.25 * np.pi * self.E_star**2 * r.dI3)
            self._u = math.pi * (vals @ (r.weights * r.q**2 * r.C * r.w))
        return self._u.copy()

    def mean_gap_slope(self) -> NDArray[np.float64]:
        """``du/dp0`` [m/Pa], (n_load,) (see :func:`mean_gap_slope`)."""
        xg, wg = self.curve.stieltjes_nodes()
        q = np.exp(xg) * self.q_L
        g = _tau_c(self.psd, self.E_star, q) / q * wg
        dF = self.curve.dF(xg)
        return -4.0 / (self.E_star * self.p0**2) * np.sum(dF * g[None], axis=(1, 2))

    def contact_stiffness(self) -> NDArray[np.float64]:
        """``K = -dp0/du`` [Pa/m], (n_load,) (see :func:`contact_stiffness`)."""
        s = self.mean_gap_slope()
        with np.errstate(divide="ignore"):
            return np.where(s < 0, -1.0 / np.where(s < 0, s, -1.0), np.inf)

    def detachment(self, zeta_edges: ArrayLike | None = None) -> Detachment:
        """Detached-area bins (see :func:`detachment`)."""
        cur, q_L, q_hi = self.curve, self.q_L, self.q_hi
        z, A, N = _edges(cur, zeta_edges)
        ubar = _sub_mean_gap(self.psd, self.E_star, self.phi, (z * q_L)[None, :], A, q_hi)
        ubar[:, 0] = self.mean_gap()
        ubar[:, -1] = 0.0
        dA = N[:, 1:] - N[:, :-1]
        dAu = A[:, :-1] * ubar[:, :-1] - A[:, 1:] * ubar[:, 1:]
        ok = dA > 0
        u1 = np.where(ok, dAu / np.where(ok, dA, 1.0), 0.0)
        h = np.sqrt(_h2(self.psd, np.sqrt(z[:-1] * z[1:]) * q_L, q_hi))
        h_rms = float(np.sqrt(_h2(self.psd, q_L, q_hi)))
        return Detachment(self.p0, z, A, ubar, np.where(ok, dA, 0.0), np.maximum(u1, 0.0), h, h_rms)

    def critical_magnification(self, a_c: float) -> NDArray[np.float64]:
        """Where the contact area crosses ``a_c`` (see :func:`critical_magnification`)."""
        return critical_magnification(self.curve.zeta, self.curve.area, a_c)

    def separation_at(self, zeta_at: ArrayLike, *, rel_step: float = 1e-3) -> NDArray[np.float64]:
        """``u1 = d(A u_zeta)/dA`` [m] at per-load ``zeta_at`` (see
        :func:`separation_of_detaching_area`)."""
        cur = self.curve
        za = np.asarray(zeta_at, dtype=float).reshape(-1)
        ok = np.isfinite(za)
        out = np.full(self.p0.size, np.nan)
        if not ok.any():
            return out
        zc = np.where(ok, za, 2.0)
        zl = np.clip(zc * math.exp(-rel_step), 1.0, cur.zeta[-1])
        zh = np.clip(zc * math.exp(rel_step), 1.0, cur.zeta[-1])
        xs = np.log(np.stack([zl, zh], axis=1))  # (n_load, 2)
        N = cur.non_area_at(xs)
        A = 1.0 - N
        u = _sub_mean_gap(self.psd, self.E_star, self.phi, np.exp(xs) * self.q_L, A, self.q_hi)
        dA = N[:, 1] - N[:, 0]
        with np.errstate(divide="ignore", invalid="ignore"):
            u1 = (A[:, 0] * u[:, 0] - A[:, 1] * u[:, 1]) / dA
        out[ok] = np.maximum(u1[ok], 0.0)
        return out
