"""``xpersson.analyse`` of a finite body's archive: the analysis on the flat, the body computed
again from it, and the analysis's body quantities integrated over the body's nominal pressure
give, bit for bit, what the solve gave; the body's own outputs are unchanged."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import xpersson
from xpersson.errors import ArchiveError

SCENE = {
    "geometry": {"model": "cylinder", "radius": "1.5 mm", "length": "62.83 mm"},
    "load": {"force": {"start": "1 N", "stop": "15 N", "num": 3, "spacing": "log"}},
    "spectrum": {
        "model": "self_affine",
        "H": 0.8,
        "q_L": "2e5 1/m",
        "q_r": "5e5 1/m",
        "q_1": "1e8 1/m",
        "h_rms": "1 um",
    },
    "material": {"E": "5 MPa", "nu": 0.5},
}
LEAKAGE = {"fluid": "liquid", "viscosity": "1e-3 Pa*s", "pressure_drop": "1e5 Pa"}


@pytest.mark.parametrize("force", [None, "4 N"])
def test_body_archive_equals_the_solve(tmp_path, force):
    """An O-ring (a cylinder): leakage added to an archive that already has elastic_energy;
    every force, and one force (scalar ``force``)."""
    scene = {k: dict(v) for k, v in SCENE.items()}
    if force is not None:
        scene["load"] = {"force": force}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = xpersson.solve(scene | {"analyses": {"leakage": LEAKAGE, "elastic_energy": {}}})
        xpersson.to_netcdf(
            xpersson.solve(scene | {"analyses": {"elastic_energy": {}}}), tmp_path / "b.nc"
        )
    with xpersson.open_dataset(tmp_path / "b.nc") as archive:
        bare = archive.load()
    out = xpersson.analyse(bare, "leakage", **LEAKAGE)
    added = [v for v in out.variables if v not in bare.variables]
    assert "body_leak_rate" in added
    assert not [v for v in ref.variables if v not in out.variables]
    for v in added:
        assert out[v].dims == ref[v].dims, v
        np.testing.assert_array_equal(out[v].values, ref[v].values, err_msg=v)
    for v in ("real_contact_area", "approach", "body_elastic_energy", "nominal_pressure"):
        if v in bare:
            np.testing.assert_array_equal(out[v].values, bare[v].values, err_msg=v)


def test_force_subset_is_refused():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = xpersson.solve(SCENE)
    with pytest.raises(ArchiveError, match="subset along force"):
        xpersson.analyse(ds.isel(force=[0, 2]), "leakage", **LEAKAGE)
