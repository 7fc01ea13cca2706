"""Tests of xpersson.physics.elastic: physics.md §1.2-1.4 identities and reference numbers."""

from __future__ import annotations

import math
from decimal import Decimal

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.special import erf

from xpersson.physics.elastic import (
    KAPPA,
    G_of_zeta,
    area_fraction,
    coefficient_f,
    diffusion_time,
    e_star,
    full_contact_std,
    kappa,
    load_integral,
    pressure_pdf,
    rayleigh_pdf,
    second_moment,
    small_load_area,
)
from xpersson.physics.psd import SelfAffineRollOff


def assert_digits(value: float, quoted: str, slack: float = 1.1) -> None:
    """``value`` rounds to ``quoted`` (within ``slack`` half-units of its last digit)."""
    d = Decimal(quoted)
    half_ulp = 0.5 * 10.0 ** d.as_tuple().exponent
    assert abs(value - float(d)) <= slack * half_ulp, (value, quoted)


@pytest.fixture(scope="module")
def ref_psd():
    """physics.md §1.4 parameter set."""
    return SelfAffineRollOff.from_h_rms(1e-6, 0.8, 1e3, 1e4, 1e8)


@pytest.fixture(scope="module")
def ref_Es():
    return e_star(10e6, 0.5)


def test_e_star():
    assert e_star(10e6, 0.5) == pytest.approx(13.333333333333e6, rel=1e-12, abs=0)
    np.testing.assert_allclose(e_star(np.array([1.0, 2.0]), 0.0), [1.0, 2.0])
    for bad in [(0.0, 0.3), (1.0, 0.6), (1.0, -1.0)]:
        with pytest.raises(ValueError):
            e_star(*bad)
    assert kappa == KAPPA == pytest.approx(1.5958, abs=5e-5)


@pytest.mark.parametrize(
    ("p0", "G", "A", "lin"),
    [
        (1e4, "1930.095", "1.284154e-2", "1.284209e-2"),
        (1e5, "19.30095", "0.1278686", "0.1284209"),
        (1e6, "0.1930095", "0.8924967", None),
    ],
)
def test_reference_table_section_1_4(ref_psd, ref_Es, p0, G, A, lin):
    zeta1 = ref_psd.q_1 / ref_psd.q_L
    assert_digits(G_of_zeta(ref_psd, ref_Es, p0, zeta1), G)
    tau = diffusion_time(ref_psd, ref_Es, zeta1)
    a, one_minus_a = area_fraction(p0, tau)
    assert_digits(a, A)
    assert a + one_minus_a == pytest.approx(1.0, abs=1e-15)
    if lin is not None:
        assert_digits(small_load_area(p0, ref_Es, ref_psd.rms_slope()), lin)
    assert_digits(math.sqrt(2 * tau), "6.213043e5")
    assert full_contact_std(ref_Es, ref_psd.rms_slope()) == pytest.approx(
        math.sqrt(2 * tau), rel=1e-13, abs=0
    )


def test_diffusion_time_is_integral_of_f(ref_psd, ref_Es):
    # tau(zeta) = int_1^zeta f dzeta' (physics.md §0), integrated in ln zeta
    for zeta in [5.0, 10.0, 1e3, 1e5]:
        pts = [0.0, np.log(10.0)] if zeta > 10 else [0.0]
        edges = sorted(set(pts + [np.log(zeta)]))
        num = sum(
            quad(
                lambda s: coefficient_f(ref_psd, ref_Es, np.exp(s)) * np.exp(s),
                a,
                b,
                epsabs=0,
                epsrel=1e-12,
            )[0]
            for a, b in zip(edges[:-1], edges[1:], strict=True)
        )
        assert diffusion_time(ref_psd, ref_Es, zeta) == pytest.approx(num, rel=1e-11, abs=0)
    assert diffusion_time(ref_psd, ref_Es, 1.0) == 0.0


def test_coefficient_f_formula(ref_psd, ref_Es):
    zeta = np.array([1.0, 3.0, 30.0, 1e5])
    q = zeta * ref_psd.q_L
    ref = np.pi / 4 * ref_Es**2 * ref_psd.q_L * q**3 * ref_psd.C(q)
    np.testing.assert_allclose(coefficient_f(ref_psd, ref_Es, zeta), ref, rtol=1e-15)


