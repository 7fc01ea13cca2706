"""The detachment-stress model: true-area ratio, gamma_eff, sigma_a, Tabor parameter."""

from __future__ import annotations

import math

import numpy as np
from adhesion_testlib import PSD
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import quad

import xpersson
from xpersson.physics import coefficient_f, diffusion_time
from xpersson_adhesion import (
    detachment_stress,
    gamma_effective,
    stickiness,
    tabor_parameter,
    true_area_ratio,
)
from xpersson_adhesion._detachment import ModelLaw, TableLaw, true_area_slope
from xpersson_adhesion._wallpos import DetachmentWall

E_STAR = 4.0e6 / 3.0


@given(st.floats(1e-8, 1e3))
@settings(max_examples=40, deadline=None)
def test_true_area_ratio_is_the_exponential_average(s2):
    exact, _ = quad(
        lambda x: math.exp(-x) * math.sqrt(1 + s2 * x), 0, np.inf, epsabs=0, epsrel=1e-12
    )
    assert abs(float(true_area_ratio(s2)) - exact) <= 1e-10 * exact


def test_true_area_ratio_limits():
    xi2 = np.array([0.0, 1e-12, 1e-6, 1e-3])
    series = 1 + xi2 / 2 - xi2**2 / 4 + 3 * xi2**3 / 8
    np.testing.assert_allclose(true_area_ratio(xi2), series, rtol=1e-12)
    assert np.all(np.diff(true_area_ratio(np.geomspace(1e-6, 1e6, 50))) > 0)


def test_gamma_eff_energy_balance():
    zeta = np.geomspace(1.0, 1e4, 30)
    work = 0.04
    gamma, raw, a_star, energy = gamma_effective(PSD, E_STAR, work, zeta)
    a_star_1 = float(true_area_ratio(2 * math.pi * PSD.I3(PSD.q_1)))
    # gamma_eff A*(zeta) = dgamma A*(zeta_1) - U_el(zeta)
    np.testing.assert_allclose(raw * a_star, work * a_star_1 - energy, rtol=1e-12)
    np.testing.assert_array_equal(gamma, np.maximum(raw, 0.0))
    # U_el(zeta) = (pi E*/2) int_{zeta q_L}^{q_1} q^2 C dq, by quadrature of the spectrum
    for z, u in zip(zeta[::7], energy[::7], strict=True):
        q = np.geomspace(z * PSD.q_L, PSD.q_1, 20001)
        ref = 0.5 * math.pi * E_STAR * np.trapezoid(q**2 * PSD.C(q), q)
        assert abs(u - ref) <= 1e-6 * max(ref, 1e-30) + 1e-20
    # the full band at zeta = 1 is the full-contact energy of physics.md §5.1 -> w_eff
    w = stickiness(PSD, E_STAR, work)
    assert abs(w - (work * a_star_1 - energy[0])) < 1e-15
    # gamma_eff rises towards the finest scale, where it reaches the work of adhesion
    assert np.all(np.diff(raw) > 0)
    np.testing.assert_allclose(raw[-1], work, rtol=1e-12)


def test_sigma_a_formula_and_clipping():
    gamma = np.array([-1.0, 0.0, 0.01, 0.1])
    q = np.array([1e3, 1e4, 1e5, 1e6])
    for c_a in (1.0, 2.0, 8 / math.pi, 16 / math.pi**2):
        s = detachment_stress(gamma, E_STAR, q, c_a)
        np.testing.assert_allclose(s, np.sqrt(c_a * np.maximum(gamma, 0) * E_STAR * q))
        assert s[0] == 0.0 and s[1] == 0.0


def test_table_is_pchip_in_tau_and_exact_for_affine_data():
    zeta = np.array([1.0, 3.0, 10.0, 100.0])

    def tau_of(z):
        return 5.0 * (np.asarray(z) ** 2 - 1.0)

    law = TableLaw(zeta, 0.3 + 0.7 * tau_of(zeta))
    f = law.in_tau(tau_of)
    t = np.linspace(0.0, tau_of(100.0), 101)
    np.testing.assert_allclose(f(t), 0.3 + 0.7 * t, rtol=1e-13)
    assert TableLaw([1.0], [5.0]).is_constant


def test_tabor_parameter_scaling():
    zeta = np.geomspace(1.0, 1e4, 9)
    mu1 = tabor_parameter(PSD, E_STAR, 0.05, 1e-9, zeta)
    mu2 = tabor_parameter(PSD, E_STAR, 0.10, 2e-9, zeta)
    # mu ~ (dgamma^2 / dr^3)^(1/3): doubling both multiplies by (4/8)^(1/3)
    np.testing.assert_allclose(mu2 / mu1, 0.5 ** (1 / 3), rtol=1e-12)
    assert np.all(mu1 > 0) and np.all(np.isfinite(mu1))
    # finer scales have sharper asperities (smaller R) -> smaller mu_T
    assert mu1[-1] < mu1[0]


def test_true_area_slope_is_the_derivative():
    a = np.array([0.0, 1e-6, 5e-5, 2e-4, 1e-2, 0.5, 3.0, 50.0])
    h = 1e-6 * np.maximum(a, 1e-3)
    fd = (true_area_ratio(a + h) - true_area_ratio(np.maximum(a - h, 0))) / (
        a + h - np.maximum(a - h, 0)
    )
    np.testing.assert_allclose(true_area_slope(a), fd, rtol=1e-6)


