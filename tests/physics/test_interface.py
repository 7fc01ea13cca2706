"""Tests of xpersson.physics.interface against physics.md §5 (closed forms and reference tables)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.special import erfinv, exp1

from xpersson.physics import interface as itf
from xpersson.physics.elastic import area_fraction, diffusion_time
from xpersson.physics.psd import SelfAffineRollOff

E_STAR = 10e6 / (1.0 - 0.5**2)
LOADS = np.array([1e3, 1e4, 1e5, 1e6])
# physics.md §5.3: u(p0) [m] and U_el/A0 [J/m^2] at 1e4, 1e5, 1e6 Pa
U_BAR = {1.0: [3.658462e-6, 1.297668e-6, 8.231990e-8, 2.116e-11],
         0.45: [2.405363e-6, 1.123853e-6, 1.189209e-7, 4.270e-11]}  # fmt: skip
U_EL = {1.0: [9.934230e-3, 4.603958e-2, 5.929185e-2],
        0.45: [5.531313e-3, 3.949646e-2, 5.926673e-2]}  # fmt: skip


@pytest.fixture(scope="module")
def psd():
    return SelfAffineRollOff.from_h_rms(1e-6, 0.8, 1e3, 1e4, 1e8)


def persson_curve(psd, p0, zeta):
    """The Persson 2001 area curve (what the elastic solve stores), with 1 - A."""
    tau = diffusion_time(psd, E_STAR, zeta)
    A, N = area_fraction(np.asarray(p0)[:, None], tau[None, :])
    return A, N


@pytest.fixture(scope="module")
def dense(psd):
    zeta = np.concatenate(([1.0], 1.0 + np.geomspace(1e-10, 1e5 - 1.0, 1500)))
    return zeta, *persson_curve(psd, LOADS, zeta)


def test_full_contact_energy(psd):
    U = itf.full_contact_energy(psd, E_STAR)
    assert U == pytest.approx(5.931643e-2, rel=1e-7)
    # vectorised over q_lo: bands add up, the top band vanishes
    q = np.geomspace(1e3, 1e8, 7)
    bands = itf.full_contact_energy(psd, E_STAR, q)
    assert bands[0] == pytest.approx(U, rel=1e-14) and bands[-1] == 0.0
    assert np.all(np.diff(bands) < 0)
    direct = 0.5 * math.pi * E_STAR * psd.moment(2.0, q[2], q[4])
    assert bands[2] - bands[4] == pytest.approx(direct, rel=1e-12)


@pytest.mark.parametrize("gamma", [1.0, 0.45])
def test_yang_persson_table(psd, dense, gamma):
    """Persson's area with S = gamma + (1 - gamma) A^2 reproduces the §5.3 table."""
    zeta, A, N = dense
    S = gamma + (1.0 - gamma) * A**2
    u = itf.mean_gap(psd, E_STAR, LOADS, zeta, A, S, N)
    np.testing.assert_allclose(u[:3], U_BAR[gamma][:3], rtol=8e-7)
    np.testing.assert_allclose(u[3], U_BAR[gamma][3], rtol=3e-4)  # 4 digits given
    U = itf.elastic_energy(psd, E_STAR, zeta, A[1:], S[1:], N[1:])
    np.testing.assert_allclose(U, U_EL[gamma], rtol=8e-7)


def test_persson_phi_is_the_exponential_integral(psd):
    """gamma = 1: u = sqrt(pi) int q^2 C w E1((w p0/E*)^2)/2 dq (§5.2) on a moderate grid."""
    zeta = np.concatenate(([1.0], 1.0 + np.geomspace(1e-6, 1e5 - 1.0, 400)))
    p0 = np.array([3e5])
    A, N = persson_curve(psd, p0, zeta)
    q = np.geomspace(1e3 * (1 + 1e-12), 1e8, 200001)
    w = 1.0 / np.sqrt(np.pi * psd.I3(q))
    f = q**2 * psd.C(q) * w * 0.5 * exp1((w * p0[0] / E_STAR) ** 2)
    ref = math.sqrt(math.pi) * np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(q))
    u = itf.mean_gap(psd, E_STAR, p0, zeta, A, None, N)
    assert u[0] == pytest.approx(ref, rel=2e-4)


def test_stiffness_is_minus_dp_du(psd, dense):
    """K = -dp/du: the analytic slope against a central difference of u(p0)."""
    zeta = dense[0]
    p = np.array([2e4, 3e5, 2e6])
    h = 1e-4

    def gap(pp):
        A, N = persson_curve(psd, pp, zeta)
        return itf.mean_gap(psd, E_STAR, pp, zeta, A, non_area=N)

    fd = -(2 * h * p) / (gap(p * (1 + h)) - gap(p * (1 - h)))
    A, N = persson_curve(psd, p, zeta)
    K = itf.contact_stiffness(psd, E_STAR, p, zeta, A, non_area=N)
    np.testing.assert_allclose(K, fd, rtol=1e-5)


def test_stiffness_low_load_limit(psd, dense):
    """K / p0 -> 1/u0 as p0 -> 0 (§5.4), u0 = 1.239822e-6 m (§5.3)."""
    zeta = dense[0]
    p = np.array([1e-2])
    A, N = persson_curve(psd, p, zeta)
    K = itf.contact_stiffness(psd, E_STAR, p, zeta, A, non_area=N)
    assert K[0] / p[0] == pytest.approx(1.0 / 1.239822e-6, rel=2e-3)