def test_G_broadcasting(ref_psd, ref_Es):
    p0 = np.array([1e4, 1e5, 1e6])
    zeta = np.geomspace(1, 1e5, 7)
    G = G_of_zeta(ref_psd, ref_Es, p0[:, None], zeta)
    assert G.shape == (3, 7)
    np.testing.assert_allclose(G[1] * 1e10, diffusion_time(ref_psd, ref_Es, zeta), rtol=1e-14)
    assert np.all(G[:, 0] == 0)
    assert np.all(np.diff(G, axis=1) > 0)
    with pytest.raises(ValueError):
        G_of_zeta(ref_psd, ref_Es, 0.0, zeta)


def test_area_monotone_and_full_contact_start(ref_psd, ref_Es):
    zeta = np.geomspace(1, 1e5, 200)
    A, one_minus_A = area_fraction(1e5, diffusion_time(ref_psd, ref_Es, zeta))
    assert A[0] == 1.0 and one_minus_A[0] == 0.0
    assert np.all(np.diff(A) <= 0)
    # strictly decreasing wherever the deficit is representable (erfc does not underflow)
    pos = one_minus_A > 0
    assert pos.sum() > 150
    assert np.all(np.diff(one_minus_A[pos]) > 0)


def test_area_fraction_tau_zero_and_broadcast():
    A, B = area_fraction(np.array([[1.0], [2.0]]), np.array([0.0, 1.0, 4.0]))
    assert A.shape == B.shape == (2, 3)
    assert np.all(A[:, 0] == 1.0) and np.all(B[:, 0] == 0.0)
    np.testing.assert_allclose(A[0, 1:], erf(np.array([0.5, 0.25])), rtol=1e-15)
    for bad in [(0.0, 1.0), (-1.0, 1.0), (1.0, -1.0), (1.0, np.nan)]:
        with pytest.raises(ValueError):
            area_fraction(*bad)


def test_near_full_contact_erfc_accuracy():
    mpmath = pytest.importorskip("mpmath")
    mpmath.mp.dps = 40
    # choose x with erfc(x) = 1e-12, then tau = (p0 / (2x))^2
    x = float(mpmath.findroot(lambda t: mpmath.erfc(t) - mpmath.mpf("1e-12"), 5.0))
    p0 = 3.0e5
    tau = (p0 / (2 * x)) ** 2
    _, one_minus_A = area_fraction(p0, tau)
    exact = float(mpmath.erfc(mpmath.mpf(p0) / (2 * mpmath.sqrt(mpmath.mpf(tau)))))
    assert one_minus_A == pytest.approx(exact, rel=1e-13, abs=0)
    assert exact == pytest.approx(1e-12, rel=1e-10, abs=0)
    # the naive 1 - erf loses ~4 digits here: this is what the complement guards against
    naive = 1.0 - erf(p0 / (2 * math.sqrt(tau)))
    assert abs(naive / exact - 1) > 1e-6


def test_near_full_contact_erfc_asymptotic():
    # independent of mpmath: erfc(x) ~ exp(-x^2)/(x sqrt(pi)) (1 - 1/(2x^2) + 3/(4x^4) - ...)
    x = 25.0
    series = sum((-1) ** n * math.prod(range(1, 2 * n, 2)) / (2 * x * x) ** n for n in range(12))
    asym = math.exp(-x * x) / (x * math.sqrt(math.pi)) * series
    _, one_minus_A = area_fraction(2 * x, 1.0)
    assert one_minus_A == pytest.approx(asym, rel=1e-13, abs=0)


@pytest.mark.parametrize(("p0", "tau"), [(1.0, 0.01), (1.0, 1.0), (1e-3, 0.5), (5e5, 2e11)])
def test_pdf_normalisation_and_load_conservation(p0, tau):
    V = 2 * tau
    upper = p0 + 14 * math.sqrt(V)
    pts = sorted({p0, min(math.sqrt(V), upper / 2)})
    P = lambda p: pressure_pdf(p, p0, tau)  # noqa: E731
    kw = dict(epsabs=0, epsrel=1e-12, limit=400, points=pts)
    A0 = quad(P, 0, upper, **kw)[0]
    M1 = quad(lambda p: p * P(p), 0, upper, **kw)[0]
    M2 = quad(lambda p: p * p * P(p), 0, upper, **kw)[0]
    assert A0 == pytest.approx(area_fraction(p0, tau)[0], rel=1e-10, abs=0)
    assert M1 == pytest.approx(p0, rel=1e-10, abs=0)
    assert load_integral(p0, tau) == p0
    assert M2 == pytest.approx(second_moment(p0, tau), rel=1e-10, abs=0)


