"""Batch bookkeeping: identities reported as such, the whole-batch status screen, lazy walls."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

from xpersson.engine import Wall, exact, solve, solve_batch

TAU = np.concatenate([[0.0], np.logspace(-3, 1.5, 12)])
P0 = np.array([0.3, 1.0, 2.5])


@pytest.mark.parametrize("wall", [0.0, -0.4])
def test_one_wall_balances_are_reported_as_identities(wall):
    batch = solve_batch(TAU, P0, (Wall.absorbing(wall), None))
    assert batch.exact_balances.all()
    for name in ("probability_balance", "load_balance"):
        values = getattr(batch, name)
        assert values.shape == (P0.size, TAU.size)
        assert np.all(values == 0.0) and not values.flags.writeable
    # what the zeros stand for holds: erf + erfc = 1 and load = p0 - wall * non_area
    np.testing.assert_allclose(batch.area + batch.non_area, 1.0, rtol=0, atol=4e-16)
    np.testing.assert_allclose(batch.load, P0[:, None] - wall * batch.non_area, rtol=1e-15)
    np.testing.assert_array_equal(batch.area, exact.one_wall_area(TAU, P0[:, None], wall))
    # single solves still evaluate the residuals (round-off)
    one = solve(TAU, 1.0, Wall.absorbing(wall))
    assert np.max(np.abs(one.probability_balance)) < 1e-15


def test_two_walls_still_evaluate_their_balances():
    batch = solve_batch(TAU, P0, (Wall.absorbing(-0.5), Wall.absorbing(4.0)))
    assert not batch.exact_balances.any()
    np.testing.assert_allclose(
        batch.probability_balance,
        batch.area + batch.absorbed_lower + batch.absorbed_upper - 1.0,
        rtol=0,
        atol=0,
    )


def test_batch_screen_gives_the_per_load_status_when_the_tolerance_cannot_be_met():
    # 8 eps of the closed form exceeds rtol = 1e-17: every load fails, as each single solve
    batch = solve_batch(TAU, P0, rtol=1e-17, atol=1e-30)
    for i, p0 in enumerate(P0):
        one = solve(TAU, p0, rtol=1e-17, atol=1e-30)
        assert batch.status[i] == one.status == "tolerance_not_met"
        assert batch.message[i] == one.message
    ok = solve_batch(TAU, P0, rtol=1e-6)
    assert ok.status == ["success"] * P0.size


def test_dropped_moving_wall_is_reported_where_it_is():
    tau = np.logspace(-4, 0, 9)
    far = Wall.yield_closure(lambda t: 40.0 + 5.0 * t, lambda t: 5.0 + 0.0 * t)
    batch = solve_batch(tau, P0, (Wall.absorbing(0.0), far))
    assert batch.method == ["exact"] * P0.size
    np.testing.assert_allclose(batch.wall_upper, np.broadcast_to(40.0 + 5.0 * tau, (3, 9)))
    np.testing.assert_array_equal(batch.wall_lower, 0.0)
    np.testing.assert_allclose(batch[1].wall_upper, 40.0 + 5.0 * tau)
    again = pickle.loads(pickle.dumps(solve_batch(tau, P0, (Wall.absorbing(0.0), far))))
    np.testing.assert_allclose(again.wall_upper[2], 40.0 + 5.0 * tau)