def test_near_full_contact_is_finite_and_smooth(psd):
    """1 - A(zeta_1) from 1e-4 down to 1e-13: u -> 0 smoothly, K finite, positive, growing."""
    zeta = np.concatenate(([1.0], 1.0 + np.geomspace(1e-8, 1e5 - 1.0, 300)))
    G1 = diffusion_time(psd, E_STAR, 1e5)
    target = np.array([1e-4, 1e-8, 1e-12, 1e-13])
    x = np.array([4.0, 5.0, 6.5, 7.0])  # erfc(x) spans 1e-8 .. 4e-23; pick p0 = 2 x sqrt(G1)
    p0 = 2.0 * x * math.sqrt(G1)
    A, N = persson_curve(psd, p0, zeta)
    assert N[:, -1].max() < target[0] and N[:, -1].min() < 1e-21
    u = itf.mean_gap(psd, E_STAR, p0, zeta, A, None, N)
    K = itf.contact_stiffness(psd, E_STAR, p0, zeta, A, None, N)
    assert np.all(np.isfinite(u)) and np.all(u > 0) and np.all(np.diff(u) < 0)
    assert np.all(np.isfinite(K)) and np.all(K > 0) and np.all(np.diff(K) > 0)


def test_critical_magnification(psd, dense):
    zeta, A, N = dense
    zc = itf.critical_magnification(zeta, A, 0.42)
    # Persson 2001: A = erf(p0 / (2 sqrt(tau))) = a_c  <=>  tau = (p0 / (2 erfinv(a_c)))^2
    tau_c = (LOADS / (2.0 * erfinv(0.42))) ** 2
    got = diffusion_time(psd, E_STAR, np.where(np.isfinite(zc), zc, 1.0))
    ok = np.isfinite(zc)
    assert ok.tolist() == [True, True, True, False]  # 1e6 Pa stays above a_c: sealed
    np.testing.assert_allclose(got[ok], tau_c[ok], rtol=1e-6)


ZHOU_P0 = np.array([1e-3, 0.01, 0.025, 0.04, 0.113])
# physics.md §5.5: A(zeta_1), u(p0) g=1, <u> g=1, u(p0) g=0.45, <u> g=0.45 (units of h_rms)
ZHOU = np.array([
    [0.005769, 3.1267, 3.1364, 2.0876, 2.1066],
    [0.05764, 0.97383, 1.0573, 0.92117, 1.0038],
    [0.14345, 0.38433, 0.5062, 0.45496, 0.5486],
    [0.22759, 0.19168, 0.3029, 0.25704, 0.3385],
    [0.58611, 0.016153, 0.04737, 0.02822, 0.05311],
])  # fmt: skip


def test_gap_distribution_table():
    hr = 6e-6
    zhou = SelfAffineRollOff.from_h_rms(hr, 0.8, 1e4, 1e4, 1e6)
    zeta = np.concatenate(([1.0], 1.0 + np.geomspace(1e-9, 99.0, 300)))
    tau = diffusion_time(zhou, 1.0, zeta)
    A, N = area_fraction(ZHOU_P0[:, None], tau[None, :])
    d1 = itf.detachment(zhou, 1.0, ZHOU_P0, zeta, A, None, N)
    d45 = itf.detachment(zhou, 1.0, ZHOU_P0, zeta, A, 0.45 + 0.55 * A**2, N)
    got = np.stack(
        [d1.contact, d1.mean_gap / hr, itf.gap_mean(d1) / hr, d45.mean_gap / hr,
         itf.gap_mean(d45) / hr], axis=1
    )  # fmt: skip
    np.testing.assert_allclose(got, ZHOU, rtol=1e-3)
    # exact bookkeeping: mass of the continuous part = 1 - A(zeta_1); its CDF tends to it
    np.testing.assert_allclose(d1.weight.sum(axis=1), 1.0 - A[:, -1], rtol=1e-12)
    cdf = itf.gap_cdf(d1, np.array([0.0, 1e6 * hr]))
    np.testing.assert_allclose(cdf[:, 1], 1.0 - A[:, -1], rtol=1e-9)
    assert np.all(cdf[:, 0] == 0.0)
    # pointwise density, physics.md §5.5 (p0 = 0.025, gamma = 1)
    u = np.array([0.05, 0.1, 0.25, 0.5, 1.0]) * hr
    ref = [1.72005, 1.26561, 0.79448, 0.51417, 0.26828]
    np.testing.assert_allclose(itf.gap_pdf(d1, u)[2] * hr, ref, rtol=1e-3)


def test_bad_curves_are_refused(psd):
    zeta = np.array([1.0, 10.0, 100.0])
    with pytest.raises(ValueError, match="zeta must increase from 1"):
        itf.elastic_energy(psd, E_STAR, zeta[::-1], np.ones(3))
    with pytest.raises(ValueError, match=r"lie in \[0, 1\]"):
        itf.elastic_energy(psd, E_STAR, zeta, np.array([1.0, 1.2, 0.5]))
    with pytest.raises(ValueError, match="p0 must hold 1 finite positive"):
        itf.mean_gap(psd, E_STAR, [-1.0], zeta, np.array([1.0, 0.5, 0.2]))


def test_dF_sums_at_the_stieltjes_nodes_equal_the_spline_evaluation():
    """``_Curve.dF_weighted`` (``dF`` from the spline's coefficients, each node in its known
    interval) equals the weighted sums of ``_Curve.dF`` at the nodes of ``stieltjes_nodes``
    to rounding (positive terms: no cancellation)."""
    from xpersson.physics._curve import _Curve

    z = np.geomspace(1.0, 1e5, 60)
    area = np.array([np.exp(-a * np.log(z)) for a in (0.05, 0.3, 0.9)])
    curve = _Curve(z, area, None, None)
    xg, wg = curve.stieltjes_nodes()
    ref = np.sum(curve.dF(xg) * wg[None], axis=-1)
    np.testing.assert_allclose(curve.dF_weighted(wg), ref, rtol=1e-13, atol=0)