def test_pdf_matches_mirrored_gaussian_and_is_stable():
    p = np.linspace(-1.0, 6.0, 71)
    p0, tau = 2.0, 0.7
    direct = (np.exp(-((p - p0) ** 2) / (4 * tau)) - np.exp(-((p + p0) ** 2) / (4 * tau))) / (
        np.sqrt(4 * np.pi * tau)
    )
    got = pressure_pdf(p, p0, tau)
    np.testing.assert_allclose(got[p > 0], direct[p > 0], rtol=1e-12, atol=1e-300)
    assert np.all(got[p <= 0] == 0.0)
    # tiny p p0 / tau: the difference form cancels completely, the product form does not
    p0, tau, pp = 1e-9, 1.0, 1e-9
    val = pressure_pdf(pp, p0, tau)
    ref = np.exp(-((pp - p0) ** 2) / 4) / np.sqrt(4 * np.pi) * (pp * p0 / tau)
    assert val == pytest.approx(ref, rel=1e-12, abs=0)
    assert np.all(pressure_pdf(p, 1.0, 0.0) == 0.0)
    assert pressure_pdf(p[:, None], np.array([1.0, 2.0]), 0.3).shape == (71, 2)


def test_second_moment_full_contact_limit():
    assert second_moment(3.0, 0.0) == 9.0
    p0, tau = 1e3, 1.0  # p0 >> sqrt(V)
    assert second_moment(p0, tau) == pytest.approx(p0**2 + 2 * tau, rel=1e-15, abs=0)


@pytest.mark.parametrize(
    ("G", "ratio"), [(1e2, "0.99917"), (1e4, "0.9999917"), (1e6, "0.99999992")]
)
def test_small_load_kappa_ratio(G, ratio):
    # full-contact tau(zeta1) = (pi/4) E*^2 m3 = E*^2 h'^2 / 8, so E* h' = sqrt(8 tau)
    p0, E_star = 2.0e3, 1.0e7
    tau = G * p0**2
    h_prime = math.sqrt(8 * tau) / E_star
    A, _ = area_fraction(p0, tau)
    assert_digits(A / small_load_area(p0, E_star, h_prime), ratio)


def test_small_load_with_reference_psd(ref_psd, ref_Es):
    tau = diffusion_time(ref_psd, ref_Es, ref_psd.q_1 / ref_psd.q_L)
    p0 = 1.0
    A, _ = area_fraction(p0, tau)
    assert A / small_load_area(p0, ref_Es, ref_psd.rms_slope()) == pytest.approx(1.0, abs=1e-9)


def test_rayleigh_small_load_shape():
    V = 1.0
    p0 = 1e-3 * math.sqrt(V)
    tau = V / 2
    p = np.linspace(0, 10, 100001)
    A, _ = area_fraction(p0, tau)
    dev = np.max(np.abs(pressure_pdf(p, p0, tau) / A - rayleigh_pdf(p, V)))
    assert 1.3e-7 < dev < 1.5e-7  # physics.md §1.3-5: ~1.4e-7
    # mean contact pressure p0/A -> sqrt(pi V / 2)
    assert p0 / A == pytest.approx(math.sqrt(math.pi * V / 2), rel=1e-6, abs=0)


def test_full_contact_gaussian_std(ref_psd, ref_Es):
    zeta1 = ref_psd.q_1 / ref_psd.q_L
    tau = diffusion_time(ref_psd, ref_Es, zeta1)
    p0 = 1e3 * math.sqrt(2 * tau)  # G << 1
    std = math.sqrt(second_moment(p0, tau) - load_integral(p0, tau) ** 2)
    assert std == pytest.approx(ref_Es * ref_psd.rms_slope() / 2, rel=1e-9, abs=0)
