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
