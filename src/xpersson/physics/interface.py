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
from functools import lru_cache

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.interpolate import CubicSpline
from scipy.special import erf

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

_TINY = 1e-300
_SQRT2 = math.sqrt(2.0)
_GL_ORDER = 6


# -- quadrature ---------------------------------------------------------------------------------
@lru_cache(maxsize=16)
def _gauss(n: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Gauss-Legendre nodes and weights on ``[0, 1]``."""
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (x + 1.0), 0.5 * w


def _panels(edges: NDArray[np.float64], n: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    x, w = _gauss(n)
    a, b = edges[:-1, None], edges[1:, None]
    return (a + (b - a) * x).ravel(), ((b - a) * w).ravel()


@dataclass(frozen=True)
class _QRule:
    q: NDArray[np.float64]  # nodes [1/m]
    weights: NDArray[np.float64]  # [1/m]
    C: NDArray[np.float64]  # C(q) [m^4]
    w: NDArray[np.float64]  # (pi int_{q_a}^q q'^3 C)^(-1/2) [1]
    dI3: NDArray[np.float64]  # int_{q_a}^q q'^3 C [1]


def _q_rule(
    psd: object, q_a: float, q_b: float, *, n_s: int = 36, panels_per_decade: int = 6
) -> _QRule:
    """Composite Gauss-Legendre rule on ``[q_a, q_b]`` exact for the ``w`` singularity at q_a.

    ``[q_a, q_m]`` (``q_m = min(1.5 q_a, next PSD breakpoint)``) with ``q = q_a + s^2`` and
    geometric panels towards ``s = 0``; above, panels uniform in ``ln q`` split at every PSD
    breakpoint (kinks of ``C``).
    """
    qa, qb = float(q_a), float(q_b)
    if qb <= qa * (1.0 + 1e-14):
        e = np.zeros(0)
        return _QRule(e, e, e, e, e)
    nodes = np.asarray(psd.nodes(), dtype=float)  # type: ignore[attr-defined]
    inner = nodes[(nodes > qa * (1.0 + 1e-12)) & (nodes < qb)]
    q_m = min(1.5 * qa, inner[0] if inner.size else qb, qb)
    s_m = math.sqrt(q_m - qa)
    s_edges = np.concatenate(([0.0], s_m * 0.5 ** np.arange(n_s, -1, -1)))
    s, ws = _panels(s_edges, 10)
    parts_q, parts_w = [qa + s * s], [2.0 * s * ws]
    brk = np.unique(np.concatenate(([q_m], inner[inner > q_m], [qb])))
    for lo, hi in zip(brk[:-1], brk[1:], strict=True):
        if hi <= lo * (1.0 + 1e-14):
            continue
        m = max(1, int(np.ceil(panels_per_decade * np.log10(hi / lo))))
        t, wt = _panels(np.linspace(np.log(lo), np.log(hi), m + 1), 10)
        parts_q.append(np.exp(t))
        parts_w.append(wt * np.exp(t))
    q = np.concatenate(parts_q)
    C = np.asarray(psd.C(q), dtype=float)  # type: ignore[attr-defined]
    dI3 = _delta_I3(psd, np.full(q.shape, qa), q)
    return _QRule(q, np.concatenate(parts_w), C, 1.0 / np.sqrt(np.pi * dI3), dI3)


def _delta_I3(psd: object, qa: NDArray[np.float64], q: NDArray[np.float64]) -> NDArray[np.float64]:
    """``int_{qa}^{q} q'^3 C dq'`` without cancellation for ``q`` close to ``qa``."""
    d = np.asarray(psd.I3(q), dtype=float) - np.asarray(psd.I3(qa), dtype=float)  # type: ignore[attr-defined]
    dq = q - qa
    small = dq < 1e-6 * qa
    if np.any(small):
        qm = qa[small] + 0.5 * dq[small]
        d[small] = dq[small] * qm**3 * np.asarray(psd.C(qm), dtype=float)  # type: ignore[attr-defined]
    return np.maximum(d, np.finfo(float).tiny)


def _tau_c(psd: object, E_star: float, q: ArrayLike) -> NDArray[np.float64]:
    return 0.25 * np.pi * E_star**2 * np.asarray(psd.I3(q), dtype=float)  # type: ignore[attr-defined]


def _rows(spl: CubicSpline, knots: NDArray[np.float64], xq: NDArray[np.float64]) -> NDArray:
    """Evaluate a spline fitted along axis 1 of ``(n_load, n_knot)`` data at per-load points.

    ``xq`` has shape ``(n_load, ...)``; row ``l`` is evaluated with load ``l``'s polynomial
    pieces (clamped to the knots' range).
    """
    shape = xq.shape
    x2 = np.clip(xq.reshape(shape[0], -1), knots[0], knots[-1])
    idx = np.clip(np.searchsorted(knots, x2, side="right") - 1, 0, knots.size - 2)
    c = spl.c  # (4, n_int, n_load)
    load = np.arange(shape[0])[:, None]
    d = x2 - knots[idx]
    val = ((c[0][idx, load] * d + c[1][idx, load]) * d + c[2][idx, load]) * d + c[3][idx, load]
    return val.reshape(shape)


# -- the solved curve ---------------------------------------------------------------------------
class _Curve:
    """Per-load curve ``F = A S`` on ``zeta``, interpolated in ``x = ln zeta``.

    ``1 - F`` is represented by a cubic spline of ``ln(1 - F)`` on the nodes after the first
    (exact near full contact, where ``1 - F`` spans decades between nodes) and linearly on the
    first interval (``F(1) = 1``).
    """

    def __init__(
        self,
        zeta: ArrayLike,
        area: ArrayLike,
        s_factor: ArrayLike | None,
        non_area: ArrayLike | None,
    ) -> None:
        z = np.asarray(zeta, dtype=float)
        A = np.atleast_2d(np.asarray(area, dtype=float))
        if z.ndim != 1 or z.size < 2 or A.shape[-1] != z.size:
            raise ValueError(
                f"zeta must be 1-D with >= 2 magnifications and area (..., {z.size}); got "
                f"zeta {z.shape}, area {A.shape}"
            )
        if not (abs(z[0] - 1.0) < 1e-12 and np.all(np.diff(z) > 0)):
            raise ValueError("zeta must increase from 1 (the curve starts at full contact)")
        if not np.all(np.isfinite(A)) or np.any(A < 0) or np.any(A > 1):
            raise ValueError("area fractions must be finite and lie in [0, 1]")
        N = 1.0 - A if non_area is None else np.atleast_2d(np.asarray(non_area, dtype=float))
        S = np.ones_like(A) if s_factor is None else np.broadcast_to(s_factor, A.shape)
        if np.any(~np.isfinite(S)) or np.any(S <= 0) or np.any(S > 1 + 1e-12):
            raise ValueError("s_factor must lie in (0, 1]")
        self.zeta = z
        self.x = np.log(z)
        self.area = A
        self.non_area = np.clip(N, 0.0, 1.0)
        self.F = A * S
        self.NF = np.clip(self.non_area + A * (1.0 - S), 0.0, 1.0)
        self.NF[:, 0] = 0.0
        y = np.log(np.maximum(self.NF, _TINY))
        self._y = y
        self._spl = CubicSpline(self.x[1:], y[:, 1:], axis=1) if z.size > 2 else None
        yA = np.log(np.maximum(self.non_area, _TINY))
        self._spl_a = CubicSpline(self.x[1:], yA[:, 1:], axis=1) if z.size > 2 else None

    @property
    def n_load(self) -> int:
        return self.area.shape[0]

    def non_area_at(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """``1 - A`` at per-load points ``x = ln zeta`` of shape (n_load, ...)."""
        x = np.asarray(x, dtype=float)
        x1 = self.x[1]
        lin = self.non_area[:, 1].reshape((-1,) + (1,) * (x.ndim - 1)) * np.clip(x / x1, 0, 1)
        if self._spl_a is None:
            return lin
        val = np.exp(np.minimum(_rows(self._spl_a, self.x[1:], x), 0.0))
        return np.clip(np.where(x < x1, lin, val), 0.0, 1.0)

    def nf(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """``1 - F`` at ``x = ln zeta`` (any shape), per load: shape ``(n_load,) + x.shape``."""
        x = np.asarray(x, dtype=float)
        x1 = self.x[1]
        lin = self.NF[:, 1].reshape((-1,) + (1,) * x.ndim) * np.clip(x / x1, 0.0, 1.0)
        if self._spl is None:
            return np.clip(lin, 0.0, 1.0)
        xs = np.clip(x, x1, self.x[-1])
        ys = np.minimum(self._spl(xs), 0.0)
        return np.where(x < x1, lin, np.exp(ys))

    def dF(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """``-dF/dx`` (>= 0) at ``x = ln zeta``, per load."""
        x = np.asarray(x, dtype=float)
        x1 = self.x[1]
        lin = (self.NF[:, 1] / x1).reshape((-1,) + (1,) * x.ndim) * np.ones_like(x)
        if self._spl is None:
            return lin
        xs = np.clip(x, x1, self.x[-1])
        ys = np.minimum(self._spl(xs), 0.0)
        dys = np.maximum(self._spl(xs, 1), 0.0)
        return np.where(x < x1, lin, np.exp(ys) * dys)

    def stieltjes_nodes(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Gauss-Legendre nodes ``x`` (n_int, m) and weights (n_int, m) per interval."""
        t, w = _gauss(_GL_ORDER)
        a, b = self.x[:-1, None], self.x[1:, None]
        return a + (b - a) * t, (b - a) * w


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


def _q_max(psd: object, zeta: NDArray[np.float64]) -> float:
    return min(float(psd.q_1), float(zeta[-1]) * float(psd.q_L))  # type: ignore[attr-defined]


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


# -- mean gap -----------------------------------------------------------------------------------
class _Phi:
    """``Phi(G) = int_0^G sqrt(G') (-dF)`` per load as a spline in ``s = ln tau_c``."""

    def __init__(self, psd: object, E_star: float, p0: NDArray[np.float64], cur: _Curve) -> None:
        q_L = float(psd.q_L)  # type: ignore[attr-defined]
        xg, wg = cur.stieltjes_nodes()
        sqrt_tau = np.sqrt(_tau_c(psd, E_star, np.exp(xg) * q_L))
        inc = np.sum(cur.dF(xg) * (sqrt_tau * wg)[None], axis=-1) / p0[:, None]
        phi = np.concatenate((np.zeros((cur.n_load, 1)), np.cumsum(inc, axis=1)), axis=1)
        tau = _tau_c(psd, E_star, cur.zeta * q_L)
        self.tau1 = float(tau[1])
        self.s = np.log(tau[1:])
        self.phi = phi
        self.p0 = p0
        self._spl = CubicSpline(self.s, phi[:, 1:], axis=1) if self.s.size > 1 else None
        self._tab: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None

    def at_tau(self, tau: NDArray[np.float64]) -> NDArray[np.float64]:
        """``Phi`` at ``G = tau/p0^2`` for every load (shared ``tau``): (n_load,) + tau.shape."""
        tau = np.asarray(tau, dtype=float)
        lin = self.phi[:, 1].reshape((-1,) + (1,) * tau.ndim) * np.clip(tau / self.tau1, 0, 1)
        if self._spl is None:
            return lin
        s = np.clip(np.log(np.maximum(tau, _TINY)), self.s[0], self.s[-1])
        return np.where(tau < self.tau1, lin, np.maximum(self._spl(s), 0.0))

    def at_tau_per_load(self, tau: NDArray[np.float64]) -> NDArray[np.float64]:
        """``Phi`` at per-load ``tau`` of shape (n_load, ...) (uniform-table look-up)."""
        tau = np.asarray(tau, dtype=float)
        shape = tau.shape
        t2 = tau.reshape(shape[0], -1)
        if self._spl is None:
            return (self.phi[:, 1:2] * np.clip(t2 / self.tau1, 0.0, 1.0)).reshape(shape)
        grid, table = self._table()
        n = grid.size
        with np.errstate(divide="ignore"):
            u = np.log(t2)
        u -= grid[0]
        u *= 1.0 / (grid[1] - grid[0])
        np.clip(u, 0.0, n - 1.000001, out=u)
        i = u.astype(np.intp)
        u -= i
        i += (np.arange(shape[0]) * n)[:, None]
        flat = table.ravel()
        v0 = flat.take(i)
        val = v0 + u * (flat.take(i + 1) - v0)
        low = t2 < self.tau1
        if low.any():
            lin = self.phi[:, 1:2] * np.clip(t2 / self.tau1, 0.0, 1.0)
            val = np.where(low, lin, val)
        return val.reshape(shape)

    def _table(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The spline sampled on a uniform grid in ``s`` (linear look-up error ~1e-6)."""
        if getattr(self, "_tab", None) is None:
            n = int(min(8192, max(1024, 64 * (self.s[-1] - self.s[0]))))
            grid = np.linspace(self.s[0], self.s[-1], n)
            self._tab = (grid, np.maximum(self._spl(grid), 0.0))  # type: ignore[misc]
        return self._tab


def _loads(p0: ArrayLike, n_load: int) -> NDArray[np.float64]:
    p = np.atleast_1d(np.asarray(p0, dtype=float)).ravel()
    if p.size != n_load or np.any(~(p > 0)) or np.any(~np.isfinite(p)):
        raise ValueError(f"p0 must hold {n_load} finite positive pressures [Pa], got {p0!r}")
    return p


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


# -- sub-problems at magnification zeta -----------------------------------------------------------
_SUB_EDGES = np.concatenate(([0.0], 0.4 ** np.arange(9, -1, -1)))


def _sub_mean_gap(
    psd: object,
    E_star: float,
    phi: _Phi,
    q_a: NDArray[np.float64],
    area_a: NDArray[np.float64],
    q_hi: float,
) -> NDArray[np.float64]:
    """Mean separation [m] of the apparent contact at ``q_a`` (n_load, n_a) under ``p0/A_a``.

    ``u_a = pi int_{q_a}^{q_hi} q^2 C w_a Phi(tau_a(q) A_a^2 / p0^2) dq`` with ``tau_a``, ``w_a``
    counted from ``q_a`` (physics.md §5.5a, §6.1). Vectorised: ``q = q_a exp(V s^2)``,
    ``V = ln(q_hi/q_a)``, graded Gauss-Legendre panels in ``s``.
    """
    s, ws = _panels(_SUB_EDGES, 6)
    qa = np.asarray(q_a, dtype=float)
    V = np.log(np.maximum(q_hi / qa, 1.0))
    q = qa[..., None] * np.exp(V[..., None] * s * s)
    dq = q * (2.0 * V[..., None] * s) * ws
    qaf = np.broadcast_to(qa[..., None], q.shape).ravel()
    dI3 = _delta_I3(psd, qaf, q.ravel()).reshape(q.shape)
    C = np.asarray(psd.C(q.ravel()), dtype=float).reshape(q.shape)  # type: ignore[attr-defined]
    kern = dq * q**2 * C / np.sqrt(np.pi * dI3)
    tau_eq = 0.25 * np.pi * E_star**2 * dI3 * (area_a**2)[..., None]
    tau_eq = np.broadcast_to(tau_eq, (phi.p0.size,) + tau_eq.shape[1:])
    vals = phi.at_tau_per_load(tau_eq)
    return math.pi * np.sum(vals * kern, axis=-1)


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


def _h2(psd: object, q: ArrayLike, q_hi: float) -> NDArray[np.float64]:
    m_hi = float(psd.running_moment(1.0, q_hi))  # type: ignore[attr-defined]
    m = np.asarray(psd.running_moment(1.0, np.minimum(q, q_hi)), dtype=float)  # type: ignore[attr-defined]
    return np.maximum(2.0 * math.pi * (m_hi - m), 0.0)


def _edges(cur: _Curve, zeta_edges: ArrayLike | None) -> tuple[NDArray, NDArray, NDArray]:
    """Bin edges with the contact area there (spline of ``ln(1 - A)`` between the nodes)."""
    if zeta_edges is None:
        return cur.zeta, cur.area, cur.non_area
    z = np.unique(np.clip(np.asarray(zeta_edges, dtype=float), 1.0, cur.zeta[-1]))
    if z[0] != 1.0 or z[-1] != cur.zeta[-1]:
        raise ValueError("zeta_edges must run from 1 to the curve's last magnification")
    x = np.log(z)
    N = cur.non_area_at(np.broadcast_to(x, (cur.n_load, x.size)))
    N = np.maximum.accumulate(N, axis=1)
    N[:, 0] = 0.0
    N[:, -1] = cur.non_area[:, -1]
    return z, 1.0 - N, N


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


def _pairs(det: Detachment, u: NDArray[np.float64]) -> tuple[NDArray, NDArray, NDArray]:
    h = np.maximum(det.h, _TINY)[None, :, None]
    return u[None, None, :], det.u1[:, :, None], h


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
        return Detachment(
            self.p0, z, A, ubar, np.where(ok, dA, 0.0), np.maximum(u1, 0.0), h, h_rms
        )

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
