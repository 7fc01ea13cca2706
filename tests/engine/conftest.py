"""Engine test helpers: make ``xpersson`` importable from the source tree, load the peer scenes."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

_SRC = Path(__file__).resolve().parents[2] / "src"
try:  # installed (editable) package first
    import xpersson.engine  # noqa: F401
except ImportError:  # pragma: no cover - source-tree fallback
    sys.path.insert(0, str(_SRC))

PEERS = Path(__file__).parents[2] / ".." / "shared" / "peers"


@pytest.fixture
def compiled_on():
    """numba present and the compiled path on for the test, whatever ``XPERSSON_COMPILED``
    says (these tests compare the compiled path with the numpy one)."""
    pytest.importorskip("numba")
    import xpersson

    with xpersson.set_options(compiled=True):
        yield


@pytest.fixture(scope="session")
def scene_mod():
    """The shared peer module ``scene`` (skips cleanly when ../shared/peers is absent)."""
    if not (PEERS / "scene.py").exists():
        pytest.skip("shared peers folder (../shared/peers) not present")
    sys.path.insert(0, str(PEERS.resolve()))
    import scene

    return scene
