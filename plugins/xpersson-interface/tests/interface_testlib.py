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


def scene(p0, *, psd="persson", closure="persson01", boundary=None, analyses=None, **out):
    """A scene dict on the physics.md §1.4 spectrum ("persson") or the Zhou GFMD one ("zhou")."""
    if psd == "persson":
        spectrum = {"model": "self_affine", "H": 0.8, "q_L": "1e3 1/m", "q_r": "1e4 1/m",
                    "q_1": "1e8 1/m", "h_rms": "1 um"}  # fmt: skip
        material = {"E": "10 MPa", "nu": 0.5}
    else:
        spectrum = {"model": "self_affine", "H": 0.8, "q_L": "1e4 1/m", "q_r": "1e4 1/m",
                    "q_1": "1e6 1/m", "h_rms": "6 um"}  # fmt: skip
        material = {"E": "0.75 Pa", "nu": 0.5}  # E* = 1 Pa
    sc = {
        "spectrum": spectrum,
        "material": material,
        "load": {"p0": [f"{float(p)!r} Pa" for p in np.atleast_1d(p0)]},
        "coefficient": {"model": "elastic", "closure": closure},
        "boundary": boundary or {"model": "elastic"},
        "analyses": analyses or {},
    }
    if out:
        sc["output"] = out
    return sc
