"""Seal leakage: Bruggeman oracle, critical junction, monotonicity and sealing (physics.md §6)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from interface_testlib import E_STAR

from xpersson_interface import (
    AreaLaw,
    bruggeman,
    bruggeman_gap,
    critical_junction,
    detachment,
    effective_pressure_drop,
    leak_rate,
)

LOADS = np.geomspace(2e4, 3e6, 10)


@given(
    a=st.floats(0.0, 0.49),
    sigma_c=st.floats(1e-30, 1e3),
)
@settings(max_examples=60, deadline=None)
def test_bruggeman_binary_oracle(a, sigma_c):
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
def cj(psd):
    return critical_junction(psd, E_STAR, LOADS)


@pytest.fixture(scope="module")
def det(psd):
    return detachment(psd, E_STAR, LOADS, n_zeta=150)


def test_percolation_area_is_a_c(psd, cj):
    law = AreaLaw()
    open_ = ~cj["sealed"]
    G = 0.25 * np.pi * (E_STAR / LOADS[open_]) ** 2 * psd.I3(cj["zeta_c"][open_] * psd.q_L)
    np.testing.assert_allclose(law.area(G), 0.42, rtol=1e-10)
    # sealed exactly when the finest-scale area exceeds a_c
    np.testing.assert_array_equal(cj["sealed"], cj["area_final"] >= 0.42)
    assert cj["sealed"].any() and (~cj["sealed"]).any()
    assert np.all(cj["u1"][cj["sealed"]] == 0.0) and np.all(np.isnan(cj["zeta_c"][cj["sealed"]]))


def test_critical_gap_matches_detachment_bins(psd, cj):
    """u1(zeta_c) of the critical junction = the gap-PDF u1 = d(A u)/dA at zeta_c."""
    i = 3
    zc = cj["zeta_c"][i]
    edges = np.array([1.0, zc * np.exp(-2e-3), zc * np.exp(2e-3), psd.q_1 / psd.q_L])
    d = detachment(psd, E_STAR, LOADS[[i]], zeta=edges)
    assert d.u1[0, 1] == pytest.approx(cj["u1"][i], rel=1e-5)


def test_leak_rate_monotone_and_sealed(cj, det):
    dp = effective_pressure_drop("liquid", 1e5)
    Q = leak_rate(cj["u1"] ** 3, 1e-3, 1e-2, dp, 1e-3)
    open_ = ~cj["sealed"]
    assert np.all(np.diff(Q[open_]) < 0) and np.all(Q[open_] > 0)
    assert np.all(Q[cj["sealed"]] == 0.0)
    u3 = bruggeman_gap(det)
    Q_emt = leak_rate(u3, 1e-3, 1e-2, dp, 1e-3)
    pos = Q_emt > 0
    assert np.all(np.diff(Q_emt[pos]) < 0)
    np.testing.assert_array_equal(~pos, det.contact >= 0.5)  # plain Bruggeman threshold
    # rescaled EMT seals together with the critical junction (a_c = 0.42)
    u3c = bruggeman_gap(det, a_c=0.42)
    np.testing.assert_array_equal(u3c == 0, det.contact >= 0.42)
    assert np.all(u3c <= u3)
    # effective-medium gap lies between 0 and the largest gaps; below the mean gap at high load
    assert np.all(np.cbrt(u3[pos]) < 6 * det.h_rms)


def test_leak_rate_units_and_gas():
    u3 = np.array([1e-18])
    q = leak_rate(u3, 2e-3, 1e-2, 1e5, 1e-3)
    assert q[0] == pytest.approx(5.0 * 1e-18 * 1e5 / 12e-3)
    # isothermal ideal gas: volume flow at p_out, (p_in^2 - p_out^2)/(2 p_out)
    assert effective_pressure_drop("gas", p_in=3e5, p_out=1e5) == pytest.approx(4e5)
    # small pressure difference: gas -> liquid law
    assert effective_pressure_drop("gas", p_in=1.001e5, p_out=1e5) == pytest.approx(100.0, rel=1e-3)
    with pytest.raises(ValueError):
        effective_pressure_drop("plasma", 1.0)
