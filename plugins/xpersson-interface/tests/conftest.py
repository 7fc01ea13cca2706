"""Shared fixtures: the physics.md §1.4 scene, the Zhou (GFMD) scene, and leakage at 1000
loads through the load table and directly."""

from __future__ import annotations

import json
from collections.abc import Callable

import numpy as np
import pytest
from interface_testlib import H_RMS_ZHOU

import xpersson
from xpersson.physics.psd import SelfAffineRollOff
from xpersson_interface import _by_load as by_load_mod


@pytest.fixture(scope="session")
def psd():
    """physics.md §1.4: H = 0.8, q_L = 1e3, q_r = 1e4, q_1 = 1e8 1/m, h_rms = 1 um."""
    return SelfAffineRollOff.from_h_rms(1e-6, 0.8, 1e3, 1e4, 1e8)


@pytest.fixture(scope="session")
def zhou():
    """Zhou/GFMD scene: E* = 1 Pa, C = C0 q^-3.6 on [1e4, 1e6] 1/m, h_rms = 6 um."""
    return SelfAffineRollOff.from_h_rms(H_RMS_ZHOU, 0.8, 1e4, 1e4, 1e6)


@pytest.fixture(scope="session")
def leak_1000() -> Callable[[dict], tuple]:
    """``pair(spectrum)``: the leak analysis at 1000 loads (1 kPa - 1 MPa, the speed design's
    50 output magnifications) through the load table (its own settings) and with every load
    computed directly, as ``(table, direct)`` Datasets; each spectrum solved once a session."""
    done: dict[str, tuple] = {}

    def pair(spectrum: dict) -> tuple:
        key = json.dumps(spectrum, sort_keys=True)
        if key not in done:
            sc = {
                "spectrum": spectrum,
                "material": {"E": "10 MPa", "nu": 0.5},
                "load": {"p0": {"start": "1000.0 Pa", "stop": "1000000.0 Pa", "num": 1000}},
                "output": {"zeta": [float(z) for z in np.geomspace(1.0, 1e3, 50)]},
                "analyses": {"leakage": {}},
            }
            table = xpersson.solve(sc)
            with pytest.MonkeyPatch.context() as mp:
                mp.setattr(by_load_mod, "TABLE_MIN", 10**9)
                done[key] = (table, xpersson.solve(sc))
        return done[key]

    return pair
