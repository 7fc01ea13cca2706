"""Exact two-wall series (physics.md §3.1): check values, images vs sines, identities."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import quad

from xpersson_plasticity._series import (
    three_gaussian_areas,
    two_wall_areas,
    two_wall_pdf,
)

T_CHECK = np.array([0.01, 0.1, 1.0])
A_EL = np.array([0.9661044, 0.3839343, 5.32786e-5])
A_PL = np.array([7.43e-7, 0.1138744, 0.2999734])


@pytest.mark.parametrize("method", ["auto", "images", "sine"])
@pytest.mark.parametrize("Y", [1.0, 2.5e9])
def test_check_values(method, Y):
    # p0 / sigma_Y = 0.3, t in units of sigma_Y^2
    r = two_wall_areas(T_CHECK * Y**2, 0.3 * Y, Y, method)
    np.testing.assert_allclose(r.elastic, A_EL, rtol=0, atol=1e-7)
    np.testing.assert_allclose(r.plastic, A_PL, rtol=0, atol=1e-7)
    # the small plastic area at t = 0.01 is erfc(3.5) to relative accuracy
    assert r.plastic[0] == pytest.approx(7.430983723414e-07, rel=1e-9)


@pytest.mark.parametrize("x", [0.01, 0.3, 0.5, 0.9, 0.999])
def test_images_and_sines_agree(x):
    t = np.geomspace(2e-3, 20.0, 300)
    a = two_wall_areas(t, x, 1.0, "images")
    b = two_wall_areas(t, x, 1.0, "sine")
    for u, v in zip(a, b, strict=True):
        np.testing.assert_allclose(u, v, rtol=0, atol=1e-12)


def test_pdf_images_and_sines_agree():
    p = np.linspace(0, 1, 201)
    t = np.geomspace(5e-3, 5.0, 40)
    a = two_wall_pdf(p, t, 0.3, 1.0, "images")
    b = two_wall_pdf(p, t, 0.3, 1.0, "sine")
    np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 * np.max(np.abs(a)))


@pytest.mark.parametrize("t", [0.003, 0.05, 0.3, 2.0])
def test_pdf_integrates_to_areas_and_load(t):
    # independent quadrature of the density: int P = A_el, int p P + Y A_pl = p0
    Y, p0 = 2.0e9, 0.7e9
    tau = t * Y**2
    r = two_wall_areas(tau, p0, Y)

    def dens(p):
        return two_wall_pdf(p, tau, p0, Y)[0, 0]

    pts = [p0] if t < 0.1 else None
    mass = quad(dens, 0, Y, points=pts, epsabs=1e-13, limit=200)[0]
    mom = quad(lambda p: p * dens(p), 0, Y, points=pts, epsabs=1e-13 * Y, limit=200)[0]
    assert mass == pytest.approx(float(r.elastic), abs=1e-10)
    assert (mom + Y * float(r.plastic)) / p0 == pytest.approx(1.0, abs=1e-10)
    assert float(r.elastic + r.plastic + r.non_contact) == pytest.approx(1.0, abs=1e-14)


def test_limits():
    r0 = two_wall_areas(0.0, 0.3, 1.0)
    assert (float(r0.elastic), float(r0.plastic), float(r0.non_contact)) == (1.0, 0.0, 0.0)
    r = two_wall_areas(np.array([10.0, 50.0]), 0.3, 1.0)
    # A_pl -> p0/sigma_Y, A_non -> 1 - p0/sigma_Y, first sine mode decays as exp(-pi^2 t)
    np.testing.assert_allclose(r.plastic, 0.3, atol=1e-40 + 4 / np.pi * np.exp(-(np.pi**2) * 10))
    assert float(r.plastic[1]) == pytest.approx(0.3, abs=1e-15)
    assert float(r.non_contact[1]) == pytest.approx(0.7, abs=1e-15)
    # monotone: elastic decreasing, absorbed increasing
    t = np.geomspace(1e-2, 10, 200)
    r = two_wall_areas(t, 0.3, 1.0)
    assert np.all(np.diff(r.elastic) < 0)
    assert np.all(np.diff(r.plastic) >= 0) and np.all(np.diff(r.non_contact) >= 0)


def test_far_wall_recovers_single_wall():
    # sigma_Y -> infinity: A_el = erf(p0 / (2 sqrt(tau))) (physics.md §1.2)
    from scipy.special import erf

    tau = np.geomspace(1e-4, 1.0, 20)
    r = two_wall_areas(tau, 1.0, 1e3)
    np.testing.assert_allclose(r.elastic, erf(1.0 / (2 * np.sqrt(tau))), rtol=1e-13)


def test_agrees_with_engine_exact():
    exact = pytest.importorskip("xpersson.engine.exact")
    t = np.geomspace(1e-3, 10.0, 200) * 1e18
    for p0 in (1e7, 3e8, 9.9e8):
        r = two_wall_areas(t, p0, 1e9)
        lo, up = exact.two_wall_absorbed(t, p0, 0.0, 1e9)
        np.testing.assert_allclose(r.plastic, up, rtol=0, atol=1e-13)
        np.testing.assert_allclose(r.non_contact, lo, rtol=0, atol=1e-13)
        np.testing.assert_allclose(r.elastic, exact.two_wall_area(t, p0, 0.0, 1e9), atol=1e-13)
        np.testing.assert_allclose(r.load, exact.two_wall_load(t, p0, 0.0, 1e9), atol=1e-13 * p0)


def test_three_gaussian_small_tau_and_defect():
    # exact to round-off while sqrt(2 t) << sigma_Y - p0 ...
    t = np.array([1e-4, 1e-3, 5e-3])
    a, b = three_gaussian_areas(t, 0.3, 1.0), two_wall_areas(t, 0.3, 1.0)
    for u, v in zip(a, b, strict=True):
        np.testing.assert_allclose(u, v, atol=1e-12)
    # ... but violates P(0) = 0 once sqrt(2 t) ~ sigma_Y: the areas turn unphysical
    assert float(three_gaussian_areas(1.0, 0.3, 1.0).elastic) < 0  # unphysical


@pytest.mark.parametrize(("p0", "Y"), [(1.0, 1.0), (2.0, 1.0), (0.0, 1.0), (-1.0, 1.0)])
def test_series_rejects_p0_outside_domain(p0, Y):
    with pytest.raises(ValueError, match="0 < p0 < Y"):
        two_wall_areas(0.1, p0, Y)
