"""The per-load reference of ``dmt``: Brent's method on the engine's map, one load at a time.

:func:`solve_dmt` solves ``p_rep = p0 + p_att(p_rep)`` for one load as the boundary did before
the batched path (:func:`._dmt_batch.solve_loads`, which the boundary uses); the tests compare
the two.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ._curves import curve_grid, increasing
from ._traction import attraction, attraction_quadrature, max_traction
from .dmt import DMTState

__all__ = ["solve_dmt"]


def solve_dmt(
    psd: Any,
    E_star: float,
    p0: float,
    tau_of_zeta: Any,
    zeta: np.ndarray,
    law: str,
    work: float,
    rng: float,
    rtol: float = 1e-6,
    guess: float | None = None,
) -> DMTState:
    """Solve ``p_rep = p0 + p_att(p_rep)`` for one load: the per-load reference.

    Brent's method on the map ``p_att`` evaluated through the core engine, one load at a time
    (the boundary itself uses :func:`._dmt_batch.solve_loads`; the tests compare the two).

    Parameters
    ----------
    psd : PowerSpectrum
        Roughness spectrum (Persson convention, m^4).
    E_star : float
        Contact modulus [Pa].
    p0 : float
        Nominal pressure [Pa] (tensile if negative).
    tau_of_zeta : callable
        Diffusion time [Pa^2] at magnifications [1] (the scene's clock).
    zeta : ndarray
        Output magnifications [1], from 1.
    law : {"dugdale", "lj93", "exponential"}
        Traction-gap law.
    work : float
        Work of adhesion [J/m^2], >= 0.
    rng : float
        Range of the law [m], > 0.
    rtol : float
        Relative tolerance of ``p_rep``.
    guess : float, optional
        A predicted ``p_rep`` [Pa] (from the solved neighbouring loads): for a compressive
        ``p0`` the root is then bracketed around it (:func:`_bracket_near`) instead of on
        ``[p0, p0 + max traction]``: fewer evaluations, the same root to ``rtol`` where the
        bracket holds one root.

    Raises
    ------
    ValueError
        No repulsive pressure balances a tensile ``p0`` (the load is beyond pull-off).
    """
    from xpersson.engine import Wall, solve
    from xpersson.physics.interface import detachment

    zeta = np.asarray(zeta, dtype=float)
    z = curve_grid(zeta)
    tau = np.asarray(tau_of_zeta(z), dtype=float)
    calls: dict[float, tuple[float, float, float, float]] = {}

    def p_att_on(zz: np.ndarray, tt: np.ndarray, p_rep: float) -> tuple[float, float, Any, Any]:
        zz, tt = increasing(zz, tt)
        res = solve(tt, p_rep, Wall.absorbing(0.0), rtol=min(rtol, 1e-8))
        area = np.clip(res.area, 0.0, 1.0)
        det = detachment(psd, E_star, p_rep, zz, area, non_area=res.non_area)
        if law == "lj93":
            pa, merr = attraction_quadrature(law, det, work, rng)
            return float(pa[0]), float(merr[0]), det, area
        return float(attraction(law, det, work, rng)[0]), 0.0, det, area

    def evaluate(p_rep: float) -> tuple[float, float, float, float]:
        if p_rep not in calls:
            p_att, mass, det, area = p_att_on(z, tau, p_rep)
            calls[p_rep] = (p_att, float(det.mean_gap[0]), mass, float(area[-1]))
        return calls[p_rep]

    def g(p_rep: float) -> float:
        return p_rep - p0 - evaluate(p_rep)[0]

    p_rep = p0 if work == 0.0 else _root(g, p0, law, work, rng, rtol, guess)
    if p_rep <= 0:
        raise ValueError(f"load.p0 = {p0:g} Pa: the DMT contact needs p_rep > 0 Pa")
    p_att, mgap, mass, area = evaluate(p_rep)
    resid = abs(p_rep - p0 - p_att) / max(abs(p0), p_rep)
    disc = 0.0
    if work > 0:
        z2 = curve_grid(zeta, per_decade=16)
        coarse = p_att_on(z2, np.asarray(tau_of_zeta(z2), dtype=float), p_rep)[0]
        disc = abs(coarse - p_att) / max(p_att, 1e-300)
    return DMTState(p0, p_rep, p_rep - p0, resid, len(calls), mgap, mass, area, disc)


def _root(
    g: Any, p0: float, law: str, work: float, rng: float, rtol: float, guess: float | None
) -> float:
    """The root ``p_rep`` [Pa] of ``g(p_rep) = p_rep - p0 - p_att(p_rep)`` (see
    :func:`solve_dmt`): ``p0`` itself where ``g(p0) >= 0``; otherwise Brent's method on a
    bracket (around ``guess``, or ``[p0, p0 + max traction]``; tensile ``p0``: scanned down
    from the maximum traction for the largest root)."""
    from scipy.optimize import brentq

    hi = max(p0, 0.0) + max_traction(law, work, rng)
    if p0 > 0 and g(p0) >= 0:
        return p0
    lo = p0 if p0 > 0 else None
    if lo is not None and guess is not None and lo < guess < hi:
        lo, hi = _bracket_near(g, lo, hi, guess)
    if lo is None:  # tensile: scan down from hi for the largest root
        p = hi
        for _ in range(64):
            p *= 0.5
            if g(p) < 0:
                lo = p
                break
            hi = p
        if lo is None:
            raise ValueError(
                f"load.p0 = {p0:g} Pa is beyond the DMT pull-off: no repulsive pressure "
                f"p_rep > 0 [Pa] balances p0 + p_att(p_rep) for law {law!r} "
                f"(work_of_adhesion = {work:g} J/m^2, range = {rng:g} m); allowed range: "
                "p0 above the pull-off stress"
            )
    return float(brentq(g, lo, hi, xtol=1e-300, rtol=max(rtol, 4 * np.finfo(float).eps)))


def _bracket_near(g: Any, lo: float, hi: float, guess: float) -> tuple[float, float]:
    """A bracket ``[a, b]`` of ``[lo, hi]`` around ``guess`` with ``g(a) < 0 <= g(b)`` [Pa].

    ``g(lo) < 0 < g(hi)`` holds on entry. The side of ``guess`` holding the sign change is
    searched with steps growing tenfold from ``1e-4 guess``; at worst the bracket is
    ``[lo, guess]`` or ``[guess, hi]``.
    """
    if g(guess) >= 0:
        step = 1e-4 * guess
        while guess - step > lo:
            if g(guess - step) < 0:
                return guess - step, guess
            step *= 10.0
        return lo, guess
    step = 1e-4 * guess
    while guess + step < hi:
        if g(guess + step) >= 0:
            return guess, guess + step
        step *= 10.0
    return guess, hi
