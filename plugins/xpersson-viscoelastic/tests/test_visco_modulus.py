"""Modulus models: closed-form angular integrals (physics.md §4.4) against mpmath quadrature."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from xpersson_viscoelastic import MasterCurve, Prony, sls, synthetic_tread, u_over_b

mp = pytest.importorskip("mpmath")
E_R, E_G, TAU = 3e6, 3e9, 1e-3


def _angular_mp(E, b):
    """(mean_sq, loss) by adaptive mpmath quadrature over the full circle [0, 2 pi]."""
    mp.mp.dps = 30
    pts = [0, mp.pi / 2, mp.pi, 3 * mp.pi / 2, 2 * mp.pi]
    if b > 1:  # the resonance cos(phi) = 1/b of the loss peak
        c = mp.acos(1 / mp.mpf(b))
        pts = sorted(pts + [c, mp.pi - c, mp.pi + c, 2 * mp.pi - c])

    def e(phi):
        return E(mp.mpf(b) * mp.cos(phi))

    sq = mp.quad(lambda p: abs(e(p)) ** 2, pts) / (2 * mp.pi)
    loss = mp.quad(lambda p: mp.cos(p) * mp.im(e(p)), pts)
    return float(sq), float(loss)


def _sls_mp(x):  # E(omega) with x = omega tau
    return (E_R + 1j * x * E_G) / (1 + 1j * x)


B_VALUES = [1e-9, 1e-6, 1e-3, 0.1, 1.0, 1.272, 10.0, 1e2, 1e3]


@pytest.mark.parametrize("b", B_VALUES)
def test_sls_angular_integrals_match_quadrature_to_1e10(b):
    model = sls(E_R, E_G, TAU)
    mean_sq, loss = model.angular(b / TAU)
    ref_sq, ref_loss = _angular_mp(_sls_mp, b)
    assert mean_sq == pytest.approx(ref_sq, rel=1e-10)
    assert loss == pytest.approx(ref_loss, rel=1e-10)
    # the closed forms of physics.md §4.4, evaluated in 30-digit arithmetic
    s = mp.sqrt(1 + mp.mpf(b) ** 2)
    assert loss == pytest.approx(float((E_G - E_R) * 2 * mp.pi / b * (1 - 1 / s)), rel=1e-12)
    assert mean_sq == pytest.approx(float(E_G**2 - (E_G**2 - E_R**2) / s), rel=1e-12)
    # no cancellation: the excess over E_r^2 is accurate too (it is ~b^2 at small b)
    excess = float((E_G**2 - E_R**2) * (s - 1) / s)
    assert model.excess_mean_sq(b / TAU) == pytest.approx(excess, rel=1e-12)


def test_single_scale_velocity_factor_peak():
    res = minimize_scalar(
        lambda b: -u_over_b(b), bounds=(0.1, 10), method="bounded", options={"xatol": 1e-10}
    )
    assert round(float(res.x), 4) == 1.2720
    assert round(float(-res.fun), 5) == 0.30028
    assert u_over_b(0.0) == 0.0 and u_over_b(np.inf) == 0.0


@pytest.mark.parametrize("w", [1e-3, 1.0, 37.0, 1e4])
def test_prony_closed_forms_match_quadrature(w):
    model = Prony(2e6, [1e7, 3e8, 5e7], [1e-4, 2e-2, 3.0])
    mean_sq, loss = model.angular(w)

    def E(x):  # x = w cos(phi) as an mpf
        return 2e6 + sum(
            d * 1j * x * t / (1 + 1j * x * t) for d, t in zip(model.delta_E, model.tau, strict=True)
        )

    mp.mp.dps = 30
    pts = [0, mp.pi / 2, mp.pi, 3 * mp.pi / 2, 2 * mp.pi]
    sq = float(mp.quad(lambda p: abs(E(w * mp.cos(p))) ** 2, pts) / (2 * mp.pi))
    lo = float(mp.quad(lambda p: mp.cos(p) * mp.im(E(w * mp.cos(p))), pts))
    assert mean_sq == pytest.approx(sq, rel=1e-9)
    assert loss == pytest.approx(lo, rel=1e-9)


def test_prony_limits_and_conjugate_symmetry():
    m = synthetic_tread()
    assert m.E_r == 3e6 and m.E_g == pytest.approx(3e9, rel=1e-14)
    assert m.tau.size == 40
    assert m.angular(0.0)[0] == pytest.approx(3e6**2, rel=1e-15)
    assert m.angular(0.0)[1] == 0.0
    assert m.angular(1e30)[0] == pytest.approx(m.E_g**2, rel=1e-12)
    w = np.geomspace(1e-3, 1e12, 50)
    np.testing.assert_array_equal(m.modulus(-w), np.conj(m.modulus(w)))
    assert np.all(m.modulus(w).imag > 0)


def test_master_curve_from_sampled_sls_reproduces_closed_forms():
    model = sls(E_R, E_G, TAU)
    w = np.geomspace(1e-4, 1e10, 800) / TAU
    E = model.modulus(w)
    mc = MasterCurve(w, E.real, E.imag)
    np.testing.assert_array_equal(mc.modulus(-w[::7]), np.conj(mc.modulus(w[::7])))
    for wq in (1e-2 / TAU, 1 / TAU, 1e2 / TAU):
        a, b = mc.angular(wq), model.angular(wq)
        assert a[0] == pytest.approx(b[0], rel=2e-3)
        assert a[1] == pytest.approx(b[1], rel=2e-3)


def test_master_curve_without_loss_has_zero_loss_integral():
    w = np.geomspace(1.0, 1e6, 5)
    mc = MasterCurve(w, np.geomspace(3e6, 3e7, 5), np.zeros(5))
    assert np.all(mc.angular(np.geomspace(1e-3, 1e9, 20))[1] == 0.0)


def test_models_refuse_bad_parameters():
    with pytest.raises(ValueError, match="E_g must be >= E_r"):
        sls(3e6, 1e6, 1e-3)
    with pytest.raises(ValueError, match="delta_E"):
        Prony(3e6, [-1.0], [1.0])
    with pytest.raises(ValueError, match="E''"):
        MasterCurve([1.0, 2.0], [1e6, 2e6], [1.0, -1.0])


def test_stieltjes_rule_is_exact_for_cubics_and_fourth_order():
    from xpersson_viscoelastic.kernel import stieltjes_increments

    x = np.sort(np.random.default_rng(1).uniform(0, 3, 9))
    inc = stieltjes_increments(x**2 - x, x**3, x)  # int (x^2 - x) 3x^2 dx, exact for cubics
    exact = lambda t: 0.6 * t**5 - 0.75 * t**4  # noqa: E731
    np.testing.assert_allclose(inc, exact(x[1:]) - exact(x[:-1]), rtol=1e-11, atol=1e-13)
    errs = []
    for n in (21, 41, 81):
        x = np.linspace(0.0, 2.0, n)
        total = stieltjes_increments(np.exp(-x), np.sin(x), x).sum()
        ref = 0.5 * (1 + np.exp(-2) * (np.sin(2) - np.cos(2)))  # int_0^2 e^-x cos x dx
        errs.append(abs(total - ref))
    assert errs[0] / errs[1] > 12 and errs[1] / errs[2] > 12  # ~16 for fourth order


def test_master_curve_angular_rule_integrates_the_interpolant():
    from scipy.integrate import quad

    model = sls(E_R, E_G, TAU)
    w = np.geomspace(1e-4, 1e10, 30) / TAU
    E = model.modulus(w)
    mc = MasterCurve(w, E.real, E.imag)
    W = 1e4 / TAU
    cuts = sorted({0.0, float(np.pi / 2), *np.arccos(np.clip(w / W, 0, 1)).tolist()})

    def parts(p):
        e1, e2 = mc._parts(np.array([W * np.cos(p)]))
        return float(e1[0]), float(e2[0])

    def piecewise(fn):  # adaptive quadrature on every smooth piece
        return sum(
            quad(fn, a, b, epsabs=0, epsrel=1e-11, limit=200)[0]
            for a, b in zip(cuts[:-1], cuts[1:], strict=True)
            if b > a
        )

    loss = 4 * piecewise(lambda p: np.cos(p) * parts(p)[1])
    sq = (2 / np.pi) * piecewise(lambda p: parts(p)[0] ** 2 + parts(p)[1] ** 2)
    got = mc.angular(W)
    assert got[0] == pytest.approx(sq, rel=1e-9)
    assert got[1] == pytest.approx(loss, rel=1e-9)


def test_master_curve_q_integrals_meet_rtol():
    from xpersson.physics import SelfAffineRollOff
    from xpersson_viscoelastic import kernel

    model = sls(E_R, E_G, TAU)
    w = np.geomspace(1e-4, 1e10, 60) / TAU
    E = model.modulus(w)
    mc = MasterCurve(w, E.real, E.imag)
    psd = SelfAffineRollOff.from_h_rms(1e-5, 0.8, 1e3, 1e4, 1e7)
    z = np.geomspace(1.5, 1e4, 6)
    ref = kernel.diffusion_time(psd, mc, 0.5, z, 0.01, nodes=16, panels_per_decade=32)
    got = kernel.diffusion_time(psd, mc, 0.5, z, 0.01)  # the coefficient's rtol >= 1e-6 rule
    np.testing.assert_allclose(got, ref, rtol=1e-6)


def test_prony_parts_in_passes_keep_shape_and_closed_forms():
    # more frequencies than one pass of Prony.parts (4096): the result keeps the input's shape
    # and every frequency matches its own evaluation and the closed form of the sls
    m = sls(3e6, 3e9, 1e-3)
    w = np.geomspace(1e-6, 1e12, 7 * 1800).reshape(7, -1)
    excess, loss = m.parts(w)
    assert excess.shape == loss.shape == w.shape
    k = [0, 4095, 4096, 4097, 8192, w.size - 1]
    one = [m.parts(w.flat[i]) for i in k]
    np.testing.assert_allclose(excess.flat[k], [e for e, _ in one], rtol=1e-14)
    np.testing.assert_allclose(loss.flat[k], [lo for _, lo in one], rtol=1e-14)
    b = w * 1e-3
    s = np.sqrt(1 + b * b)
    dE = 3e9 - 3e6
    np.testing.assert_allclose(loss, 2 * np.pi * dE * b / (s * (1 + s)), rtol=1e-13)
    c = 3e6 + dE / 2  # E_r + dE tau / (tau + tau)
    u = b * b / (s * (1 + s))  # 1 - 1/s without cancellation
    np.testing.assert_allclose(excess, 2 * dE * c * u, rtol=1e-13)
