"""netCDF archive: CF attributes, provenance, identical re-opening, atomic writes, quantify."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr

import xpersson
from xpersson.io import open_dataset, to_netcdf


@pytest.fixture
def solved(scene):
    scene["output"] = {"pressure_pdf": True, "p_points": 64, "zeta_per_decade": 4}
    scene["analyses"] = {"contact_area": {}}
    return xpersson.solve(scene)


def test_every_variable_has_cf_units_and_long_name(solved):
    for name, var in solved.variables.items():
        assert "units" in var.attrs, name
        assert "long_name" in var.attrs, name
    assert solved.attrs["Conventions"] == "CF-1.11, ACDD-1.3"
    assert solved.P.dims == ("p0", "zeta", "p")
    assert solved.P.attrs["units"] == "Pa^-1"
    assert solved.psd_C.attrs["units"] == "m^4"


def test_provenance_records_scene_plugins_environment(solved):
    scene = json.loads(solved.attrs["xpersson_scene"])
    assert scene["spectrum"]["model"] == "self_affine"
    assert scene["material"]["E"] == "10000000.0 Pa"
    plugins = json.loads(solved.attrs["xpersson_plugins"])
    used = {(p["group"], p["name"]) for p in plugins}
    assert used == {
        ("spectra", "self_affine"),
        ("coefficients", "elastic"),
        ("boundaries", "elastic"),
        ("analyses", "contact_area"),
    }
    assert all(p["distribution"] == "xpersson" and p["version"] for p in plugins)
    env = json.loads(solved.attrs["xpersson_environment"])
    assert {"python", "numpy", "xarray"} <= set(env)


def test_archive_reopens_identical(solved, tmp_path):
    path = to_netcdf(solved, tmp_path / "out.nc")
    again = open_dataset(path)
    xr.testing.assert_identical(again, solved)


def test_scalar_load_archive_reopens_identical(scene, tmp_path):
    scene["load"]["p0"] = "0.1 MPa"
    ds = xpersson.solve(scene)
    assert ds.p0.ndim == 0 and "p0" not in ds.dims
    xr.testing.assert_identical(open_dataset(to_netcdf(ds, tmp_path / "s.nc")), ds)


def test_refuses_overwrite_and_leaves_no_partial_file(solved, tmp_path, monkeypatch):
    path = tmp_path / "out.nc"
    to_netcdf(solved, path)
    with pytest.raises(FileExistsError):
        to_netcdf(solved, path)
    to_netcdf(solved, path, overwrite=True)

    def fail(*args, **kwargs):
        raise RuntimeError("disk full")

    monkeypatch.setattr(xr.Dataset, "to_netcdf", fail)
    with pytest.raises(RuntimeError, match="disk full"):
        to_netcdf(solved, tmp_path / "new.nc")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.nc"]


def test_quantify_gives_pint_arrays(solved):
    pytest.importorskip("pint_xarray")
    from xpersson.units import quantify

    q = quantify(solved)
    assert str(q.P.data.units) in ("1 / pascal", "1/Pa", "1 / Pa")
    e = q.E_star.data.to("MPa")
    assert float(e.magnitude) == pytest.approx(1e7 / 0.75 / 1e6)
    assert q.psd_C.data.units == q.psd_C.data._REGISTRY.Unit("m**4")
    assert float((q.diffusion_time.data.to("MPa**2")).magnitude[-1]) == pytest.approx(
        float(solved.diffusion_time[-1]) / 1e12
    )


def test_pressure_pdf_only_when_asked(scene):
    ds = xpersson.solve(scene)
    assert "P" not in ds and "p" not in ds.dims
    assert np.all(ds.area_fraction.isel(zeta=0) == 1)
