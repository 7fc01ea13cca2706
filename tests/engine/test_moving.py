"""Moving walls: linear wall vs exact (§2.2), yield closure identities and its fixed-wall limit."""

from __future__ import annotations

import numpy as np
import pytest

from xpersson.engine import Wall, exact, solve

P0, S0, C = 0.5, 0.2, 1.0


def test_linear_wall_area_and_density_match_exact():
    tau = np.logspace(-3, 0, 13)
    p = np.linspace(-1.0, 4.0, 201)
    res = solve(tau, P0, Wall.linear(-S0, -C), None, rtol=1e-6, method="cn", p_out=p)
    assert res.status == "success", res.message
    ex = exact.linear_wall_area(tau, P0, S0, C)
    assert np.max(np.abs(res.area / ex - 1)) <= 1e-5
    P_ex = exact.linear_wall_density(p[None, :], tau[:, None], P0, S0, C)
    err = np.abs(res.P - P_ex).max(axis=1) / P_ex.max(axis=1)
    assert np.max(err) <= 1e-5
    # the error estimate bounds the true error
    assert np.all(np.abs(res.area - ex) <= res.error_estimate + 1e-15)
    # balances: probability and load + int p_w d(absorbed) = p0
    assert np.max(np.abs(res.probability_balance)) < 1e-4
    assert np.max(np.abs(res.load_balance)) < 1e-4
    np.testing.assert_allclose(res.wall_lower, -(S0 + C * tau))


def test_auto_uses_the_exact_linear_wall():
    tau = np.array([0.01, 0.1, 1.0])
    res = solve(tau, P0, Wall.linear(-S0, -C))
    assert res.method == "exact"
    np.testing.assert_allclose(res.area, [0.9999994776, 0.9185595730, 0.5953292117], rtol=2e-10)
    assert np.max(np.abs(res.load_balance)) < 1e-13
    # a plain callable that is affine is recognised too
    res2 = solve(tau, P0, Wall.absorbing(lambda t: -(S0 + C * t)))
    assert res2.method == "exact"
    np.testing.assert_allclose(res2.area, res.area, rtol=1e-13)


@pytest.mark.parametrize("c", [-2.0, 5.0])
def test_linear_wall_fast_walls(c):
    tau = np.logspace(-3, 0, 7)
    res = solve(tau, P0, Wall.absorbing(lambda t: -(S0 + c * t)), rtol=1e-4, method="cn")
    ex = exact.linear_wall_area(tau, P0, S0, c)
    assert res.status == "success", res.message
    assert np.max(np.abs(res.area / ex - 1)) <= 1e-4
    assert np.all(res.area >= 0) and np.all(np.isfinite(res.area))


def _yield(eps, y0=1.0):
    return Wall.yield_closure(lambda t: y0 + eps * t, lambda t: eps + 0.0 * t)


def test_yield_closure_conservation_identities():
    tau = np.logspace(-3, 1, 9)
    y = lambda t: 0.4 + 2.0 * t  # noqa: E731  fast rising yield wall
    res = solve(
        tau, 0.3, Wall.absorbing(0.0), Wall.yield_closure(y, lambda t: 2.0 + 0 * t), rtol=1e-6
    )
    assert res.method == "cn" and res.status == "success", res.message
    # int P + A_pl + A_non = 1
    tot = res.area + res.absorbed_upper + res.absorbed_lower
    np.testing.assert_allclose(tot, 1.0, atol=1e-6)
    np.testing.assert_allclose(res.probability_balance, tot - 1.0, atol=1e-15)
    # int p P + Y A_pl = p0  (lower wall at 0 adds nothing)
    force = res.load + y(tau) * res.absorbed_upper
    np.testing.assert_allclose(force, 0.3, rtol=1e-6)
    assert np.max(np.abs(res.load_balance)) < 1e-6
    assert np.all(res.absorbed_upper >= 0)


def test_yield_closure_converges_to_fixed_two_wall_solution():
    tau = np.array([0.01, 0.03, 0.1, 0.3, 1.0])
    ex = exact.two_wall_area(tau, 0.3, 0.0, 1.0)
    apl = exact.two_wall_absorbed(tau, 0.3, 0.0, 1.0)[1]
    diffs = []
    for eps in (1e-1, 1e-2, 1e-3):
        res = solve(tau, 0.3, Wall.absorbing(0.0), _yield(eps), rtol=1e-5)
        assert res.status == "success", res.message
        diffs.append(max(np.max(np.abs(res.area - ex)), np.max(np.abs(res.absorbed_upper - apl))))
    # O(eps) convergence
    assert diffs[1] < 0.15 * diffs[0] and diffs[2] < 0.15 * diffs[1]
    assert diffs[2] < 1e-3
    # a fixed yield wall is an absorbing wall (exact path, A_pl = absorbed at the wall)
    res = solve(tau, 0.3, Wall.absorbing(0.0), Wall.yield_closure(1.0))
    assert res.method == "exact"
    np.testing.assert_allclose(res.absorbed_upper, apl, rtol=1e-12)


def test_adhesion_like_receding_wall_load_identity():
    # sigma_a growing like sqrt(tau): wall at -a sqrt(tau) (not linear -> numerical path)
    tau = np.logspace(-2, 2, 9)
    wall = Wall.absorbing(lambda t: -0.3 - 0.5 * np.sqrt(t))
    res = solve(tau, 0.2, wall, rtol=1e-5)
    assert res.method == "cn" and res.status == "success", res.message
    assert np.all(np.diff(res.area) < 0)
    assert np.max(np.abs(res.probability_balance)) < 1e-4
    assert np.max(np.abs(res.load_balance)) < 1e-4
    # load exceeds p0 by the tensile stress left behind: load = p0 - int p_w d(absorbed) > p0
    assert np.all(res.load[1:] > 0.2)