def test_tabulated_model_wall_matches_the_exact_law():
    from xpersson.plugins import DiffusionClock

    law = ModelLaw(PSD, E_STAR, 0.03, 1.0)
    clock = DiffusionClock(
        lambda z: diffusion_time(PSD, E_STAR, z), lambda z: coefficient_f(PSD, E_STAR, z), 1e4
    )
    # the slope of sigma^2 is the derivative of sigma^2 (finite differences in zeta)
    z = np.geomspace(1.5, 9e3, 25)
    s2, ds2 = law.sigma2_and_slope(z)
    fd = (law.sigma2_and_slope(z * (1 + 1e-6))[0] - law.sigma2_and_slope(z * (1 - 1e-6))[0]) / (
        2e-6 * z
    )
    np.testing.assert_allclose(ds2, fd, rtol=1e-5, atol=1e-9 * np.max(np.abs(s2)))
    # the Hermite table in tau against sigma_a(zeta(tau)) evaluated exactly
    fast = DetachmentWall(law.in_tau(clock))
    exact = DetachmentWall(law=law, clock=clock)
    t = float(clock.tau_of_zeta(1e4)) * np.concatenate(
        [np.logspace(-12, 0, 300), np.linspace(0, 1, 301)]
    )
    ref = exact.sigma(t)
    assert np.max(np.abs(fast.sigma(t) - ref)) <= 1e-9 * np.max(ref)
    np.testing.assert_array_equal(fast(t), -fast.sigma(t))


@given(st.integers(2, 60), st.integers(0, 2**32 - 1), st.floats(-2.0, 2.0))
@settings(max_examples=60, deadline=None)
def test_onset_roots_are_the_roots_of_the_whole_table(n, seed, shift):
    """onset_times solves only the pieces of sigma_a^2 that can hold a root: the same roots as
    PPoly.roots over every piece."""
    from scipy.interpolate import CubicHermiteSpline, PPoly

    from xpersson_adhesion._wallpos import _cubic_roots

    rng = np.random.default_rng(seed)
    x = np.cumsum(rng.random(n + 1) + 0.01)
    y = rng.normal(size=n + 1) + shift
    y[rng.integers(0, n + 1)] = 0.0  # a root on a node
    sp = CubicHermiteSpline(x, y, rng.normal(size=n + 1))
    poly = PPoly(sp.c, sp.x, extrapolate=False)
    full = np.unique(np.asarray(poly.roots(extrapolate=False)))
    full = full[np.isfinite(full)]
    fast = _cubic_roots(poly)
    fast = fast[np.isfinite(fast)]
    np.testing.assert_allclose(fast, full, rtol=0, atol=1e-12 * x[-1])


def test_detachment_walls_equal_by_content_key():
    """Walls built from the same content are equal and hash equal (the engine then solves
    their loads in one batch on the plain path as on the shared-walls path); without a key a
    wall equals only itself."""
    f = lambda t: np.zeros_like(t)  # noqa: E731
    a, b = DetachmentWall(f, key=("model", 1.0)), DetachmentWall(f, key=("model", 1.0))
    assert a == b and hash(a) == hash(b) and len({a, b}) == 1
    assert a != DetachmentWall(f, key=("model", 2.0))
    plain = DetachmentWall(f)
    assert plain == plain and plain != DetachmentWall(f) and a != plain


def test_table_keyed_on_the_clock_is_the_sampled_table():
    """A clock with a content key (the pipeline's, Coefficient.clock_key) keys the table on
    it without sampling the clock: the same table bit for bit as the one keyed on the
    clock's samples, and equal keys for equal clocks (the loads' walls stay one batch)."""
    from xpersson.cache import clear_caches, content_key
    from xpersson.options import cache_enabled
    from xpersson.plugins import DiffusionClock

    law = ModelLaw(PSD, E_STAR, 0.03, 1.0)

    def clock(key=None):
        return DiffusionClock(
            lambda z: diffusion_time(PSD, E_STAR, z),
            lambda z: coefficient_f(PSD, E_STAR, z),
            1e4,
            key=key,
        )

    key = content_key(("elastic", PSD, E_STAR))
    clear_caches()
    by_clock, ck = law.table_and_key(clock(key))
    by_samples, ck_samples = law.table_and_key(clock())
    assert ck != ck_samples  # two kinds of key: each compares with its own kind
    a, b = by_clock.spline.poly, by_samples.spline.poly
    np.testing.assert_array_equal(a.c, b.c)
    np.testing.assert_array_equal(a.x, b.x)
    again, ck_again = law.table_and_key(clock(key))
    assert ck_again == ck
    if cache_enabled():  # kept: the clock is not sampled again
        assert again is by_clock
    assert DetachmentWall(by_clock, key=ck) == DetachmentWall(again, key=ck_again)


def test_finer_scale_energy_is_zero_not_rounding_below_at_the_finest_scale():
    """A held-out scene (engine_limit seed 404) whose last output magnification rounds just under
    q_1/q_L: the finer scales' energy there is exactly 0 (no scales left), never -1e-16 (which
    failed the solve on valid_min = 0), and the energy never increases with zeta."""
    scene = {
        "spectrum": {
            "model": "self_affine",
            "H": 0.3197,
            "q_L": "9301.595147526405 1/m",
            "q_r": "36897.87491679483 1/m",
            "q_1": "930159514.7526405 1/m",
            "h_rms": "1 um",
        },
        "material": {"E": "1 MPa", "nu": 0.5},
        "load": {"p0": "1000 Pa"},
        "output": {"zeta_per_decade": 4},
        "boundary": {"model": "jkr", "work_of_adhesion": "0.05 J/m**2"},
        "solver": {"rtol": 1e-06, "method": "cn"},
    }
    energy = xpersson.solve(scene)["finer_scale_energy"].values
    assert energy[-1] == 0.0
    assert np.all(np.diff(energy) <= 0.0)
