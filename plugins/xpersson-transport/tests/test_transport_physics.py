"""The transport formulas on their own: closed forms, limits and exact identities."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from xpersson_transport import _physics as ph
from xpersson_transport._gap import gas_from_cdf

pos = st.floats(1e-12, 1e12, allow_nan=False, allow_infinity=False)


def test_single_hertz_holm_contact_gives_the_analogy_constant():
    """One circular contact of radius a: flat-punch stiffness 2 a E*, Holm conductance
    4 a / (rho_1 + rho_2) (each half-space rho/(4a)); their ratio is Barber's constant."""
    a, E_star = 37e-6, 68e9
    rho1, rho2 = 1.7e-8, 2.8e-8
    K_spot = 2.0 * a * E_star
    G_spot = 1.0 / (rho1 / (4 * a) + rho2 / (4 * a))
    assert G_spot / K_spot == pytest.approx(ph.electrical_factor(rho1, rho2, E_star), rel=1e-15)
    k1, k2 = 400.0, 237.0
    H_spot = 1.0 / (1 / (4 * k1 * a) + 1 / (4 * k2 * a))
    assert H_spot / K_spot == pytest.approx(ph.thermal_factor(k1, k2, E_star), rel=1e-15)


def test_holm_a_spot_resistance_of_identical_metals():
    """Holm (Electric Contacts, 1967): one a-spot between identical metals has R = rho/(2a)."""
    a, rho, E_star = 10e-6, 1.7e-8, 60e9
    # the spot seen as Holm's picture with one spot per unit area: A = pi a^2, q = c_r / a
    K = ph.holm_stiffness(math.pi * a**2, math.pi / 2 / a, E_star)
    R = 1.0 / (ph.electrical_factor(rho, rho, E_star) * K)
    assert R == pytest.approx(rho / (2 * a), rel=1e-14)  # 8.5e-4 ohm


@settings(max_examples=60, deadline=None)
@given(pos, pos, pos, st.floats(1e-3, 1e3), st.floats(1e-3, 1e3))
def test_scaling_with_conductivities_and_moduli(r1, r2, E, lam, mu):
    """g/K ~ 1/(rho_1 + rho_2) and ~ kappa_s, both ~ 1/E*, to round-off."""
    c = ph.electrical_factor(r1, r2, E)
    assert ph.electrical_factor(lam * r1, lam * r2, mu * E) == pytest.approx(c / (lam * mu),
                                                                            rel=1e-13)  # fmt: skip
    t = ph.thermal_factor(r1, r2, E)
    assert ph.thermal_factor(lam * r1, lam * r2, mu * E) == pytest.approx(t * lam / mu, rel=1e-13)
    # the thermal constant is the electrical one with rho -> 1/kappa
    assert ph.thermal_factor(r1, r2, E) == pytest.approx(
        ph.electrical_factor(1 / r1, 1 / r2, E), rel=1e-13
    )


def _linear_pdf_integral(u0, u1, f0, f1, lam):
    """int_{u0}^{u1} f(u)/(u + lam) du for linear f (closed form)."""
    s = (f1 - f0) / (u1 - u0)
    c = f0 - s * u0
    return s * (u1 - u0) + (c - s * lam) * math.log((u1 + lam) / (u0 + lam))


@pytest.mark.parametrize("lam", [0.0, 1e-12, 3e-9, 2e-7, 5e-5])
def test_gas_integral_is_exact_for_piecewise_linear_densities(lam):
    """Triangle density on [0, 2 um] (peak 1 um): the product rule is exact, also for Lambda = 0
    (the density vanishes at u = 0) and Lambda far below the grid spacing."""
    u = np.linspace(0.0, 2e-6, 9)
    pdf = np.interp(u, [0, 1e-6, 2e-6], [0, 1e6, 0])
    # first piece f = 1e12 u: int_0^1um 1e12 u / (u + lam) du (= 1e6 for lam = 0)
    first = 1e6 if lam == 0 else _linear_pdf_integral(0.0, 1e-6, 0.0, 1e6, lam)
    want = first + _linear_pdf_integral(1e-6, 2e-6, 1e6, 0.0, lam)
    got = ph.gas_gap_conductance(u, pdf, 0.026, lam)
    assert got == pytest.approx(0.026 * want, rel=1e-12)


