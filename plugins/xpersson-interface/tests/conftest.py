"""Shared fixtures: the physics.md §1.4 scene and the Zhou (GFMD) scene."""

from __future__ import annotations

import pytest
from interface_testlib import H_RMS_ZHOU

from xpersson.physics.psd import SelfAffineRollOff


@pytest.fixture(scope="session")
def psd():
    """physics.md §1.4: H = 0.8, q_L = 1e3, q_r = 1e4, q_1 = 1e8 1/m, h_rms = 1 um."""
    return SelfAffineRollOff.from_h_rms(1e-6, 0.8, 1e3, 1e4, 1e8)


@pytest.fixture(scope="session")
def zhou():
    """Zhou/GFMD scene: E* = 1 Pa, C = C0 q^-3.6 on [1e4, 1e6] 1/m, h_rms = 6 um."""
    return SelfAffineRollOff.from_h_rms(H_RMS_ZHOU, 0.8, 1e4, 1e4, 1e6)
