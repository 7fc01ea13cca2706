"""Fixtures of the xpersson-adhesion tests."""

from __future__ import annotations

import pytest


@pytest.fixture(scope="session")
def solve():
    """xpersson.solve (the core pipeline)."""
    import xpersson

    return xpersson.solve


@pytest.fixture(autouse=True, scope="session")
def _adhesive_registered():
    """``adhesive`` in the registry even when the installed entry points predate it."""
    from xpersson.plugins import get_registry
    from xpersson_adhesion.adhesive import AdhesiveBoundary

    reg = get_registry()
    if "adhesive" not in reg.names("boundaries"):
        reg.register("boundaries", "adhesive", AdhesiveBoundary)