def test_gas_reduces_to_continuum_and_to_zero_in_vacuum():
    u = np.linspace(0.0, 4e-6, 401)
    pdf = u * np.exp(-u / 5e-7)
    pdf /= np.trapezoid(pdf, u)
    cont = ph.gas_gap_conductance(u, pdf, 0.03, 0.0)  # finite: pdf(0) = 0
    lams = (1e-7, 1e-9, 1e-11, 1e-13, 1e-15)
    err = [abs(ph.gas_gap_conductance(u, pdf, 0.03, lam) / cont - 1) for lam in lams]
    assert np.all(np.diff(err) < 0) and err[-1] < 1e-7
    assert ph.gas_gap_conductance(u, pdf, 0.0, 1e-7) == 0.0  # vacuum
    # larger jump length, less conductance
    g = [ph.gas_gap_conductance(u, pdf, 0.03, lam) for lam in (0, 1e-9, 1e-8, 1e-7, 1e-6)]
    assert np.all(np.diff(g) < 0)


def test_gas_log_divergence_at_contact_edges():
    """pdf(0+) > 0: the continuum form diverges; d g / d ln Lambda -> -kappa pdf(0) exactly."""
    u = np.linspace(0.0, 1e-6, 101)
    pdf = np.full(u.size, 1e6)  # uniform on [0, 1 um]
    assert np.isinf(ph.gas_gap_conductance(u, pdf, 1.0, 0.0))
    g1, g2 = (ph.gas_gap_conductance(u, pdf, 1.0, lam) for lam in (1e-14, 1e-15))
    assert (g2 - g1) / math.log(10.0) == pytest.approx(1e6, rel=1e-7)


def test_jump_length_air():
    """Full accommodation, gamma = 1.4, Pr = 0.71: Lambda = 2 (2.8/2.4) lambda / 0.71."""
    assert ph.jump_length(68e-9) == pytest.approx(2 * (2.8 / 2.4) * 68e-9 / 0.71, rel=1e-15)
    assert ph.jump_length(0.0) == 0.0
    assert ph.jump_length(68e-9, 0.5, 0.5) == pytest.approx(3 * ph.jump_length(68e-9))


def test_radiation_black_and_gray():
    assert ph.radiation_conductance(300.0, 1.0, 1.0) == pytest.approx(
        4 * 5.670374419e-8 * 300.0**3, rel=1e-15
    )  # 6.12 W/(m^2 K)
    assert ph.radiation_conductance(300.0, 0.0, 0.8) == 0.0
    eps = 1 / (1 / 0.5 + 1 / 0.5 - 1)
    assert ph.radiation_conductance(300.0, 0.5, 0.5) == pytest.approx(
        eps * ph.radiation_conductance(300.0, 1, 1)
    )


def test_film_in_series():
    assert np.isinf(ph.film_conductance([0.1], 1e-3, 0.0)).all()
    g_f = ph.film_conductance(np.array([0.1, 0.2]), 2.0, 1e-8)  # rho_f d = 2e-8 ohm m^2
    np.testing.assert_allclose(g_f, [5e6, 1e7], rtol=1e-15)
    np.testing.assert_allclose(ph.in_series(g_f, np.inf), g_f)
    np.testing.assert_allclose(ph.in_series(3.0, 6.0), 2.0)


def test_closest_to_one():
    x = np.array([1.0, 10.0, 100.0])
    y = np.array([[0.1, 1.0, 10.0], [2.0, 3.0, 4.0], [0.1, 0.2, 0.3], [5.0, 0.1, 10.0]])
    z, r = ph.closest_to_one(x, y)
    assert z[0] == pytest.approx(10.0) and r[0] == 1.0
    assert z[1] == 1.0 and r[1] == 2.0  # no crossing: closest grid point
    assert z[2] == 100.0 and r[2] == 0.3
    assert z[3] == pytest.approx(10.0 ** (np.log(5) / np.log(50))) and r[3] == 1.0  # first one


@pytest.mark.parametrize("lam", [0.0, 1e-12, 3e-9, 2e-7])
def test_gas_by_parts_on_the_cdf(lam):
    """int rho/(u + Lambda) = int F/(u + Lambda)^2: exact for piecewise-linear F (uniform
    density on [0, 1 um]: kappa ln((1 um + Lambda)/Lambda)); equals the density rule."""
    u = np.array([0.0, 0.25e-6, 1e-6, 3e-6])
    F = np.interp(u, [0.0, 1e-6], [0.0, 1.0])
    got = gas_from_cdf(u, F, 0.5, lam)
    if lam == 0.0:
        assert np.isinf(got)
        return
    assert got == pytest.approx(0.5 * 1e6 * math.log((1e-6 + lam) / lam), rel=1e-13)
    rho = np.where(u < 1e-6, 1e6, 0.0)
    u2 = np.array([0.0, 0.25e-6, 1e-6, 1e-6 * (1 + 1e-12), 3e-6])
    rho2 = np.array([1e6, 1e6, 1e6, 0.0, 0.0])
    assert ph.gas_gap_conductance(u2, rho2, 0.5, lam) == pytest.approx(got, rel=1e-9)
    assert gas_from_cdf(u, F, 0.0, lam) == 0.0 and rho.size == 4
