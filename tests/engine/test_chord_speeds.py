"""The ``cn`` mesh moves with the steps' chord speeds where a wall's speed is differenced
(:func:`xpersson.engine._cn_grading._chord_from`): on a wall whose acceleration jumps at knots
that no step boundary meets (a PCHIP table, as the ``jkr`` plugin's detachment wall), the
reported error estimate bounds the true error against a much finer solve.

With the walls' point speeds the knots inside steps left an error irregular in the step:
on these walls the estimate missed the true error up to 6.6x (err/tol up to 3) with 5-13x the
steps (``benchmarks/jkr_control.py`` measures the same on the speed design's ``jkr`` scenes).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.interpolate import PchipInterpolator

from xpersson.engine import Wall, solve
from xpersson.engine._cn_grading import _chord_from

TAU = np.geomspace(1e-2, 10.0, 12)
RTOL = 1e-5


def _wall(seed: int) -> Wall:
    """A detaching wall: ``-(0.5 + 0.6 sqrt(tau))`` [Pa] tabled as a PCHIP through 30 knots
    per decade, each value jittered by 0.3 % (the acceleration jumps at every knot)."""
    rng = np.random.default_rng(seed)
    t = np.concatenate([[0.0], np.geomspace(1e-3, 10.0, 121)])
    y = -(0.5 + 0.6 * np.sqrt(t)) * (1.0 + 3e-3 * rng.standard_normal(t.size))
    table = PchipInterpolator(t, y)
    return Wall.absorbing(lambda tau: table(np.clip(tau, 0.0, 10.0)))


@pytest.mark.parametrize("seed", [0, 2, 4])
def test_estimate_bounds_the_error_on_a_kinked_table(seed):
    wall = _wall(seed)
    res = solve(TAU, 1.0, wall, rtol=RTOL, method="cn")
    ref = solve(TAU, 1.0, wall, rtol=1e-3 * RTOL, method="cn", options={"max_work": 1e9})
    assert res.status == "success" and ref.status == "success"
    err = np.abs(res.area - ref.area)
    tol = RTOL * np.abs(ref.area) + 1e-7 * RTOL  # (atol: its default, 1e-7 rtol)
    assert np.all(err <= res.error_estimate)  # the estimate bounds the error
    assert np.all(err <= tol)  # and the tolerance holds
    assert np.max(ref.error_estimate / tol) < 1e-2  # (the reference is far finer)


def test_chord_speeds_only_where_a_speed_is_differenced():
    from xpersson.engine._problem import make_problem

    tau = np.geomspace(1e-2, 1.0, 4)
    moving = make_problem(tau, 1.0, Wall.absorbing(lambda t: -0.5 - t), None, 1e-6, None,
                          None, 10**5, {})  # fmt: skip
    linear = make_problem(tau, 1.0, Wall.linear(-0.5, -1.0), None, 1e-6, None, None, 10**5, {})
    fixed = make_problem(tau, 1.0, Wall.absorbing(-0.5), None, 1e-6, None, None, 10**5, {})
    assert _chord_from(moving, 0.25, ()) == 0.25  # from the march's start
    # declared motion or a fixed wall: point speeds up to the first graded zone, as before
    assert _chord_from(linear, 0.25, ()) == math.inf
    assert _chord_from(fixed, 0.25, ((0.5, 0.7),)) == 0.5
