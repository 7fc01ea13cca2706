"""Shared fixtures of the core test suite."""

from __future__ import annotations

import copy
from pathlib import Path

import pytest

SHARED = Path(__file__).resolve().parents[1].parent / "shared"

# physics.md §1.4 parameter set
REFERENCE_SCENE = {
    "spectrum": {
        "model": "self_affine",
        "H": 0.8,
        "q_L": "1e3 1/m",
        "q_r": "1e4 1/m",
        "q_1": "1e8 1/m",
        "h_rms": "1 um",
    },
    "material": {"E": "10 MPa", "nu": 0.5},
    "load": {"p0": ["1e4 Pa", "1e5 Pa", "1e6 Pa"]},
}


@pytest.fixture
def scene() -> dict:
    """A fresh copy of the physics.md §1.4 reference scene (three loads)."""
    return copy.deepcopy(REFERENCE_SCENE)


@pytest.fixture
def refdata() -> Path:
    """The shared GFMD reference data folder (skips when absent)."""
    path = SHARED / "refdata" / "xu2024-gfmd"
    if not path.is_dir():
        pytest.skip(f"reference data not available at {path}")
    return path
