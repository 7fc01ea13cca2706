"""Tables read from files (Prony modes, master curve, shift table) go into the archive inline:
no file path in the written netCDF, and the archive's scene rebuilds the solve bit for bit
without the files."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr
from visco_testlib import scene

import xpersson
from xpersson_viscoelastic import ViscoelasticCoefficient, sls

FRICTION = {"friction": {}}


def _tables(folder):
    model = sls(3e6, 3e9, 1e-3)
    f = np.geomspace(1e-4, 1e10, 60) / (2 * np.pi * 1e-3)
    E = model.modulus(2 * np.pi * f)
    rows = "\n".join(
        f"{float(a)!r}, {float(b)!r}, {float(c)!r}"
        for a, b, c in zip(f, E.real / 1e6, E.imag / 1e6, strict=True)
    )
    (folder / "curve.txt").write_text("f [Hz], E_storage [MPa], E_loss [MPa]\n" + rows + "\n")
    (folder / "modes.txt").write_text("tau [ms], delta_E [GPa]\n1, 2.997\n2, 0\n")
    (folder / "shift.txt").write_text("T [K], a_T [1]\n250, 100\n293.15, 1\n350, 0.01\n")


@pytest.mark.parametrize(
    ("coefficient", "files", "inline"),
    [
        ({"modulus": "prony", "prony_file": "modes.txt"}, ["prony_file"], ["delta_E"]),
        (
            {"modulus": "master_curve", "master_curve": "curve.txt", "shift": "table",
             "shift_table": "shift.txt", "temperature": "300 K"},
            ["master_curve", "shift_table"],
            ["master_omega", "master_E_storage", "master_E_loss", "shift_T", "shift_a_T"],
        ),
    ],
)  # fmt: skip
def test_table_files_are_archived_inline_and_rebuild_the_solve(
    tmp_path, coefficient, files, inline
):
    folder = tmp_path / "tables_here"
    folder.mkdir()
    _tables(folder)
    coef = {k: str(folder / v) if k in files else v for k, v in coefficient.items()}
    ds = xpersson.solve(scene({**coef, "velocity": "1 cm/s"}, analyses=FRICTION))
    out = xpersson.to_netcdf(ds, tmp_path / "out.nc")
    assert str(folder).encode() not in out.read_bytes()  # no machine-specific path in the file
    for name in ("curve.txt", "modes.txt", "shift.txt"):
        (folder / name).unlink()
    with xr.open_dataset(out) as stored:
        archived = json.loads(stored.attrs["xpersson_scene"])
    assert not set(files) & set(archived["coefficient"])
    assert set(inline) <= set(archived["coefficient"])
    again = xpersson.solve(archived)
    for name in ("area_fraction", "mu_visc"):
        np.testing.assert_array_equal(again[name].values, ds[name].values)


@pytest.mark.parametrize(
    ("params", "match"),
    [
        ({"modulus": "master_curve", "master_omega": ["1 1/s", "2 1/s"]}, r"given together"),
        (
            {"modulus": "master_curve", "master_omega": ["1 1/s", "2 1/s"], "master_curve": "c",
             "master_E_storage": ["3 MPa", "3 MPa"], "master_E_loss": ["0 Pa", "0 Pa"]},
            r"master_curve: give either master_curve or master_omega",
        ),
        (
            {"modulus": "master_curve", "master_omega": ["2 1/s", "1 1/s"],
             "master_E_storage": ["3 MPa", "3 MPa"], "master_E_loss": ["0 Pa", "0 Pa"]},
            r"strictly increasing",
        ),
        ({"shift": "table", "shift_T": ["300 K", "290 K"], "shift_a_T": [1.0, 2.0]}, r"shift_T"),
        ({"shift": "table", "shift_T": ["290 K", "300 K"], "shift_a_T": [1.0, 0.0]}, r"shift_a_T"),
        ({"shift": "table"}, r"shift_table: required .*shift_T, shift_a_T"),
    ],
)  # fmt: skip
def test_bad_inline_tables_named(params, match):
    from xpersson.scene import convert_params

    raw = {**params, "velocity": "1 cm/s"}
    with pytest.raises(ValueError, match=match):  # (a column's bounds: on conversion)
        ViscoelasticCoefficient(
            **convert_params(ViscoelasticCoefficient.parameters, raw, "coefficient")
        )
