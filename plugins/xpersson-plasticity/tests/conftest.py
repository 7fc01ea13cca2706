"""Fixtures of the xpersson-plasticity tests."""

from __future__ import annotations

import pytest


@pytest.fixture
def engine():
    """The diffusion engine, or skip."""
    eng = pytest.importorskip("xpersson.engine", reason="xpersson.engine not available yet")
    if not hasattr(eng, "solve"):
        pytest.skip("xpersson.engine.solve not available yet")
    return eng
