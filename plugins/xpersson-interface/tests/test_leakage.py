"""Seal leakage: Bruggeman oracle, critical junction, monotonicity, sealing and refusals (§6)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from interface_testlib import E_STAR, dense_zeta, detach, persson_curve, scene

import xpersson
from xpersson.physics import critical_magnification, separation_of_detaching_area
from xpersson.scene import SceneError
from xpersson_interface import bruggeman, bruggeman_gap, effective_pressure_drop, leak_rate

LOADS = np.geomspace(2e4, 3e6, 10)


@given(a=st.floats(0.0, 0.49), sigma_c=st.floats(1e-30, 1e3))
@settings(max_examples=60, deadline=None)
def test_bruggeman_binary_oracle(a, sigma_c):
    """Binary medium (physics.md §6.2): sigma_eff = sigma_c (1 - 2a) below a = 1/2."""
    s = bruggeman(a, [1.0 - a], [sigma_c])
    assert s == pytest.approx(sigma_c * (1.0 - 2.0 * a), rel=1e-10, abs=1e-300)


@given(a=st.floats(0.5, 1.0))
def test_bruggeman_binary_sealed(a):
    assert bruggeman(a, [1.0 - a], [2.0]) == 0.0


def test_bruggeman_is_a_mean_between_bounds():
    m = np.array([0.2, 0.3, 0.4])
    s = np.array([1.0, 8.0, 27.0])
    e = bruggeman(0.1, m, s)
    harmonic = 1.0 / np.sum(np.array([0.1 / 1e-300, *(m / s)]))
    assert harmonic < e < np.sum(m * s)


@pytest.fixture(scope="module")
def curve(psd):
    z = dense_zeta(1e5, 400)
    A, N = persson_curve(psd, E_STAR, LOADS, z)
    return z, A, N


def test_critical_gap_matches_detachment_bins(psd, curve):
    """u1(zeta_c) of the critical junction = the gap-PDF u1 = d(A u)/dA of a bin around zeta_c."""
    z, A, N = curve
    zc = critical_magnification(z, A, 0.42)
    u1 = separation_of_detaching_area(psd, E_STAR, LOADS, z, A, zc, None, N)
    open_ = np.isfinite(zc)
    assert open_.any() and (~open_).any() and np.all(np.isnan(u1[~open_]))
    np.testing.assert_array_equal(open_, A[:, -1] < 0.42)
    i = 3
    edges = np.array([1.0, zc[i] * np.exp(-1e-3), zc[i] * np.exp(1e-3), 1e5])
    d = detach(psd, E_STAR, LOADS[[i]], n=400, edges=edges)
    assert d.u1[0, 1] == pytest.approx(u1[i], rel=1e-5)


def test_bruggeman_gap_equals_the_scalar_solver_on_fine_cells(psd, monkeypatch):
    """The vectorised solver on its 120 cells, their midpoints moved (``_leakage._moved``),
    = the scalar solver on 4000 midpoint cells (converged: the midpoint rule's error falls
    as the cells' width squared, ~1e-6 there) within 1e-5; the midpoint rule on the same
    120 cells is off by more than 1e-4."""
    from xpersson.physics import gap_cdf
    from xpersson_interface import _leakage

    d = detach(psd, E_STAR, LOADS[:6], n=150)
    u3 = bruggeman_gap(d)
    umax = float(np.max(d.mean_gap)) + 10.0 * d.h_rms
    edges = np.concatenate(([0.0], np.geomspace(1e-7 * d.h_rms, umax, 4000)))
    cdf = gap_cdf(d, edges)
    ref = np.zeros(6)
    for i in range(6):
        m = np.concatenate((np.diff(cdf[i]), [max(1.0 - d.contact[i] - cdf[i, -1], 0.0)]))
        m[0] += cdf[i, 0]
        sig = np.concatenate((np.sqrt(edges[:-1] * edges[1:]), [np.inf])) ** 3
        sig[0] = (0.5 * edges[1]) ** 3
        ref[i] = bruggeman(d.contact[i], m, sig)
    assert np.all(ref > 0)
    np.testing.assert_allclose(u3, ref, rtol=1e-5, atol=0.0)
    monkeypatch.setattr(_leakage, "_moved", lambda s, *_: s)  # the plain midpoint rule
    assert np.all(np.abs(bruggeman_gap(d) / ref - 1.0) > 1e-4)


def test_leak_rates_from_a_scene_are_monotone_and_sealed():
    ds = xpersson.solve(scene(LOADS, analyses={"leakage": {"n_bins": 60}}))
    sealed = ds["leak_sealed"].values.astype(bool)
    Q = ds["leak_rate"].values
    assert sealed.any() and (~sealed).any()
    assert np.all(np.diff(Q[~sealed]) < 0) and np.all(Q[~sealed] > 0) and np.all(Q[sealed] == 0)
    # sealed exactly where the Dataset's own finest-scale area exceeds a_c; then u1 is NaN
    A = ds["area_fraction"].isel(zeta=-1).values
    np.testing.assert_array_equal(sealed, A > 0.42)
    assert np.all(np.isnan(ds["leak_u1"].values[sealed]))
    assert np.all(np.isnan(ds["leak_zeta_c"].values[sealed]))
    Q_emt = ds["leak_rate_emt"].values
    pos = Q_emt > 0
    assert np.all(np.diff(Q_emt[pos]) < 0)
    np.testing.assert_array_equal(~pos, ds["leak_sealed_emt"].values.astype(bool))


def test_leak_rate_units_and_gas():
    u3 = np.array([1e-18])
    q = leak_rate(u3, 2e-3, 1e-2, 1e5, 1e-3)
    assert q[0] == pytest.approx(5.0 * 1e-18 * 1e5 / 12e-3)
    # isothermal ideal gas: volume flow at p_out, (p_in^2 - p_out^2)/(2 p_out)
    assert effective_pressure_drop("gas", p_in=3e5, p_out=1e5) == pytest.approx(4e5)
    # small pressure difference: gas -> liquid law
    assert effective_pressure_drop("gas", p_in=1.001e5, p_out=1e5) == pytest.approx(100.0, rel=1e-3)
    with pytest.raises(ValueError, match="fluid"):
        effective_pressure_drop("plasma", 1.0)


def test_gas_flowing_backwards_is_refused_before_any_work():
    """p_in < p_out used to give a negative leak rate with status success."""
    sc = scene([1e5], analyses={"leakage": {"fluid": "gas", "p_in": "1 bar", "p_out": "2 bar"}})
    with pytest.raises(SceneError, match=r"leakage\.p_in = 100000 Pa must be >= leakage\.p_out"):
        xpersson.solve(sc)


def test_loads_sealed_on_the_stored_curve_take_the_direct_paths_sealed_values(monkeypatch):
    """Loads whose stored contact stays above both sealing values skip the direct path
    (``_leakage.sealed_both``); their outputs are the direct path's bit for bit, the others'
    within round-off of the batch (the effective medium's band sums: <= 1e-12)."""
    import xpersson_interface.plugins as plugins_mod
    from xpersson_interface import _leakage

    p0 = [f"{p:g} Pa" for p in np.geomspace(1e4, 1e7, 10)]
    sc = scene(p0, analyses={"leakage": {}})
    plan = _leakage.sealed_plan
    seen = []
    monkeypatch.setattr(plugins_mod, "sealed_plan", lambda *a: seen.append(plan(*a)) or seen[-1])
    fast = xpersson.solve(sc)
    sealed = seen[0][0]
    assert 0 < sealed.sum() < sealed.size  # some loads skipped, some computed
    none = np.zeros_like(sealed)
    monkeypatch.setattr(plugins_mod, "sealed_plan", lambda *a: (none, none))
    ref = xpersson.solve(sc)
    for k in ("leak_sealed", "leak_sealed_emt"):
        np.testing.assert_array_equal(fast[k].values, ref[k].values)
    assert np.all(ref["leak_sealed"].values[sealed] == 1)
    assert np.all(ref["leak_sealed_emt"].values[sealed] == 1)
    for k in ("leak_zeta_c", "leak_u1", "leak_flow_factor", "leak_rate", "leak_rate_emt"):
        got, want = fast[k].values, ref[k].values
        np.testing.assert_array_equal(got[sealed], want[sealed])
        np.testing.assert_allclose(got, want, rtol=1e-12, atol=0.0)
