"""Correction-factor ("fudge factor") closures of Persson's elastic theory
(:cite:p:`yang2008,wang2017,xu2024`).

All variants keep the mirrored-Gaussian pressure PDF but replace its variance ``V_c = 2 tau_c``
(complete-contact variance) by an effective variance ``V = 2 tau_eff``; the contact area is
``A = erf(p0 / sqrt(2 V)) = erf(p0 / (2 sqrt(tau_eff)))``.

* ``"persson01"``: ``tau_eff = tau_c``.
* ``"yp08"`` (Yang & Persson 2008): ``d tau_eff / d tau_c = S(A)``, ``S = g + (1 - g) A^2``,
  default ``g = GAMMA_DEFAULT = 0.42``.
* ``"wm17"`` (Wang & Muser 2017): same ODE, ``S = g - (2/9) A^2 + (11/9 - g) A^4``,
  default ``g = 5/9``.
* ``"xu24"`` (Xu et al. 2024): algebraic, ``tau_eff = [g + (1 - g) A] tau_c``, solved as a fixed
  point, default ``g = GAMMA_DEFAULT``; its ``S`` factor (used in the strain energy) is
  ``g + (1 - g) A``.

The package-wide default ``gamma`` of the Yang-Persson correction factor is
:data:`GAMMA_DEFAULT` ``= 0.42`` (the value of the reference implementation; the 0.45 of some
published figures lies in the same fitted range 0.42-0.45 and is one parameter away). Every
plugin that offers a ``gamma`` defaults to it (WM17's 5/9 is part of that model's definition).

:func:`variance_factor` gives ``S = d tau_eff / d tau_c`` as a function of the running area for
every closure; the elastic energy of a closure is ``(pi E*/2) int q^2 C A S dq`` with it (for
Xu24 this *is* the authors' "hybrid" energy: ``tau_c dr/dtau_c`` adds their
``((1 - g)/E*) int A V_c/q dA`` term).

Because the ODE is autonomous in ``tau_c`` and ``A`` depends on ``tau_eff / p0^2`` only, every
closure gives ``tau_eff = p0^2 F(tau_c / p0^2)`` with a universal ``F`` of ``G = tau_c/p0^2``.
For the ODE closures ``F`` is computed once per ``(closure, gamma, rtol)`` (DOP853 with dense
output in ``s = ln G`` for the bounded ratio ``r = F(G)/G``, ``dr/ds = S(A(rG)) - r``) and cached,
then evaluated for all loads at once. The result is therefore the *continuum* solution,
independent of how finely ``tau_c`` is sampled.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.special import erf, erfinv

from ..cache import memoize

__all__ = [
    "CLOSURES",
    "DEFAULT_GAMMA",
    "GAMMA_DEFAULT",
    "closure_S",
    "effective_ratio",
    "effective_tau",
    "variance_factor",
]

#: Allowed closure names.
CLOSURES: tuple[str, ...] = ("persson01", "yp08", "wm17", "xu24")

#: The one package-wide default of the Yang-Persson ``gamma`` (yp08, xu24, analyses' S factor).
GAMMA_DEFAULT: float = 0.42

#: Default ``gamma`` per closure (``None``: no parameter).
DEFAULT_GAMMA: dict[str, float | None] = {
    "persson01": None,
    "yp08": GAMMA_DEFAULT,
    "wm17": 5.0 / 9.0,
    "xu24": GAMMA_DEFAULT,
}

# Below G_START, 1 - S < 1e-300 for every closure (erfc(1/(2 sqrt(G))) underflows), so
# tau_eff = tau_c to machine precision. Above G_END, r = F(G)/G has converged to its
# asymptote gamma to within ~1/(gamma G) relative, far below double precision.
_G_START = 1e-4
# WM17's S(A) = g - 2/9 A^2 + (11/9 - g) A^4 has a positive minimum over A in [0, 1] only for
# g > (11 - sqrt(117))/18 ~ 0.0102; below it V would decrease with zeta (unphysical).
_WM17_GAMMA_MIN = (11.0 - np.sqrt(117.0)) / 18.0
_G_END = 1e24
_XU24_MAXITER = 200


def _check(closure: str, gamma: float | None) -> float | None:
    if closure not in CLOSURES:
        raise ValueError(f"unknown closure {closure!r}; allowed: {', '.join(CLOSURES)}")
    if closure == "persson01":
        return None
    g = DEFAULT_GAMMA[closure] if gamma is None else float(gamma)
    if not (0.0 < g <= 1.0):  # also rejects NaN
        raise ValueError(f"gamma must lie in (0, 1], got {gamma!r}")
    if closure == "wm17" and not g > _WM17_GAMMA_MIN:
        raise ValueError(
            f"wm17 needs gamma > {_WM17_GAMMA_MIN:.6f} so that S(A) > 0, got {gamma!r}"
        )
    return g


def closure_S(closure: str, A: ArrayLike, gamma: float | None = None) -> NDArray[np.float64]:
    """Correction factor ``S(A)`` of a closure (dimensionless).

    Parameters
    ----------
    closure : {"persson01", "yp08", "wm17", "xu24"}
        Closure name.
    A : array_like
        Relative contact area(s) ``A/A0`` in ``[0, 1]``.
    gamma : float, optional
        Closure parameter in ``(0, 1]``; default :data:`DEFAULT_GAMMA` (ignored for
        ``persson01``).

    Returns
    -------
    ndarray
        ``S`` with the shape of ``A``: 1 (persson01), ``g + (1-g)A^2`` (yp08),
        ``g - 2/9 A^2 + (11/9 - g) A^4`` (wm17), ``g + (1-g) A`` (xu24, the ratio ``V/V_c``).
        ``S(1) = 1`` for all closures.
    """
    g = _check(closure, gamma)
    A_arr = np.asarray(A, dtype=float)
    if closure == "persson01":
        return np.ones_like(A_arr)
    assert g is not None
    if closure == "yp08":
        return g + (1.0 - g) * A_arr**2
    if closure == "wm17":
        A2 = A_arr**2
        return g - (2.0 / 9.0) * A2 + (11.0 / 9.0 - g) * A2**2
    return g + (1.0 - g) * A_arr  # xu24


def variance_factor(closure: str, A: ArrayLike, gamma: float | None = None) -> NDArray[np.float64]:
    """``S = d tau_eff / d tau_c`` along a closure's path, as a function of the area (1).

    Parameters
    ----------
    closure : {"persson01", "yp08", "wm17", "xu24"}
        Closure name.
    A : array_like
        Running contact area ``A/A0`` in ``[0, 1]`` of the closure itself.
    gamma : float, optional
        Closure parameter (default :data:`DEFAULT_GAMMA`).

    Returns
    -------
    ndarray
        ``S`` in ``(0, 1]``: :func:`closure_S` for the ODE closures (their definition), and for
        the algebraic Xu24 ``tau_eff = r tau_c``, ``r = g + (1 - g) A``,
        ``S = r + tau_c dr/dtau_c = r - (1 - g) x E / (2 (1 + (1 - g) x E / (2 r)))`` with
        ``x = erfinv(A)``, ``E = 2 exp(-x^2)/sqrt(pi)`` (implicit differentiation of
        ``A = erf(1/(2 sqrt(r G)))``).
    """
    g = _check(closure, gamma)
    A_arr = np.clip(np.asarray(A, dtype=float), 0.0, 1.0)
    if closure != "xu24":
        return closure_S(closure, A_arr, gamma)
    assert g is not None
    r = g + (1.0 - g) * A_arr
    x = erfinv(np.minimum(A_arr, 1.0 - 1e-16))
    xE = x * (2.0 / np.sqrt(np.pi)) * np.exp(-x * x)
    c = 1.0 - g
    return r - c * xE / (2.0 * (1.0 + c * xE / (2.0 * r)))


@memoize("physics.closure_ode", scope="process", maxsize=64)
def _ode_solution(closure: str, gamma: float, rtol: float):  # noqa: ANN202 - OdeSolution
    """Dense solution ``r(s)``, ``s = ln G``, of ``dr/ds = S(A(rG)) - r``, ``r(s0) = 1``."""

    def rhs(s: float, r: NDArray[np.float64]) -> NDArray[np.float64]:
        G = np.exp(s)
        # trial stages of large steps may overshoot below 0; r >= gamma on the true solution
        A = erf(0.5 / np.sqrt(np.maximum(r, 1e-300) * G))
        return closure_S(closure, A, gamma) - r

    s0, s1 = np.log(_G_START), np.log(_G_END)
    from scipy.integrate import solve_ivp  # lazily: scipy.integrate costs ~0.5 s to import

    sol = solve_ivp(
        rhs,
        (s0, s1),
        [1.0],
        method="DOP853",
        rtol=rtol,
        atol=rtol * 1e-2,
        dense_output=True,
    )
    if not sol.success:  # pragma: no cover - defensive
        raise RuntimeError(f"closure ODE integration failed: {sol.message}")
    return sol.sol, float(sol.y[0, -1])


def _xu24_ratio(G: NDArray[np.float64], gamma: float, tol: float = 1e-14) -> NDArray[np.float64]:
    """Solve ``r = g + (1-g) erf(1/(2 sqrt(r G)))`` for ``r`` in ``[g, 1]`` (vectorised).

    Safeguarded Newton: iterates stay inside a bracket that is updated by the sign of the
    residual; a bisection step replaces any Newton step that leaves the bracket.
    """
    shape = np.shape(G)
    G = np.asarray(G, dtype=float).ravel()
    lo = np.full(G.shape, gamma)
    hi = np.ones(G.shape)
    r = np.ones(G.shape)  # Persson01 start
    c = 1.0 - gamma
    two_over_sqrtpi = 2.0 / np.sqrt(np.pi)
    active = G > 0
    for _ in range(_XU24_MAXITER):
        if not np.any(active):
            break
        ra, Ga = r[active], G[active]
        x = 0.5 / np.sqrt(ra * Ga)
        F = ra - gamma - c * erf(x)
        dF = 1.0 + c * two_over_sqrtpi * np.exp(-x * x) * x / (2.0 * ra)
        lo_a = np.where(F < 0, ra, lo[active])
        hi_a = np.where(F > 0, ra, hi[active])
        rn = ra - F / dF
        bad = ~((rn >= lo_a) & (rn <= hi_a))
        rn = np.where(bad, 0.5 * (lo_a + hi_a), rn)
        rn = np.where(F == 0, ra, rn)
        step = np.abs(rn - ra)
        r[active], lo[active], hi[active] = rn, lo_a, hi_a
        done = (step <= tol * rn) | (F == 0) | (hi_a - lo_a <= tol * rn)
        idx = np.flatnonzero(active)
        active[idx[done]] = False
    r[G == 0] = 1.0
    return r.reshape(shape)


def effective_ratio(
    G: ArrayLike, closure: str, gamma: float | None = None, rtol: float = 1e-10
) -> NDArray[np.float64]:
    """Universal ratio ``r(G) = tau_eff / tau_c`` as a function of ``G = tau_c / p0^2``.

    Parameters
    ----------
    G : array_like
        ``tau_c / p0^2`` (dimensionless), >= 0.
    closure : {"persson01", "yp08", "wm17", "xu24"}
        Closure name.
    gamma : float, optional
        Closure parameter in ``(0, 1]`` (default :data:`DEFAULT_GAMMA`).
    rtol : float
        Relative tolerance of the ODE integration (ODE closures only).

    Returns
    -------
    ndarray
        ``r`` in ``[gamma, 1]``, shape of ``G``; ``r = 1`` for ``G <= 1e-4`` (full contact).
    """
    g = _check(closure, gamma)
    G_arr = np.asarray(G, dtype=float)
    if np.any(~(G_arr >= 0)) or np.any(~np.isfinite(G_arr)):
        raise ValueError("G must be finite and >= 0")
    if closure == "persson01":
        return np.ones_like(G_arr)
    assert g is not None
    if closure == "xu24":
        return _xu24_ratio(G_arr, g)
    if not 0.0 < rtol < 1e-3:
        raise ValueError("rtol must lie in (0, 1e-3)")
    sol, r_end = _ode_solution(closure, g, float(rtol))
    r = np.ones(G_arr.shape)
    mid = (G_arr > _G_START) & (G_arr < _G_END)
    if np.any(mid):
        r[mid] = sol(np.log(G_arr[mid]))[0]
    r[G_arr >= _G_END] = r_end
    return r


def effective_tau(
    tau_c: ArrayLike,
    p0: ArrayLike,
    closure: str,
    gamma: float | None = None,
    rtol: float = 1e-10,
) -> NDArray[np.float64]:
    """Effective diffusion time ``tau_eff = V/2`` [Pa^2] of a correction-factor closure.

    Parameters
    ----------
    tau_c : array_like, shape (n_zeta,)
        Complete-contact diffusion time ``tau_c(zeta) = (pi/4) E*^2 I3(zeta q_L)`` [Pa^2],
        non-decreasing, ``tau_c[0] >= 0`` (typically 0 at ``zeta = 1``). The ODE closures are
        integrated from ``tau_c = 0`` (``zeta = 1``), whatever ``tau_c[0]`` is.
    p0 : array_like, shape (n_load,)
        Nominal pressures [Pa], > 0.
    closure : {"persson01", "yp08", "wm17", "xu24"}
        Closure name.
    gamma : float, optional
        Closure parameter in ``(0, 1]``; defaults 0.42 (yp08, xu24), 5/9 (wm17).
    rtol : float
        Relative tolerance of the ODE solution (the Xu24 fixed point is solved to ~1e-14).

    Returns
    -------
    ndarray, shape (n_load, n_zeta)
        ``tau_eff`` [Pa^2] (general rule: shape ``p0.shape + tau_c.shape``). Use
        :func:`xpersson.physics.elastic.area_fraction` ``(p0[:, None], tau_eff)`` for ``A``.

    Raises
    ------
    ValueError
        Unknown closure, ``gamma`` outside ``(0, 1]``, negative/decreasing ``tau_c`` or
        non-positive ``p0``.
    """
    _check(closure, gamma)
    tc = np.asarray(tau_c, dtype=float)
    p = np.asarray(p0, dtype=float)
    if np.any(~(tc >= 0)) or np.any(~np.isfinite(tc)):
        raise ValueError("tau_c must be finite and >= 0")
    if tc.ndim == 1 and np.any(np.diff(tc) < 0):
        raise ValueError("tau_c must be non-decreasing along zeta")
    if np.any(~(p > 0)) or np.any(~np.isfinite(p)):
        raise ValueError("p0 must be finite and > 0")
    G = np.multiply.outer(1.0 / p**2, tc)
    if closure == "persson01":
        return np.broadcast_to(tc, G.shape).copy()
    return effective_ratio(G, closure, gamma, rtol) * tc
