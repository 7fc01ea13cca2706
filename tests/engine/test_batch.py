"""solve_batch: one call for many loads gives what solve gives each load; EngineBatch."""

from __future__ import annotations

import numpy as np
import pytest

from xpersson.engine import EngineBatch, EngineResult, Wall, solve, solve_batch

TAU = np.concatenate([[0.0], np.logspace(-3, 1.5, 12)])
P0 = np.array([0.3, 1.0, 2.5])
FIELDS = (
    "area",
    "non_area",
    "absorbed_lower",
    "absorbed_upper",
    "load",
    "wall_lower",
    "wall_upper",
    "error_estimate",
    "probability_balance",
    "load_balance",
)


@pytest.mark.parametrize(
    ("walls", "method", "tau"),
    [
        ((Wall.absorbing(0.0), None), "auto", TAU),
        ((Wall.absorbing(-0.5), Wall.absorbing(4.0)), "auto", TAU),
        ((Wall.absorbing(0.0), None), "sine", TAU),
        ((Wall.absorbing(0.0), Wall.absorbing(4.0)), "sine", TAU),
        ((Wall.linear(-0.2, -1.0), None), "auto", TAU),
        ((Wall.absorbing(lambda t: -(0.2 + t)), None), "cn", TAU[:8]),
    ],
)
def test_batch_equals_per_load_solves(walls, method, tau):
    p = np.linspace(-1.0, 5.0, 9)
    batch = solve_batch(tau, P0, walls, method=method, rtol=1e-4, p_out=p)
    assert isinstance(batch, EngineBatch) and len(batch) == P0.size
    assert batch.area.shape == (P0.size, tau.size) and batch.P.shape == (P0.size, tau.size, 9)
    for i, p0 in enumerate(P0):
        one = solve(tau, p0, *walls, method=method, rtol=1e-4, p_out=p)
        got = batch[i]
        assert isinstance(got, EngineResult)
        assert (got.status, got.method) == (one.status, one.method)
        if method == "cn":  # one grid for the batch (the finest any load needs): same accuracy
            assert np.all(np.abs(got.area - one.area) <= 2e-4 * got.area + 2e-10)
            continue
        for name in FIELDS:
            np.testing.assert_allclose(
                getattr(got, name), getattr(one, name), rtol=1e-12, atol=1e-14 * max(1.0, p0)
            )
        np.testing.assert_allclose(got.P, one.P, rtol=1e-12, atol=1e-14)


def test_batch_sequence_protocol_and_per_load_walls():
    walls = [
        (Wall.absorbing(0.0), None),
        (Wall.absorbing(0.0), Wall.absorbing(3.0)),
        (Wall.absorbing(0.0), None),
    ]
    batch = solve_batch(TAU, P0, walls)
    assert [r.method for r in batch] == ["exact"] * 3
    assert batch[-1].area is not None and np.array_equal(batch[-1].area, batch[2].area)
    assert [r.p0 if hasattr(r, "p0") else None for r in batch[:2]] == [None, None]
    assert np.isinf(batch.wall_upper[0]).all() and np.all(batch.wall_upper[1] == 3.0)
    np.testing.assert_allclose(batch[1].area, solve(TAU, 1.0, upper=Wall.absorbing(3.0)).area)
    with pytest.raises(IndexError):
        batch[3]
    with pytest.raises(ValueError, match="walls"):
        solve_batch(TAU, P0, walls[:2])


def test_batch_validates_every_load_before_work():
    with pytest.raises(ValueError, match=r"p0 \[Pa\].*above the lower wall"):
        solve_batch(TAU, [1.0, -1.0])
    with pytest.raises(ValueError, match=r"tau_out \[Pa\^2\]"):
        solve_batch(np.ones((2, 3)), P0)


def _rising_wall(y0: float, speed: float) -> Wall:
    return Wall.yield_closure(lambda t: y0 + speed * t, lambda t: speed + 0.0 * t)


