"""Where the ``cn`` time plan grades its steps and moves its mesh with chord speeds: the
graded stretches after the walls' declared breakpoints, and the time from which the mesh
moves with each step's chord speed (see :mod:`._cn_plan`)."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ._problem import Problem

__all__ = ["_GRADE", "_chord_from", "_differenced", "_graded_zones"]

Array = NDArray[np.float64]


_GRADE = 4.0  # steps uniform in (tau - tau_b)^(1/_GRADE) after a wall breakpoint

_NO_TIMES = np.zeros(0)  # the graded times of a plan without breakpoints (read-only)
_NO_TIMES.setflags(write=False)


def _differenced(wall) -> bool:
    """Whether the speeds of ``wall`` are differences (:func:`._cn_plan._probe_times` gives
    times)."""
    fixed = wall is None or wall.is_fixed
    return not (fixed or wall.dposition is not None or wall.motion is not None)


def _chord_from(pb: Problem, tau_s: float, zones: tuple[tuple[float, float], ...]) -> float:
    """The time [Pa^2] from which the mesh moves with the steps' chord speeds (the edges'
    exact displacement over the step): from the march's start where a wall's speed is a
    difference of its positions (a position callable without a declared speed or motion:
    such a wall, e.g. the ``jkr`` plugin's PCHIP table of the detachment stress, may have
    kinks in its speed that no step boundary meets; the point speeds then leave an error
    irregular in the step that the Richardson control cannot see: on "roll H=0.69 3dec" of
    held-out seed 4242 of ``benchmarks/summary.py`` the fourth-order answer was 6x its
    estimate, see ``benchmarks/jkr_control.py``); else from the first graded zone (after a
    declared breakpoint; inf: none)."""
    if _differenced(pb.lower) or _differenced(pb.upper):
        return tau_s
    return zones[0][0] if zones else math.inf


def _graded_zones(
    pbs: list[Problem], tau_s: float, tau_end: float, ratio: float
) -> tuple[tuple[tuple[float, float], ...], Array]:
    """Graded stretches after the walls' declared breakpoints, and their step times.

    After a breakpoint ``tau_b`` the wall may move like ``sqrt(tau - tau_b)`` (unbounded speed):
    on ``[tau_b, tau_b + H]``, ``H = min(tau_b, tau_end - tau_b)``, the steps are uniform in
    ``u = (tau - tau_b)^(1/4)`` (in ``s = u^2`` the motion is smooth; the quartic grading also
    removes the ``ds^2 log`` term that uniform steps in ``s`` leave, so that the error has a
    clean second-order expansion for the Richardson control); at its end they match the
    geometric steps ``~ ratio tau``.
    """
    if not any(p.lower.breakpoints or (p.upper is not None and p.upper.breakpoints) for p in pbs):
        return (), _NO_TIMES  # (no breakpoint: no zone)
    bps = sorted(
        {
            float(t)
            for p in pbs
            for w in (p.lower, p.upper)
            if w is not None
            for t in getattr(w, "breakpoints", ())
            if tau_s <= t < tau_end  # (a one-wall start may end at a breakpoint)
        }
    )
    zones: list[tuple[float, float]] = []
    pts: list[Array] = []
    for i, tb in enumerate(bps):
        nxt = bps[i + 1] if i + 1 < len(bps) else tau_end
        h = min(tb, nxt - tb)
        n_g = max(2, int(math.ceil(_GRADE * (h / tb) ** (1 / _GRADE) / ratio)))
        pts.append(tb + h * (np.arange(n_g + 1) / n_g) ** _GRADE)
        zones.append((tb, tb + h))
    return tuple(zones), (np.concatenate(pts) if pts else np.zeros(0))
