"""DiffusionClock: tau(zeta) and its inverse."""

from __future__ import annotations

import numpy as np
import pytest

from xpersson.physics import elastic
from xpersson.physics.psd import SelfAffineRollOff
from xpersson.plugins import DiffusionClock


@pytest.mark.parametrize("H", [0.1, 0.5, 0.8, 1.0])
def test_zeta_of_tau_inverts_tau_of_zeta(H):
    psd = SelfAffineRollOff.from_h_rms(1e-6, H, 1e3, 1e4, 1e11)
    E_star = 1e7

    def tau(z):
        return elastic.diffusion_time(psd, E_star, z)

    def f(z):
        return elastic.coefficient_f(psd, E_star, z)

    clock = DiffusionClock(tau, f, 1e8)
    z = np.geomspace(1.0 + 1e-9, 1e8, 300)
    back = clock.zeta_of_tau(clock.tau_of_zeta(z))
    np.testing.assert_allclose(back, z, rtol=1e-10)
    assert clock.zeta_of_tau(0.0) == 1.0


@pytest.mark.parametrize("H", [0.1, 0.8, 1.0])
def test_inverse_starts_close_and_polishes_in_two_newton_steps(H):
    # a roll-off knee (f has a kink at q_r) and the far tail: the cubic start with the exact
    # slopes 1/f leaves Newton two steps; the result is accurate to round-off
    psd = SelfAffineRollOff.from_h_rms(1e-6, H, 1e3, 1e4, 1e9)
    calls = []

    def f(z):
        calls.append(np.size(z))
        return elastic.coefficient_f(psd, 1e7, z)

    clock = DiffusionClock(lambda z: elastic.diffusion_time(psd, 1e7, z), f, 1e6)
    z = np.geomspace(1.0 + 1e-6, 1e6, 257)
    t = clock.tau_of_zeta(z)
    back = clock.zeta_of_tau(t)
    assert len(calls) <= 3  # table + two Newton steps
    np.testing.assert_allclose(back, z, rtol=1e-12)
    np.testing.assert_allclose(clock.tau_of_zeta(back), t, rtol=1e-9)


def test_earlier_times_are_looked_up_and_others_evaluated():
    # a subset of earlier times answers with the earlier values (bit for bit, no evaluation);
    # times that share the earlier first and last time but not the rest are evaluated
    psd = SelfAffineRollOff.from_h_rms(1e-6, 0.4, 1e3, 1e4, 1e9)
    calls = []

    def tau(z):
        calls.append(np.size(z))
        return elastic.diffusion_time(psd, 1e7, z)

    clock = DiffusionClock(tau, lambda z: elastic.coefficient_f(psd, 1e7, z), 1e6)
    t = clock.tau_of_zeta(np.geomspace(1.0 + 1e-6, 1e6, 201))
    z = clock.zeta_of_tau(t)
    n = len(calls)
    sub = clock.zeta_of_tau(t[[0, 7, 7, 150, 200]])
    assert len(calls) == n and sub.tobytes() == z[[0, 7, 7, 150, 200]].tobytes()
    mixed = np.array([t[0], 0.5 * (t[3] + t[4]), t[-1]])
    got = clock.zeta_of_tau(mixed)
    assert len(calls) > n
    fresh = DiffusionClock(tau, lambda z: elastic.coefficient_f(psd, 1e7, z), 1e6)
    assert got.tobytes() == fresh.zeta_of_tau(mixed).tobytes()
