"""The bundled example: tread-like compound on an asphalt-like surface, and its plot script."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

import xpersson

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def test_example_scene():
    ds = xpersson.solve(str(EXAMPLES / "tread_on_asphalt.toml"))
    assert ds.attrs["status"] == "success"
    np.testing.assert_array_equal(ds["mu"].values, (ds["mu_visc"] + ds["mu_contact"]).values)
    # universal WLF re-referenced to T_ref = 293.15 K: a_T = 1 at the scene's temperature
    assert float(ds["shift_factor"]) == pytest.approx(1.0, abs=1e-15)
    assert 0.3 < float(ds["mu_visc"].max()) < 1.0  # rubber friction magnitude at 1 cm/s


def test_plot_script(tmp_path):
    pytest.importorskip("matplotlib")
    spec = importlib.util.spec_from_file_location("plot_friction", EXAMPLES / "plot_friction.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    r = mod.friction_curves(velocities=[1e-6, 1e-2])
    # below the friction peak a colder rubber (larger a_T) has the larger friction
    assert np.all(np.diff(r["mu"][:, :, -1], axis=0) < 0)
    out = mod.plot_friction(out=tmp_path / "f.png", velocities=[1e-4, 1e-2])
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
