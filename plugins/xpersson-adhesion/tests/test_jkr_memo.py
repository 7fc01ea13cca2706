"""What ``jkr`` derives from a frozen spectrum is computed once
(``xpersson.physics.spectrum_memo``): the values are those of a fresh computation, shared
read-only, and never leak into a returned Dataset."""

from __future__ import annotations

import copy
import warnings

import numpy as np
from adhesion_testlib import PDMS, PSD

from xpersson.physics import SelfAffineRollOff, coefficient_f, diffusion_time
from xpersson.physics import spectrum_memo as memo
from xpersson.plugins import DiffusionClock
from xpersson_adhesion._detachment import ModelLaw, onset_times

E_STAR = 1e6 / 0.75


def _frozen() -> SelfAffineRollOff:
    return SelfAffineRollOff.from_h_rms(1e-6, 0.8, 1e3, 1e4, 1e7).freeze()


def _clock(psd: object) -> DiffusionClock:
    return DiffusionClock(
        lambda z: diffusion_time(psd, E_STAR, z), lambda z: coefficient_f(psd, E_STAR, z), 1e4
    )


def test_memo_computes_once_per_frozen_spectrum_and_key():
    psd, calls = _frozen(), []

    def compute() -> tuple[np.ndarray, float]:
        calls.append(1)
        return np.arange(3.0), 2.5

    first = memo(psd, ("k", 1.0), compute)
    again = memo(psd, ("k", 1.0), compute)
    assert again is first and len(calls) == 1
    assert not first[0].flags.writeable  # shared: read-only
    memo(psd, ("k", 2.0), compute)  # another key
    memo(_frozen(), ("k", 1.0), compute)  # another (equal but distinct) spectrum
    assert len(calls) == 3


def test_memo_does_not_keep_results_of_a_mutable_spectrum():
    calls = []
    assert not PSD.frozen
    for _ in range(2):
        memo(PSD, ("k",), lambda: calls.append(1) or 1.0)
    assert len(calls) == 2


def test_memoised_table_equals_a_fresh_one_and_follows_the_clock():
    psd = _frozen()
    law = ModelLaw(psd, E_STAR, 0.03, 1.0)
    clock = _clock(psd)
    table = law.in_tau(clock)
    assert law.in_tau(_clock(psd)) is table  # an equal clock: the same table
    fresh = ModelLaw(SelfAffineRollOff.from_h_rms(1e-6, 0.8, 1e3, 1e4, 1e7), E_STAR, 0.03, 1.0)
    ref = fresh.in_tau(_clock(fresh.psd))  # a spectrum that is not frozen: no memo
    t = float(clock.tau_of_zeta(1e4)) * np.linspace(0.0, 1.0, 101)
    np.testing.assert_array_equal(table(t), ref(t))
    np.testing.assert_array_equal(onset_times(table), onset_times(ref))
    # another modulus: another clock and another law, another table
    other = ModelLaw(psd, 2 * E_STAR, 0.03, 1.0).in_tau(
        DiffusionClock(
            lambda z: diffusion_time(psd, 2 * E_STAR, z),
            lambda z: coefficient_f(psd, 2 * E_STAR, z),
            1e4,
        )
    )
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


def test_memo_keeps_a_bounded_number_of_results():
    from xpersson.physics import _memo

    spectra = [_frozen() for _ in range(3)]
    for i in range(3 * _memo._MEMO_SIZE):
        memo(spectra[i % 3], ("bound", i), lambda i=i: float(i))
    kept = sum(1 for psd in spectra for key in _memo._MEMO.get(psd, {}) if key[0] == "bound")
    assert kept <= _memo._MEMO_SIZE
    calls = []
    last = 3 * _memo._MEMO_SIZE - 1
    assert memo(spectra[last % 3], ("bound", last), lambda: calls.append(1)) == float(last)
    assert not calls  # the newest result is still there
    memo(spectra[0], ("bound", 0), lambda: calls.append(1))
    assert calls  # the oldest was dropped


def test_digest_tells_arrays_apart():
    from xpersson.physics import array_digest as digest

    a = np.linspace(0.0, 1.0, 1000)
    b = a.copy()
    b[500] = np.nextafter(b[500], 2.0)
    assert digest(a) == digest(a.copy()) != digest(b)
    assert digest(a, b) != digest(b, a)


def test_sigma_a_at_the_grid_ends_equals_the_law_bit_for_bit():
    """sigma_a(1) and sigma_a(zeta_max) read from the memoised gamma_eff are the law's."""
    from xpersson.plugins import SceneContext
    from xpersson_adhesion import JKRBoundary

    psd = _frozen()
    for work in (0.03, 1e-6):
        zeta = np.geomspace(1.0, 300.0, 9)
        ctx = SceneContext(
            psd=psd,
            E=1e6,
            nu=0.5,
            E_star=E_STAR,
            p0=np.array([1e3]),
            zeta=zeta,
            p=None,
            rtol=1e-6,
            atol=0.0,
            method="auto",
        )
        bnd = JKRBoundary(work_of_adhesion=work)
        law = bnd._model(ctx)
        for z in (1.0, 300.0, 17.0):  # the ends from the memo, an inner value from the law
            assert bnd._at(ctx, law, z) == float(law(np.array([z]))[0])
        assert bnd.sigma_a_start(ctx) == float(law(np.array([1.0]))[0])
    assert law.is_constant(300.0) == bool(np.all(law(np.geomspace(1.0, 300.0, 257)) == 0.0))
