"""Closed forms: published check values, image/sine agreement, identities."""

from __future__ import annotations

import numpy as np
import pytest

from xpersson.engine import exact


def test_two_wall_check_values_physics_3_1():
    t = np.array([0.01, 0.1, 1.0])  # units of sigma_Y^2, p0/sigma_Y = 0.3
    a_el = exact.two_wall_area(t, 0.3, 0.0, 1.0)
    _, a_pl = exact.two_wall_absorbed(t, 0.3, 0.0, 1.0)
    np.testing.assert_allclose(a_el, [0.9661044, 0.3839343, 5.32786e-5], rtol=6e-7)
    np.testing.assert_allclose(a_pl, [7.43e-7, 0.1138744, 0.2999734], rtol=6e-4)
    # large-tau limit: all load carried plastically
    assert exact.two_wall_absorbed(50.0, 0.3, 0.0, 1.0)[1] == pytest.approx(0.3, rel=1e-12)


@pytest.mark.parametrize("p0", [0.001, 0.3, 0.5, 0.97])
def test_images_and_sines_agree_to_1e12(monkeypatch, p0):
    tau = 4.0 * np.logspace(np.log10(0.02), np.log10(0.5), 60)  # both series converge here
    lo, up = -0.5, 1.5  # length 2
    outs = {}
    for name, switch in (("img", 1e9), ("sin", 0.0)):
        monkeypatch.setattr(exact, "_SWITCH", switch)
        p = np.linspace(lo, up, 41)
        outs[name] = (
            exact.two_wall_area(tau, p0, lo, up),
            *exact.two_wall_absorbed(tau, p0, lo, up),
            exact.two_wall_load(tau, p0, lo, up),
            exact.two_wall_density(p[None, :], tau[:, None], p0, lo, up),
        )
    for a, b in zip(outs["img"], outs["sin"], strict=True):
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12)


def test_two_wall_small_plastic_area_has_no_cancellation():
    # at tau = 1e-3 sigma_Y^2 the plastic area is ~1e-106: images give it to full precision
    a_pl = exact.two_wall_absorbed(1e-3, 0.3, 0.0, 1.0)[1]
    from scipy.special import erfc

    assert a_pl == pytest.approx(erfc(0.7 / (2 * np.sqrt(1e-3))), rel=1e-10)


def test_one_wall_identities_and_tails():
    tau = np.logspace(-6, 6, 49)
    a = exact.one_wall_area(tau, 1.0)
    non = exact.one_wall_non_area(tau, 1.0)
    np.testing.assert_allclose(a + non, 1.0, rtol=0, atol=2e-16)
    # load identity with a wall at w: load + w * absorbed = p0
    w = -0.4
    load = exact.one_wall_load(tau, 1.0, w)
    np.testing.assert_allclose(load + w * exact.one_wall_non_area(tau, 1.0, w), 1.0, atol=4e-16)
    # near full contact 1 - A from erfc, not 1 - erf
    assert exact.one_wall_non_area(1e-3, 1.0) == pytest.approx(8.4e-112, rel=0.05)
    # small load: A -> p0 / sqrt(pi tau)
    assert exact.one_wall_area(1e12, 1.0) == pytest.approx(1 / np.sqrt(np.pi * 1e12), rel=1e-9)


def test_one_wall_density_integrates_to_area():
    for t in (0.01, 1.0, 50.0):
        p = np.linspace(0, 2.0 + 20 * np.sqrt(2 * t), 200001)
        P = exact.one_wall_density(p, t, 2.0)
        assert np.trapezoid(P, p) == pytest.approx(float(exact.one_wall_area(t, 2.0)), rel=1e-8)
        assert np.trapezoid(p * P, p) == pytest.approx(2.0, rel=1e-8)


def test_linear_wall_check_values_physics_2_2():
    tau = np.array([0.01, 0.1, 1.0])
    a = exact.linear_wall_area(tau, 0.5, 0.2, 1.0)
    np.testing.assert_allclose(a, [0.9999994776, 0.9185595730, 0.5953292117], rtol=2e-10)
    assert exact.linear_wall_load(0.1, 0.5, 0.2, 1.0) == pytest.approx(0.5217495952, rel=2e-10)
    # c = 0 is the constant-sigma_a image solution: A = erf((p0 + s0) / (2 sqrt t))
    np.testing.assert_allclose(
        exact.linear_wall_area(tau, 0.5, 0.2, 0.0), exact.one_wall_area(tau, 0.5, -0.2), rtol=1e-14
    )


def test_linear_wall_density_load_and_balance():
    p0, s0, c = 0.5, 0.2, 1.0
    for t in (0.05, 0.7):
        pw = float(exact.linear_wall_position(t, s0, c))
        p = np.linspace(pw, p0 + 30 * np.sqrt(t), 400001)
        P = exact.linear_wall_density(p, t, p0, s0, c)
        assert P[0] == 0.0 and P.min() >= 0
        a = float(exact.linear_wall_area(t, p0, s0, c))
        assert np.trapezoid(P, p) == pytest.approx(a, rel=1e-8)
        load = float(exact.linear_wall_load(t, p0, s0, c))
        assert np.trapezoid(p * P, p) == pytest.approx(load, rel=1e-8)
        # load + int p_w d(absorbed) = p0
        mom = float(exact.linear_wall_absorbed_moment(t, p0, s0, c))
        assert load + mom == pytest.approx(p0, abs=1e-13)


@pytest.mark.parametrize("c", [-30.0, -3.0, 3.0, 30.0])
def test_linear_wall_is_finite_and_in_range_for_fast_walls(c):
    tau = np.logspace(-6, 4, 41)
    a = exact.linear_wall_area(tau, 0.5, 0.2, c)
    non = exact.linear_wall_non_area(tau, 0.5, 0.2, c)
    assert np.all(np.isfinite(a)) and np.all((a >= 0) & (a <= 1))
    assert np.all(np.isfinite(non)) and np.all((non >= 0) & (non <= 1))
    assert np.all(np.diff(a) <= 1e-15)  # area decreases
    np.testing.assert_allclose(a + non, 1.0, atol=1e-14)
