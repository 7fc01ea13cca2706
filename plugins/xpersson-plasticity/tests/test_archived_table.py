"""A hardness table read from a file goes into the archive inline: no file path in the written
netCDF, and the archive's scene rebuilds the solve bit for bit without the file."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr

import xpersson
from xpersson import testing
from xpersson_plasticity import ScaleDependentPlasticBoundary as SD


def _scene(boundary: dict) -> dict:
    spectrum = {"model": "self_affine", "H": 0.8, "q_L": "1e4 1/m", "q_1": "1e8 1/m",
                "h_rms": "1 um"}  # fmt: skip
    sc = testing.scene(spectrum, testing.material("10 MPa"), p0=["0.1 MPa", "0.5 MPa"])
    sc["boundary"] = {"model": "plastic_scale_dependent", **boundary}
    return sc


def _same(a: xr.Dataset, b: xr.Dataset) -> bool:
    return all(
        np.array_equal(a[v].values, b[v].values, equal_nan=a[v].dtype.kind == "f")
        for v in a.data_vars
    )


def test_a_table_file_is_archived_inline_and_rebuilds_the_solve(tmp_path):
    folder = tmp_path / "tables_here"
    folder.mkdir()
    table = folder / "hardness.txt"
    table.write_text("# zeta  Y [GPa]\n1 0.003\n10 0.005\n1000 0.009\n1e5 0.02\n")
    ds = xpersson.solve(_scene({"table": str(table), "table_unit": "GPa"}))
    out = xpersson.to_netcdf(ds, tmp_path / "out.nc")
    assert str(folder).encode() not in out.read_bytes()  # no machine-specific path in the file
    table.unlink()
    with xr.open_dataset(out) as stored:
        boundary = json.loads(stored.attrs["xpersson_scene"])["boundary"]
        again = xpersson.solve(json.loads(stored.attrs["xpersson_scene"]))
    assert "table" not in boundary and boundary["table_zeta"] == [1.0, 10.0, 1000.0, 1e5]
    assert boundary["table_Y"][0] == "3000000.0 Pa"
    assert _same(ds, again)


@pytest.mark.parametrize(
    ("params", "match"),
    [
        ({"table_zeta": [1.0, 10.0]}, r"table_zeta and table_Y \[Pa\] must be given together"),
        ({"table_zeta": [1.0, 10.0], "table_Y": [3e6, 2e6]}, r"table_zeta/table_Y.*decreases"),
        ({"table_zeta": [1.0, 1.0], "table_Y": [3e6, 4e6]}, r"strictly increasing"),
        ({"table_zeta": [1.0], "table_Y": [3e6]}, r"at least two rows"),
        ({"table_zeta": [1.0, 2.0], "table_Y": [3e6, 4e6], "table": "x.txt"}, r"either table"),
    ],
)
def test_bad_inline_tables_named(params, match):
    with pytest.raises(ValueError, match=match):
        SD(**params)


def test_an_inline_table_is_the_file_table():
    z, Y = np.geomspace(1, 1e4, 9), 2e9 * np.geomspace(1, 1e4, 9) ** 0.2
    law = SD(table_zeta=z, table_Y=Y).law
    zz = np.geomspace(1, 1e4, 50)
    np.testing.assert_allclose(law.Y(zz), 2e9 * zz**0.2, rtol=1e-12)  # PCHIP: exact log-log
