"""The fixed costs of a spectral sweep cut without changing a bit: the elastic coefficient's
stacked tau and f, I3 on an output grid kept per spectrum, the self-affine spectrum built from
its rms height or slope without a unit spectrum."""

from __future__ import annotations

import numpy as np
import pytest

import xpersson
from xpersson.builtin.elastic import ElasticCoefficient
from xpersson.physics._self_affine import SelfAffineRollOff
from xpersson.physics._spectrum import PowerSpectrum
from xpersson.plugins import Coefficient, SceneContext


def _spectra(n: int, seed: int) -> list[SelfAffineRollOff]:
    rng = np.random.default_rng(seed)
    out = []
    for k in range(n):
        H, q_L = rng.uniform(0.3, 1.0), 10 ** rng.uniform(2, 4)
        q_r = q_L * (10 ** rng.uniform(0, 1) if k % 2 else 1.0)
        out.append(SelfAffineRollOff.from_h_rms(1e-6, H, q_L, q_r, q_r * 10**4).freeze())
    return out


def test_the_stacked_tau_and_f_are_the_per_point_numbers_bit_for_bit():
    zeta = np.geomspace(1.0, 1e3, 41)
    rng = np.random.default_rng(7)
    ctxs = [
        SceneContext(
            psd=p, E=E, nu=0.3, E_star=E / 0.91, p0=np.array([1e5]), zeta=zeta, rtol=1e-6, atol=0.0
        )  # fmt: skip
        for p, E in zip(_spectra(12, 1), 10 ** rng.uniform(5, 11, 12), strict=True)
    ]
    points = [ElasticCoefficient() for _ in ctxs]
    tau, f = points[0].tau_stacked(ctxs, points, zeta)
    plain_tau, plain_f = Coefficient.tau_stacked(points[0], ctxs, points, zeta)
    assert tau.shape == f.shape == (12, 41)
    assert np.array_equal(tau, plain_tau) and np.array_equal(f, plain_f)


def test_a_subclass_that_redefines_tau_is_asked_per_point():
    class Doubled(ElasticCoefficient):
        def tau(self, ctx, zeta):
            return 2.0 * super().tau(ctx, zeta)

    zeta = np.geomspace(1.0, 1e2, 9)
    ctxs = [
        SceneContext(
            psd=p, E=1e7, nu=0.5, E_star=4e7 / 3, p0=np.array([1e5]), zeta=zeta, rtol=1e-6, atol=0.0
        )  # fmt: skip
        for p in _spectra(3, 2)
    ]
    points = [Doubled() for _ in ctxs]
    tau, _ = points[0].tau_stacked(ctxs, points, zeta)
    plain = [ElasticCoefficient() for _ in ctxs]
    assert np.array_equal(tau, 2.0 * plain[0].tau_stacked(ctxs, plain, zeta)[0])


def test_I3_on_a_grid_is_kept_per_spectrum_and_read_only():
    psd = _spectra(1, 3)[0]
    q = psd.q_L * np.geomspace(1.0, 1e4, 50)
    with xpersson.set_options(cache=True):
        first = psd.I3(q)
        again = psd.I3(q.copy())  # equal content: the same array
        assert again is first and not first.flags.writeable
        assert np.array_equal(first, PowerSpectrum.running_moment(psd, 3.0, q))
        other = psd.I3(q[:-1])
        assert other is not first and np.array_equal(other, first[:-1])


def test_the_scene_check_and_the_coefficient_share_one_I3():
    from xpersson.physics import _spectrum

    scene = {
        "spectrum": {"model": "self_affine", "H": 0.71, "q_L": "1.3e3 1/m", "q_r": "5e3 1/m",
                     "q_1": "1e7 1/m", "h_rms": "1 um"},
        "material": {"E": "10 MPa", "nu": 0.5},
        "load": {"p0": "1 MPa"},
    }  # fmt: skip
    cache = _spectrum._I3_GRID
    with xpersson.set_options(cache=True):
        cache.clear()
        hits, misses = cache.hits, cache.misses
        xpersson.solve(scene)
        assert cache.misses - misses == 1 and cache.hits - hits >= 1


@pytest.mark.parametrize("k", [1.0, 3.0])
def test_the_spectrum_from_its_rms_height_or_slope_is_unchanged(k):
    rng = np.random.default_rng(11)
    for i in range(200):
        H = 1.0 if i % 10 == 0 else float(rng.uniform(0.05, 1.0))
        q_L = float(10 ** rng.uniform(0, 5))
        q_r = q_L * float(10 ** rng.uniform(0, 1.5)) if i % 3 else q_L
        q_1 = q_r * float(10 ** rng.uniform(0.01, 6))
        x = float(10 ** rng.uniform(-9, -3))
        unit = SelfAffineRollOff(1.0, H, q_L, q_r, q_1)
        C_r = x**2 / (2.0 * np.pi * unit._moment(k, q_L, q_1))
        build = SelfAffineRollOff.from_h_rms if k == 1.0 else SelfAffineRollOff.from_rms_slope
        assert build(x, H, q_L, q_r, q_1).C_r == C_r


def test_a_bad_parameter_of_a_spectrum_from_its_rms_height_names_it():
    with pytest.raises(ValueError, match="q_r must satisfy"):
        SelfAffineRollOff.from_h_rms(1e-6, 0.8, 1e3, 1e2, 1e6)


def test_stacked_C_is_each_spectrum_C_bit_for_bit_and_declines_mixed_blocks():
    from xpersson.physics.psd import stacked_C

    psds = _spectra(9, 5)[1::2] + _spectra(9, 6)[1::2]  # plateau + tail: two segments each
    assert len(psds) == 8 and all(p.nodes().size == 3 for p in psds)
    q = np.stack([p.q_L * np.geomspace(0.5, 2e4, 33) for p in psds])  # outside the support too
    got = stacked_C(psds, q)
    want = np.stack([p.C(row) for p, row in zip(psds, q, strict=True)])
    assert np.array_equal(got.view(np.uint64), want.view(np.uint64))
    flat = SelfAffineRollOff.from_h_rms(1e-6, 0.8, 1e3, 1e3, 1e7)  # one segment
    assert stacked_C([psds[0], flat], q[:2]) is None

    class Scaled(SelfAffineRollOff):
        def C(self, q):
            return 2.0 * super().C(q)

    scaled = Scaled(1e-12, 0.8, 1e3, 1e3, 1e7)
    assert stacked_C([scaled, scaled], q[:2]) is None
