"""Repository hygiene: no machine-specific path in any tracked file; typed package."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PATTERN = "(/wo" + "rk/|/tm" + "p/[a-z]|/ho" + "me/[a-z]|/ro" + "ot/)"  # split: no self-match


def test_no_machine_specific_path_in_tracked_files():
    if shutil.which("git") is None or not (ROOT / ".git").exists():
        pytest.skip("not a git checkout")
    res = subprocess.run(["git", "grep", "-nE", PATTERN], cwd=ROOT, capture_output=True, text=True)
    assert res.returncode == 1, f"machine-specific paths:\n{res.stdout}"


def test_package_ships_py_typed():
    import xpersson

    assert (Path(xpersson.__file__).parent / "py.typed").is_file()


def test_ci_runs_ruff_and_the_tests():
    text = (ROOT / ".ci" / "run").read_text()
    assert "ruff check ." in text and "pytest" in text
