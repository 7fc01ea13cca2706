"""Walls that provably stay clear of the distribution: drop them and take the exact path.

A moving upper wall ``Y(tau)`` (yield closure or absorbing) that never comes near the mass
changes nothing the tolerance can see; the problem is then the one-wall (or two fixed walls)
problem with a closed form.  "Provably": the probability that a free path started at ``p0``
(variance ``2 tau``) reaches the wall before ``tau_max`` is bounded, for a non-decreasing wall,
by the union over intervals ``[t_{i-1}, t_i]`` of the reflection-principle bound

    P(max_{s <= t_i} B_s >= Y(t_{i-1})) = erfc((Y(t_{i-1}) - p0) / (2 sqrt(t_i))),

and the wall changes the area, the absorbed fractions and the load by at most that probability
(paths that never touch it are unaffected).  The wall is dropped when the bound is below
``0.1 atol``; the bound is added to the error estimate.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from scipy.special import erfc

from ._problem import Problem, sample_times

__all__ = ["drop_clear_upper", "hit_bound"]


def hit_bound(problem: Problem) -> float:
    """Upper bound of the probability that the mass reaches the moving upper wall (or inf)."""
    up = problem.upper
    if up is None or up.is_fixed:
        return float("inf")
    t_max = problem.tau_max
    if not t_max > 0:
        return 0.0
    # the input checks' times (0, 96 log-spaced times over 16 decades, 65 equal steps, the
    # output times): a costly wall (an inverted clock) has just been evaluated there
    t = sample_times(problem.tau)
    y = up.at(t)
    if not np.all(np.isfinite(y)) or np.any(np.diff(y) < 0):
        return float("inf")  # not provably non-decreasing on the samples: no claim
    p0 = float(np.max(problem.p0))
    gap = y[:-1] - p0
    if np.any(gap <= 0):
        return float("inf")
    return float(np.sum(erfc(gap / (2.0 * np.sqrt(t[1:])))))


def drop_clear_upper(problem: Problem) -> tuple[Problem, float] | None:
    """``(problem without the upper wall, bound)`` when the moving upper wall stays clear."""
    bound = hit_bound(problem)
    if not bound <= 0.1 * problem.atol:
        return None
    return dataclasses.replace(problem, upper=None), bound
