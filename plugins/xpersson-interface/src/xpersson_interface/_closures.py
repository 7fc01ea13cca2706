"""Contact-area laws of Persson 2001 and its correction-factor closures (physics.md §1.5).

Every closure keeps the mirrored-Gaussian pressure PDF and changes its variance; the contact area
is then a *universal function of* ``G = V_c / (2 p0^2)`` (dimensionless), independent of the
spectrum. :class:`AreaLaw` evaluates ``A(G)`` (vectorised), ``dA/dG``, the correction factor
``S(A)`` entering the elastic energy, and the inverse ``G(A)``.

* ``persson01``: ``A = erf(1 / (2 sqrt(G)))``, ``S = 1``.
* ``yp08`` (Yang & Persson 2008): ``dV/dV_c = S(A)``, ``S = gamma + (1 - gamma) A^2``.
* ``wm17`` (Wang & Muser 2017): same ODE, ``S = gamma - 2/9 A^2 + (11/9 - gamma) A^4``.
* ``xu24`` (Xu et al. 2024): algebraic ``V = [gamma + (1 - gamma) A] V_c``,
  ``S = gamma + (1 - gamma) A``.

The ODE closures are integrated once per ``gamma`` (LSODA, rtol 1e-11) and stored as a cubic
spline of ``A / A_persson01`` in ``ln G`` (a smooth ratio between 1 and ``1/sqrt(gamma)``).
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.integrate import solve_ivp
from scipy.interpolate import CubicSpline
from scipy.optimize import brentq
from scipy.special import erf, erfc, erfinv

__all__ = ["CLOSURES", "DEFAULT_GAMMA", "AreaLaw", "area_law"]

CLOSURES: tuple[str, ...] = ("persson01", "yp08", "wm17", "xu24")
DEFAULT_GAMMA: dict[str, float] = {"persson01": 1.0, "yp08": 0.45, "wm17": 5.0 / 9.0, "xu24": 0.45}
_LOG_G = np.linspace(math.log(1e-3), math.log(1e16), 761)


def _a_p01(G: NDArray[np.float64]) -> NDArray[np.float64]:
    Gs = np.where(G > 0, G, 1.0)
    return np.where(G > 0, erf(0.5 / np.sqrt(Gs)), 1.0)


def _da_p01(G: NDArray[np.float64]) -> NDArray[np.float64]:
    Gs = np.where(G > 0, G, 1.0)
    with np.errstate(under="ignore"):
        d = -np.exp(-0.25 / Gs) / (2.0 * math.sqrt(math.pi)) * Gs**-1.5
    return np.where(G > 0, d, 0.0)


def _s_factor(name: str, gamma: float, A: NDArray[np.float64]) -> NDArray[np.float64]:
    if name == "persson01":
        return np.ones_like(A)
    if name == "yp08":
        return gamma + (1.0 - gamma) * A * A
    if name == "wm17":
        return gamma - (2.0 / 9.0) * A * A + (11.0 / 9.0 - gamma) * A**4
    return gamma + (1.0 - gamma) * A  # xu24


@lru_cache(maxsize=32)
def _ratio_spline(name: str, gamma: float) -> CubicSpline:
    """Spline of ``ln(A_closure / A_persson01)`` versus ``ln G``."""
    G = np.exp(_LOG_G)
    if name == "xu24":
        A = np.empty_like(G)
        for i, g in enumerate(G):
            Vc = 2.0 * g
            A[i] = brentq(
                lambda a, Vc=Vc: a - erf(1.0 / math.sqrt(2.0 * (gamma + (1 - gamma) * a) * Vc)),
                1e-300,
                1.0,
                xtol=1e-300,
                rtol=1e-15,
            )
    else:

        def rhs(s: float, V: NDArray[np.float64]) -> list[float]:
            a = math.erf(1.0 / math.sqrt(2.0 * V[0]))
            return [math.exp(s) * float(_s_factor(name, gamma, np.array(a)))]

        # G <= 1e-3: A = 1 to double precision for every closure, so V = V_c there
        sol = solve_ivp(
            rhs,
            (_LOG_G[0] + math.log(2.0), _LOG_G[-1] + math.log(2.0)),
            [2.0 * G[0]],
            t_eval=_LOG_G + math.log(2.0),
            method="LSODA",
            rtol=1e-11,
            atol=1e-14 * 2.0 * G[0],
        )
        A = erf(1.0 / np.sqrt(2.0 * sol.y[0]))
    return CubicSpline(_LOG_G, np.log(A / _a_p01(G)))


class AreaLaw:
    """Contact area as a function of ``G`` for one closure.

    Parameters
    ----------
    closure : str
        One of :data:`CLOSURES`.
    gamma : float, optional
        Closure parameter [1]; default :data:`DEFAULT_GAMMA` of the closure. Ignored for
        ``persson01``.
    """

    def __init__(self, closure: str = "persson01", gamma: float | None = None) -> None:
        if closure not in CLOSURES:
            raise ValueError(f"closure must be one of {CLOSURES}, got {closure!r}")
        self.closure = closure
        self.gamma = float(DEFAULT_GAMMA[closure] if gamma is None else gamma)
        if closure != "persson01" and not 0.0 < self.gamma <= 1.0 + 1e-12:
            raise ValueError(f"gamma must lie in (0, 1], got {self.gamma}")
        self._spl = None if closure == "persson01" else _ratio_spline(closure, self.gamma)

    def _ratio(self, G: NDArray[np.float64], nu: int = 0) -> NDArray[np.float64]:
        lg = np.log(np.clip(G, 1e-300, None))
        lg_c = np.clip(lg, _LOG_G[0], _LOG_G[-1])
        val = self._spl(lg_c, nu)  # type: ignore[misc]
        if nu:
            val = np.where((lg < _LOG_G[0]) | (lg > _LOG_G[-1]), 0.0, val)
        return val

    def area(self, G: ArrayLike) -> NDArray[np.float64]:
        """Contact area fraction ``A/A0`` [1] at ``G`` [1] (``G = 0``: 1)."""
        G = np.asarray(G, dtype=float)
        a = _a_p01(G)
        if self._spl is None:
            return a
        return np.minimum(a * np.exp(self._ratio(G)), 1.0)

    def non_area(self, G: ArrayLike) -> NDArray[np.float64]:
        """Non-contact fraction ``1 - A/A0`` [1] without cancellation near full contact."""
        G = np.asarray(G, dtype=float)
        Gs = np.where(G > 0, G, 1.0)
        c = np.where(G > 0, erfc(0.5 / np.sqrt(Gs)), 0.0)
        if self._spl is None:
            return c
        lr = self._ratio(G)
        return np.clip(-np.expm1(lr) + np.exp(lr) * c, 0.0, 1.0)

    def darea_dG(self, G: ArrayLike) -> NDArray[np.float64]:
        """Derivative ``dA/dG`` [1] (analytic for persson01, spline derivative otherwise)."""
        G = np.asarray(G, dtype=float)
        d = _da_p01(G)
        if self._spl is None:
            return d
        r = np.exp(self._ratio(G))
        Gs = np.clip(G, 1e-300, None)
        return r * (d + _a_p01(G) * self._ratio(G, 1) / Gs)

    def S(self, A: ArrayLike) -> NDArray[np.float64]:
        """Correction factor ``S(A)`` [1] of the closure (1 for persson01)."""
        return _s_factor(self.closure, self.gamma, np.asarray(A, dtype=float))

    def G_of_area(self, a: float) -> float:
        """Inverse: the ``G`` [1] at which ``A(G) = a`` (``0 < a < 1``)."""
        if not 0.0 < a < 1.0:
            raise ValueError("area fraction must lie in (0, 1)")
        g0 = 0.25 / erfinv(a) ** 2  # persson01, exact
        if self._spl is None:
            return g0
        f = lambda lg: float(self.area(np.exp(lg))) - a  # noqa: E731
        lo, hi = math.log(g0) - 1.0, math.log(g0) + 3.0
        while f(lo) < 0:
            lo -= 2.0
        while f(hi) > 0:
            hi += 2.0
        return math.exp(brentq(f, lo, hi, xtol=1e-14))


def area_law(closure: str = "persson01", gamma: float | None = None) -> AreaLaw:
    """Return the :class:`AreaLaw` of ``closure`` (cached spline tables)."""
    return AreaLaw(closure, gamma)
