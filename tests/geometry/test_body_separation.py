"""The body's interfacial spring u(p) is the mean_gap analysis's default (issue 39)."""

from __future__ import annotations

import numpy as np
import pytest

import xpersson

from .conftest import body_scene

pytest.importorskip("xpersson_interface")


@pytest.mark.parametrize(("closure", "form"), [("persson01", "yang_persson"), ("yp08", "closure")])
def test_separation_is_mean_gaps_default(closure: str, form: str) -> None:
    """Where ``A/A0 >= 1e-3`` (above it the continuation takes over) the body's ``u(p0)`` is
    the flat ``mean_gap`` with its default ``s_factor = "auto"``, to the last bit."""
    scene = body_scene(force="1 mN", h_rms="300 nm") | {
        "coefficient": {"model": "elastic", "closure": closure}
    }
    ds = xpersson.solve(scene)
    assert ds.attrs["geometry_separation_s_factor"] == form
    p0 = [f"{float(p)!r} Pa" for p in ds["p0"].values]
    flat = {k: v for k, v in scene.items() if k not in ("geometry", "load")}
    fl = xpersson.solve(flat | {"load": {"p0": p0}, "analyses": {"mean_gap": {}}})
    above = fl["area_fraction"].values[:, -1] >= 1e-3
    assert 5 < above.sum() < above.size
    np.testing.assert_array_equal(
        ds["separation_of_pressure"].values[above], fl["mean_gap"].values[above]
    )
