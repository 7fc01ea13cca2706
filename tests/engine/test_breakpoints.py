"""Declared wall breakpoints (``Wall.breakpoints``): the cn path's graded steps after them.

A breakpoint makes a step boundary, one-sided wall speeds and steps uniform in
``sqrt(tau - tau_b)`` with an implicit first step. On smooth walls this must not change the
answer: the image solution and the linear-wall check values of physics.md §2.2 still hold to
1e-6 with a breakpoint declared inside the range.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.special import erf

from xpersson.engine import Wall, solve

P0, S0, C = 0.5, 0.2, 1.0
TAUS = np.array([0.0, 0.01, 0.1, 1.0])
LINEAR_AREA = (0.9999994776, 0.9185595730, 0.5953292117)


@pytest.mark.parametrize("tb", [0.003, 0.05, 0.3])
def test_constant_wall_with_breakpoint_is_the_image_solution(tb):
    wall = Wall.absorbing(lambda t: np.full(np.shape(t), -S0), breakpoints=[tb])
    res = solve(TAUS, P0, wall, method="cn", rtol=1e-7)
    assert res.status == "success"
    exact = erf((P0 + S0) / (2.0 * np.sqrt(TAUS[1:])))
    np.testing.assert_allclose(res.area[1:], exact, rtol=0, atol=1e-6)


@pytest.mark.parametrize("tb", [0.003, 0.05, 0.3])
def test_linear_wall_with_breakpoint_check_values(tb):
    wall = Wall.absorbing(lambda t: -(S0 + C * np.asarray(t, float)), breakpoints=(tb,))
    res = solve(TAUS, P0, wall, method="cn", rtol=1e-7)
    assert res.status == "success"
    np.testing.assert_allclose(res.area[1:], LINEAR_AREA, rtol=0, atol=1e-6)


def test_breakpoints_are_validated():
    with pytest.raises(ValueError, match="breakpoints"):
        Wall.absorbing(lambda t: -np.asarray(t), breakpoints=[-1.0])
    w = Wall.absorbing(lambda t: -np.asarray(t)).with_breakpoints([0.2, 0.1, 0.2])
    assert w.breakpoints == (0.1, 0.2)
    assert Wall.absorbing(0.0, breakpoints=[1.0]).breakpoints == ()


def test_square_root_onset_meets_the_tolerance():
    """Wall at -S0 until tau_b, then -S0 - sqrt(tau - tau_b) (unbounded speed at tau_b): with
    the breakpoint declared, cn meets rtol 1e-5 (status success) and agrees with a rtol 1e-8
    solution within 10 rtol; the retreating wall absorbs less than the fixed one."""
    tb = 0.05

    def pos(t):
        return -S0 - np.sqrt(np.maximum(np.asarray(t, float) - tb, 0.0))

    wall = Wall.absorbing(pos, breakpoints=[tb])
    tau = np.geomspace(1e-3, 1.0, 13)
    ref = solve(tau, P0, wall, method="cn", rtol=1e-8, options={"levels": 14})
    res = solve(tau, P0, wall, method="cn", rtol=1e-5)
    assert ref.status == "success" and res.status == "success"
    np.testing.assert_allclose(res.area, ref.area, rtol=1e-4, atol=1e-9)
    after = tau > tb
    assert np.all(res.area[after] > erf((P0 + S0) / (2.0 * np.sqrt(tau[after]))))
