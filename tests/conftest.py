"""Shared fixtures of the core test suite."""

from __future__ import annotations

import copy
from pathlib import Path

import pytest
from xpersson_core_reference import REFERENCE_SCENE

SHARED = Path(__file__).resolve().parents[1].parent / "shared"


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
