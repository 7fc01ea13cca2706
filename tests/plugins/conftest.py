"""Make the fake plugin modules in ``fakes/`` importable (pytest runs with importlib mode).

The helpers live in uniquely named modules (``xpersson_plugtest_helpers``, ``xpersson_fake_*``)
in a folder without a ``conftest.py``, so putting it on ``sys.path`` shadows no other
``conftest`` module.
"""

from __future__ import annotations

import sys
from pathlib import Path

FAKES = str(Path(__file__).resolve().parent / "fakes")
if FAKES not in sys.path:
    sys.path.append(FAKES)
