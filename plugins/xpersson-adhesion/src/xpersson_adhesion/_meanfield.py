"""Tabulated mean-field attraction ``p_att(p_rep)`` of one scene, its roots and pull-off.

The ``adhesive`` boundary solves ``p_rep = p0 + p_att(p_rep)`` (physics.md §2.3, DMT scheme):
Persson's elastic contact at the repulsive nominal pressure ``p_rep`` [Pa], the attraction
``p_att = int sigma(u) rho(u) du`` of a traction-gap law over the gap distribution ``rho`` of
that contact (:func:`xpersson.physics.interface.detachment`, the closed form of physics.md
§5.5a). For the elastic contact the area curve is closed form, ``A = erf(p_rep/(2 sqrt(tau)))``,
so ``p_att`` is evaluated for a whole vector of ``p_rep`` in one vectorised call; the scene's
curve is tabulated once (log-spaced ``p_rep``, the ratio ``k = p_att/p_rep`` interpolated by
PCHIP in ``ln p_rep``), and every load then costs a root of a scalar interpolant.

* Largest root: the branch reached from high loads (unloading), as ``dmt``.
* Pull-off: ``-min_p (p - p_att(p))`` when negative (``0``: no tensile load holds contact).
* Below the table's first node the ratio ``k`` is held constant (the small-load limit, where
  the contact, the gaps and hence ``p_att`` scale with ``p_rep``); above its last node
  ``p_att`` is evaluated directly.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.interpolate import PchipInterpolator
from scipy.optimize import brentq

from ._traction import attraction, max_traction

__all__ = ["attraction_curve", "MeanField"]

Array = NDArray[np.float64]
#: Nodes of the table per decade of p_rep, and its span below sqrt(tau_max) [decades]
#: (4 decades: contact fractions down to ~6e-5; below, ``k`` is held constant).
PER_DECADE = 6
SPAN_BELOW = 4.0
#: Light loads for the stickiness ratio: ``LIGHT[0] <= p_rep / sqrt(tau_max) <= LIGHT[1]``
#: (contact fractions 0.06-0.6 %: the plateau of ``k``; below, the closed-form gap
#: distribution's ``k`` wanders by tens of percent with the magnification grid).
LIGHT = (1e-3, 1e-2)


def attraction_curve(
    psd: object,
    E_star: float,
    zeta: Array,
    tau: Array,
    law: str,
    work: float,
    rng: float,
    p_rep: ArrayLike,
) -> Array:
    """``p_att`` [Pa] of the elastic contact at each repulsive pressure ``p_rep`` [Pa] (> 0).

    Parameters
    ----------
    psd : PowerSpectrum
        Roughness spectrum (Persson convention, m^4).
    E_star : float
        Contact modulus [Pa].
    zeta, tau : ndarray
        Magnifications [1] of the area curve and their diffusion times [Pa^2] (increasing).
    law : str
        Traction-gap law (``dugdale``, ``exponential``, ``lj93``).
    work, rng : float
        Work of adhesion [J/m^2] and range [m] of the law.
    p_rep : array_like
        Repulsive nominal pressures [Pa], > 0.
    """
    from scipy.special import erf, erfc

    from xpersson.physics.interface import detachment

    p = np.atleast_1d(np.asarray(p_rep, dtype=float))
    with np.errstate(divide="ignore"):
        x = p[:, None] / (2.0 * np.sqrt(tau[None, :]))
    det = detachment(psd, E_star, p, zeta, erf(x), non_area=erfc(x))
    return np.asarray(attraction(law, det, work, rng), dtype=float)


class MeanField:
    """Tabulated ``p_att(p_rep)`` of one scene (SI units).

    Parameters
    ----------
    evaluate : callable
        ``p_rep [Pa] (array) -> p_att [Pa] (array)``.
    scale : float
        Pressure scale of the contact, ``sqrt(tau(zeta_max))`` [Pa] (the table spans
        ``scale 10^-SPAN_BELOW`` to ``p_hi``).
    p_hi : float
        Largest repulsive pressure needed [Pa] besides ``10 scale`` (:func:`p_hi_of`).
    """

    def __init__(self, evaluate: Callable[[Array], Array], scale: float, p_hi: float) -> None:
        self._evaluate = evaluate
        self.scale = float(scale)
        lo = scale * 10.0**-SPAN_BELOW
        hi = max(p_hi, 10.0 * scale)
        n = max(8, int(math.ceil(PER_DECADE * math.log10(hi / lo))) + 1)
        self.p = np.geomspace(lo, hi, n)
        self.p_att = np.maximum(np.asarray(evaluate(self.p), dtype=float), 0.0)
        self.k = self.p_att / self.p
        self._spline = PchipInterpolator(np.log(self.p), self.k, extrapolate=False)

    def __call__(self, p_rep: ArrayLike) -> Array:
        """``p_att`` [Pa] at ``p_rep`` [Pa] (> 0)."""
        p = np.atleast_1d(np.asarray(p_rep, dtype=float))
        k = np.where(p <= self.p[0], self.k[0], self._spline(np.log(np.maximum(p, self.p[0]))))
        out = k * p
        above = p > self.p[-1]
        if np.any(above):
            out[above] = np.maximum(self._evaluate(p[above]), 0.0)
        return out

    @property
    def small_load_ratio(self) -> float:
        """``k0``: the largest ``p_att/p_rep`` at light loads [1]; > 1: sticky (tension held).

        Light loads: the table's nodes with ``p_rep / sqrt(tau_max)`` in :data:`LIGHT`
        (contact area 0.06-0.6 %), where ``k`` has its plateau.
        """
        x = self.p / self.scale
        light = (x >= LIGHT[0]) & (x <= LIGHT[1])
        return float(np.max(self.k[light])) if np.any(light) else float(self.k[0])

    def pull_off(self) -> float:
        """Pull-off stress [Pa]: ``-min (p - p_att(p))`` over the table, or 0."""
        g = self.p - self.p_att
        i = int(np.argmin(g))
        if g[i] >= 0.0:
            return 0.0
        lo, hi = self.p[max(i - 1, 0)], self.p[min(i + 1, self.p.size - 1)]
        fine = np.geomspace(lo, hi, 33)
        return float(max(-np.min(fine - self(fine)), -g[i]))

    def root(self, p0: float) -> float:
        """Largest ``p_rep`` [Pa] with ``p_rep - p_att(p_rep) = p0``.

        Raises
        ------
        ValueError
            When no positive root exists (a tensile or zero load beyond pull-off).
        """
        if p0 > self.p[-1]:
            hi = p0 + float(self(np.array([p0]))[0]) + 1.0
            return brentq(lambda x: x - float(self(np.array([x]))[0]) - p0, p0, hi, rtol=1e-12)
        g = self.p - self.p_att - p0
        neg = np.where(g < 0.0)[0]
        if neg.size == 0:
            if p0 > 0.0 and self.k[0] < 1.0:  # the root lies below the first node (linear law)
                return p0 / (1.0 - self.k[0])
            raise ValueError(f"no repulsive pressure p_rep > 0 balances p0 = {p0:g} Pa")
        i = int(neg[-1])
        if i == self.p.size - 1:
            raise ValueError(f"p0 = {p0:g} Pa lies above the attraction table")
        return brentq(
            lambda x: x - float(self(np.array([x]))[0]) - p0,
            self.p[i],
            self.p[i + 1],
            rtol=1e-12,
        )


def p_hi_of(loads: ArrayLike, law: str, work: float, rng: float) -> float:
    """Upper end of the table [Pa] beside its floor ``10 sqrt(tau_max)`` (:class:`MeanField`).

    Above ``p_rep = 10 sqrt(tau_max)`` the gaps cover ``erfc(5) = 1.5e-12`` of the nominal
    area, so ``p_att <= erfc(5) T`` (``T`` the law's maximum traction) and every root there lies
    below ``max(p0, 0) + erfc(5) T``. (Bounding by ``p0 + T`` instead made the table span
    ``T`` = 100 MPa for a 0.5 nm range: twice the nodes for nothing.)
    """
    from scipy.special import erfc

    top = float(max(np.max(np.asarray(loads, dtype=float)), 0.0))
    return top + float(erfc(5.0)) * max_traction(law, work, rng)
