"""Test helpers of xpersson-interface (a uniquely named module, importable from any layout)."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

E_STAR = 10e6 / (1.0 - 0.5**2)  # §1.4: E = 10 MPa, nu = 0.5
H_RMS_ZHOU = 6e-6

#: <repo>/plugins/xpersson-interface/tests -> <repo>/../shared/refdata/xu2024-gfmd
REFDATA = (
    Path(
        os.environ.get(
            "XPERSSON_REFDATA",
            Path(__file__).resolve().parents[4] / "shared" / "refdata",
        )
    )
    / "xu2024-gfmd"
)


def read_csv(name: str) -> dict[str, np.ndarray]:
    """Read one reference CSV (``#`` comments, one header line); skip when absent."""
    path = REFDATA / name
    if not path.is_file():
        pytest.skip(f"reference data not found: {path} (set XPERSSON_REFDATA)")
    lines = [ln for ln in path.read_text().splitlines() if ln and not ln.startswith("#")]
    names = lines[0].split(",")
    data = np.array([[float(x) for x in ln.split(",")] for ln in lines[1:]])
    return {n: data[:, i] for i, n in enumerate(names)}