def test_moving_wall_that_stays_clear_takes_the_exact_path():
    tau = np.logspace(-4, 0, 9)
    far = _rising_wall(40.0, 5.0)  # never within reach of a mass of width ~ sqrt(2 tau) <= 1.4
    res = solve(tau, 1.0, Wall.absorbing(0.0), far)
    assert res.method == "exact" and res.success
    np.testing.assert_allclose(res.area, solve(tau, 1.0).area, rtol=1e-14)
    np.testing.assert_array_equal(res.absorbed_upper, 0.0)
    np.testing.assert_allclose(res.wall_upper, 40.0 + 5.0 * tau)  # the real wall is reported
    near = _rising_wall(1.5, 0.5)  # reached: the numerical path
    assert solve(tau, 1.0, Wall.absorbing(0.0), near, rtol=1e-3).method == "cn"


def test_cn_conserves_probability_exactly_and_keeps_area_at_most_one():
    tau = np.logspace(-4, 1, 11)
    res = solve(tau, 0.3, Wall.absorbing(0.0), _rising_wall(0.35, 2.0), rtol=1e-4)
    assert res.method == "cn" and res.success, res.message
    # finite volumes: only the mass leaving through the artificial window edges is unaccounted
    assert np.max(np.abs(res.probability_balance)) < 1e-10
    assert np.all(res.area <= 1.0) and np.all(res.area >= 0.0)
    assert np.all(res.absorbed_upper >= 0.0)  # A_pl (a rising wall gives mass back: P(Y) > 0)


@pytest.mark.parametrize("rtol", [1e-3, 1e-5])
def test_cn_error_is_aimed_at_the_request(scene_mod, rtol):
    sc = scene_mod.make_scene("realistic")
    res = solve(sc.tau(sc.zeta_out()), sc.p_bar, method="cn", rtol=rtol)
    err = scene_mod.curve_error(sc, res.area)
    assert res.success and 0.05 <= err / rtol <= 1.0, (err / rtol, res.message)
    # the estimate (about twice the asymptotic error) bounds the error and is not pessimistic
    rel_est = np.max(res.error_estimate / res.area)
    assert err <= rel_est <= 10 * err


def test_cn_work_budget_is_reported():
    moving = Wall.absorbing(lambda t: -0.1 * np.sqrt(t))
    r = solve(np.logspace(-3, 1, 5), 1.0, moving, rtol=1e-8, options={"max_work": 1e5})
    assert r.status == "max_steps" and "max_work" in r.message


def test_cn_aim_moves_the_error_inside_the_tolerance(scene_mod):
    """options['aim']: a smaller aim buys a finer grid and a smaller error, both inside rtol."""
    sc = scene_mod.make_scene("realistic")
    tau = sc.tau(sc.zeta_out())
    fine = solve(tau, sc.p_bar, method="cn", rtol=1e-4, options={"aim": 0.05})
    default = solve(tau, sc.p_bar, method="cn", rtol=1e-4)
    e_fine, e_def = (scene_mod.curve_error(sc, r.area) for r in (fine, default))
    assert fine.success and default.success
    assert fine.n_nodes > default.n_nodes and e_fine < e_def <= 1e-4


def test_cn_output_snapshots_equal_the_per_output_reductions(monkeypatch):
    """The march reduces output snapshots after the loop unless they would be large; both
    paths give the same areas, absorbed fractions and loads (a batch of loads)."""
    import xpersson.engine._moving as moving

    wall = Wall.absorbing(lambda t: -(0.2 + t))
    a = solve_batch(TAU[:8], P0, (wall, None), method="cn", rtol=1e-4)
    monkeypatch.setattr(moving, "_SNAP", 0)
    b = solve_batch(TAU[:8], P0, (wall, None), method="cn", rtol=1e-4)
    np.testing.assert_array_equal(a.area, b.area)
    np.testing.assert_array_equal(a.absorbed_lower, b.absorbed_lower)
    np.testing.assert_allclose(a.load, b.load, rtol=1e-13)


@pytest.mark.parametrize("aim", [0.0, -0.5, 1.5, float("nan")])
def test_cn_aim_outside_its_range_is_refused(aim):
    with pytest.raises(ValueError, match=r"options\['aim'\] \[1\].*\(0, 1\]"):
        solve(TAU[:5], 1.0, Wall.absorbing(lambda t: -(0.2 + t)), method="cn", options={"aim": aim})
