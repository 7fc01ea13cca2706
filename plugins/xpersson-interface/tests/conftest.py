"""Shared fixtures: the physics.md §1.4 scene, the Zhou (GFMD) scene and the reference data."""

from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np
import pytest

try:  # the core may not be installed yet: fall back to the source tree
    import xpersson  # noqa: F401
except ImportError:  # pragma: no cover
    sys.path.insert(0, str(Path(__file__).resolve().parents[3] / "src"))
try:
    import xpersson_interface  # noqa: F401
except ImportError:  # pragma: no cover
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

from xpersson.physics.psd import SelfAffineRollOff  # noqa: E402

E_STAR = 10e6 / (1.0 - 0.5**2)  # §1.4: E = 10 MPa, nu = 0.5
H_RMS_ZHOU = 6e-6

#: /work/main/plugins/xpersson-interface/tests -> /work/shared/refdata/xu2024-gfmd
REFDATA = Path(
    os.environ.get(
        "XPERSSON_REFDATA",
        Path(__file__).resolve().parents[4] / "shared" / "refdata",
    )
) / "xu2024-gfmd"


@pytest.fixture(scope="session")
def psd():
    """physics.md §1.4: H = 0.8, q_L = 1e3, q_r = 1e4, q_1 = 1e8 1/m, h_rms = 1 um."""
    return SelfAffineRollOff.from_h_rms(1e-6, 0.8, 1e3, 1e4, 1e8)


@pytest.fixture(scope="session")
def zhou():
    """Zhou/GFMD scene: E* = 1 Pa, C = C0 q^-3.6 on [1e4, 1e6] 1/m, h_rms = 6 um."""
    return SelfAffineRollOff.from_h_rms(H_RMS_ZHOU, 0.8, 1e4, 1e4, 1e6)


def read_csv(name: str) -> dict[str, np.ndarray]:
    """Read one reference CSV (``#`` comments, one header line); skip when absent."""
    path = REFDATA / name
    if not path.is_file():
        pytest.skip(f"reference data not found: {path} (set XPERSSON_REFDATA)")
    lines = [ln for ln in path.read_text().splitlines() if ln and not ln.startswith("#")]
    names = lines[0].split(",")
    data = np.array([[float(x) for x in ln.split(",")] for ln in lines[1:]])
    return {n: data[:, i] for i, n in enumerate(names)}
