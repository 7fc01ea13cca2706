"""What ``jkr`` derives from a spectrum is computed once per content (:mod:`xpersson.cache`):
the values are those of a fresh computation (caches off), shared read-only, never leak into a
returned Dataset; and its pull-off never falls back silently to another policy."""

from __future__ import annotations

import copy
import pickle
import warnings

import numpy as np
import pytest
from adhesion_testlib import PDMS

import xpersson
from xpersson.cache import cache
from xpersson.physics import SelfAffineRollOff, coefficient_f, diffusion_time
from xpersson.plugins import DiffusionClock, SceneContext
from xpersson_adhesion import JKRBoundary
from xpersson_adhesion._detachment import ModelLaw
from xpersson_adhesion._wallpos import onset_times, starts_at_zero
from xpersson_adhesion.jkr import stickiness

E_STAR = 1e6 / 0.75


def _frozen() -> SelfAffineRollOff:
    return SelfAffineRollOff.from_h_rms(1e-6, 0.8, 1e3, 1e4, 1e7).freeze()


def _clock(psd: object, e_star: float = E_STAR) -> DiffusionClock:
    return DiffusionClock(
        lambda z: diffusion_time(psd, e_star, z), lambda z: coefficient_f(psd, e_star, z), 1e4
    )


def _ctx(psd: object, p0: float = 1e3) -> SceneContext:
    return SceneContext(
        psd=psd,
        E=1e6,
        nu=0.5,
        E_star=E_STAR,
        p0=np.array([p0]),
        zeta=np.geomspace(1.0, 1e4, 9),
        p=None,
        rtol=1e-6,
        atol=0.0,
        method="auto",
    )


@pytest.fixture
def caches_on():
    """The caches on, also in CI's run with XPERSSON_CACHE=off."""
    with xpersson.set_options(cache=True):
        yield


def test_stickiness_is_computed_once_per_spectrum_content(caches_on):
    store = cache("adhesion.stickiness")
    store.clear()
    first = stickiness(_frozen(), E_STAR, 0.03)
    again = stickiness(SelfAffineRollOff.from_h_rms(1e-6, 0.8, 1e3, 1e4, 1e7), E_STAR, 0.03)
    assert again == first and (store.hits, store.misses) == (1, 1)  # equal content: one value
    stickiness(_frozen(), E_STAR, 0.04)  # another work of adhesion: another value
    assert store.misses == 2
    with xpersson.set_options(cache=False):
        assert stickiness(_frozen(), E_STAR, 0.03) == first


def test_cached_table_equals_a_fresh_one_and_follows_the_clock(caches_on):
    psd = _frozen()
    law = ModelLaw(psd, E_STAR, 0.03, 1.0)
    clock = _clock(psd)
    table = law.in_tau(clock)
    assert law.in_tau(_clock(psd)) is table  # an equal clock: the same table
    with xpersson.set_options(cache=False):
        ref = ModelLaw(_frozen(), E_STAR, 0.03, 1.0).in_tau(_clock(psd))
    assert ref is not table
    t = float(clock.tau_of_zeta(1e4)) * np.linspace(0.0, 1.0, 101)
    np.testing.assert_array_equal(table(t), ref(t))
    np.testing.assert_array_equal(onset_times(table), onset_times(ref))
    # sigma_a(tau = 0) = 0, found once with the onsets, is what evaluating the table says
    for t_ in (table, ref, lambda t: np.full(np.shape(t), 2.0), lambda t: np.zeros(np.shape(t))):
        assert starts_at_zero(t_) is (float(t_(np.zeros(1))[0]) == 0.0)
    # another modulus: another clock and another law, another table
    other = ModelLaw(psd, 2 * E_STAR, 0.03, 1.0).in_tau(_clock(psd, 2 * E_STAR))
    assert other is not table and not np.array_equal(other(t[1:]), table(t[1:]))


def test_repeated_solves_are_identical_and_own_their_arrays(solve):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        first = solve(copy.deepcopy(PDMS))
        second = solve(copy.deepcopy(PDMS))
    for name in ("area_fraction", "sigma_a", "gamma_eff", "true_area_ratio", "tabor_parameter"):
        np.testing.assert_array_equal(first[name].values, second[name].values)
    for name in ("gamma_eff", "true_area_ratio", "finer_scale_energy", "tabor_parameter"):
        values = second[name].values
        assert values.flags.writeable
        values[...] = -1.0  # the caller's copy: the next solve is unaffected
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        third = solve(copy.deepcopy(PDMS))
    np.testing.assert_array_equal(first["tabor_parameter"].values, third["tabor_parameter"].values)
    np.testing.assert_array_equal(first["gamma_eff"].values, third["gamma_eff"].values)


def test_pull_off_at_an_area_never_falls_back_to_sigma_a():
    """``pull_off_area > 0`` solves the wall of the scene's clock: without the clock it is an
    error (it used to return sigma_a(1), the other policy, silently): interpret() passes
    ``ctx.clock``, so a context without the run's clock cannot give the pull-off."""
    psd = _frozen()
    ctx, clock = _ctx(psd), _clock(psd)
    bnd = JKRBoundary(work_of_adhesion=0.03, pull_off_area=1e-3)
    s1 = bnd.sigma_a_start(ctx)
    tau_end = float(clock.tau_of_zeta(1e4))
    with pytest.raises(ValueError, match="pull_off_area = 0.001 .* diffusion clock"):
        bnd.pull_off(ctx, tau_end)
    solved = bnd.pull_off(ctx, tau_end, clock)
    assert 0.0 < solved < s1  # the area policy, not sigma_a(1)
    with xpersson.set_options(cache=False):
        assert bnd.pull_off(ctx, tau_end, clock) == solved
    before = pickle.dumps(bnd)
    bnd.walls(ctx, 1e3, clock)
    assert pickle.dumps(bnd) == before  # walls() keeps nothing for interpret() on the instance
    assert ctx.clock is None
    with pytest.raises(ValueError, match="diffusion clock"):
        bnd.pull_off(ctx, tau_end, ctx.clock)
    assert JKRBoundary(work_of_adhesion=0.03).pull_off(ctx, tau_end) == s1  # the default policy


def test_sigma_a_at_the_grid_ends_equals_the_law_bit_for_bit():
    """sigma_a(1) and sigma_a(zeta_max) read from the cached gamma_eff are the law's."""
    psd = _frozen()
    for work in (0.03, 1e-6):
        ctx = _ctx(psd)
        ctx = SceneContext(**{**ctx.__dict__, "zeta": np.geomspace(1.0, 300.0, 9)})
        bnd = JKRBoundary(work_of_adhesion=work)
        law = bnd._model(ctx)
        for z in (1.0, 300.0, 17.0):  # the ends from the cache, an inner value from the law
            assert bnd._at(ctx, law, z) == float(law(np.array([z]))[0])
        assert bnd.sigma_a_start(ctx) == float(law(np.array([1.0]))[0])
    assert law.is_constant(300.0) == bool(np.all(law(np.geomspace(1.0, 300.0, 257)) == 0.0))
