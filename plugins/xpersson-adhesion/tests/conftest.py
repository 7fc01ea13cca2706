"""Fixtures of the xpersson-adhesion tests."""

from __future__ import annotations

import pytest


@pytest.fixture(scope="session")
def solve():
    """xpersson.solve (the core pipeline)."""
    import xpersson

    return xpersson.solve
