"""A (v, T) friction sweep of a tabulated master curve: stacked, and equal to the
point-by-point path (each point's q panels split where q v a_T crosses a table frequency)."""

from __future__ import annotations

import numpy as np
import pytest
from visco_testlib import scene

import xpersson
from xpersson.pipeline import stacked
from xpersson.sweep import plain_paths

FRICTION = {"friction": {"tau_f": "0.5 MPa", "shear_law": "velocity"}}
WLF = {"shift": "wlf", "T_ref": "293.15 K", "C1": 7.84, "C2": "114.75 K"}


@pytest.mark.fast_paths
def test_master_curve_sweep_stacked_equals_point_by_point(tmp_path, monkeypatch):
    w = np.geomspace(1e-2, 1e10, 60)
    E = 3e6 + 3e9 * (1j * w * 1e-4) / (1 + 1j * w * 1e-4)  # a sampled SLS
    path = tmp_path / "curve.txt"
    rows = [f"{a:.17g}, {b:.17g}, {c:.17g}" for a, b, c in zip(w, E.real, E.imag, strict=True)]
    path.write_text("omega [rad/s], E_storage [Pa], E_loss [Pa]\n" + "\n".join(rows) + "\n")
    coef = {
        "velocity": ["1e-4 m/s", "1 cm/s", "1 m/s"],
        "temperature": ["273.15 K", "313.15 K"],
        "modulus": "master_curve",
        "master_curve": str(path),
        **WLF,
    }
    calls = []
    run = stacked.run_stacked
    monkeypatch.setattr(stacked, "run_stacked", lambda pts: calls.append(len(pts)) or run(pts))
    batch = xpersson.solve(scene(coef, analyses=FRICTION))
    assert calls == [6]
    with plain_paths():
        point = xpersson.solve(scene(coef, analyses=FRICTION))
    for name, var in point.variables.items():
        if var.dtype.kind == "f":
            np.testing.assert_allclose(batch[name].values, var.values, rtol=1e-12, atol=1e-300)
