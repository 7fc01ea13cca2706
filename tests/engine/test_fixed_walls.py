"""Numerical fixed-wall solvers against the closed forms (peer scenes, physics.md §3.1)."""

from __future__ import annotations

import numpy as np
import pytest

from xpersson.engine import Wall, exact, solve

SCENES = ("realistic", "extreme", "ultra", "lowH")


@pytest.mark.parametrize("name", SCENES)
@pytest.mark.parametrize("rtol", [1e-4, 1e-6, 1e-8])
def test_sine_one_wall_matches_mirrored_gaussian(scene_mod, name, rtol):
    sc = scene_mod.make_scene(name)
    tau = sc.tau(sc.zeta_out())  # Pa^2, physical units
    res = solve(tau, sc.p_bar, Wall.absorbing(0.0), None, rtol=rtol, method="sine")
    ex = exact.one_wall_area(tau, sc.p_bar)
    assert res.status == "success", res.message
    assert np.max(np.abs(res.area / ex - 1)) <= rtol
    assert np.all(res.error_estimate <= rtol * ex + res.error_estimate.min() + 1e-300)
    # reported balances are the identities' residuals (wall at 0: load/p0 - 1)
    np.testing.assert_allclose(res.load_balance, res.load / sc.p_bar - 1, atol=1e-15)
    assert np.max(np.abs(res.probability_balance)) < 1e-12
    assert np.max(np.abs(res.load_balance)) < 1e-9


@pytest.mark.parametrize("name", SCENES)
def test_cn_on_fixed_wall_meets_rtol(scene_mod, name):
    sc = scene_mod.make_scene(name)
    tau = sc.tau(sc.zeta_out())
    res = solve(tau, sc.p_bar, Wall.absorbing(0.0), None, rtol=1e-4, method="cn")
    ex = exact.one_wall_area(tau, sc.p_bar)
    if res.status == "success":
        assert np.max(np.abs(res.area / ex - 1)) <= 1e-4
    else:  # an honest failure must say why
        assert res.message


@pytest.mark.parametrize("rtol", [1e-4, 1e-6, 1e-8])
def test_two_walls_check_values(rtol):
    sy = 2.5e6  # Pa
    tau = np.array([0.01, 0.1, 1.0]) * sy**2
    res = solve(tau, 0.3 * sy, Wall.absorbing(0.0), Wall.absorbing(sy), rtol=rtol, method="sine")
    assert res.status == "success"
    np.testing.assert_allclose(res.area, [0.9661044, 0.3839343, 5.32786e-5], rtol=6e-7)
    np.testing.assert_allclose(res.absorbed_upper, [7.43e-7, 0.1138744, 0.2999734], rtol=6e-4)
    ex = exact.two_wall_area(tau, 0.3 * sy, 0.0, sy)
    assert np.max(np.abs(res.area / ex - 1)) <= rtol
    # load identity: load + sigma_Y A_pl = p0
    np.testing.assert_allclose(res.load + sy * res.absorbed_upper, 0.3 * sy, rtol=1e-12)
    assert np.max(np.abs(res.load_balance)) < 1e-12


def test_sine_two_walls_over_many_decades_with_field():
    tau = np.logspace(-9, 1, 41)
    p = np.linspace(-0.2, 1.3, 301)
    res = solve(
        tau, 0.3, Wall.absorbing(-0.2), Wall.absorbing(1.3), rtol=1e-8, method="sine", p_out=p
    )
    ex = exact.two_wall_area(tau, 0.3, -0.2, 1.3)
    big = ex > 1e-300
    assert np.max(np.abs(res.area[big] / ex[big] - 1)) <= 1e-8
    P_ex = exact.two_wall_density(p[None, :], tau[:, None], 0.3, -0.2, 1.3)
    scale = P_ex.max(axis=1, keepdims=True)
    assert np.max(np.abs(res.P - P_ex) / scale) < 1e-8


def test_field_only_on_request():
    tau = np.array([0.0, 0.1, 1.0])
    r = solve(tau, 1.0)
    assert r.P is None and r.p is None
    p = np.linspace(0, 5, 11)
    r = solve(tau, 1.0, p_out=p)
    assert r.P.shape == (3, 11) and np.all(r.P[0] == 0)
    np.testing.assert_allclose(r.P[1:], exact.one_wall_density(p, tau[1:, None], 1.0))
    assert r.area[0] == 1.0 and r.non_area[0] == 0.0


def test_near_full_contact_non_area_is_accurate():
    tau = np.array([1e-3, 1e-2])
    r = solve(tau, 0.5)  # exact path
    np.testing.assert_allclose(r.non_area, exact.one_wall_non_area(tau, 0.5), rtol=1e-14)
    assert r.non_area[0] < 1e-25 and r.non_area[0] > 0
