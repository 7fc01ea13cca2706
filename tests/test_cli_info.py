"""``xpersson info`` on a sweep says its swept dimensions and which point it prints
(``--point DIM=INDEX`` picks another); ``validate`` prints a readable summary (issue 38)."""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import pytest

import xpersson
from xpersson.cli import main

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def sweep_nc(tmp_path_factory):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = xpersson.solve(
            ROOT / "examples" / "sweep.toml",
            load__p0=["0.1 MPa", "1 MPa"],
            output__zeta_per_decade=2,
        )
    return xpersson.to_netcdf(ds, tmp_path_factory.mktemp("i") / "s.nc"), ds


def test_info_on_a_sweep_names_its_dimensions_and_the_point_it_prints(sweep_nc, capsys):
    path, ds = sweep_nc
    assert main(["info", str(path)]) == 0
    out = capsys.readouterr().out
    assert "  sweep: H (3: 0.6 .. 0.8 [1]), E (2: 5e+06 .. 1e+07 [Pa])" in out
    assert "sweep point shown below: H = 0.6 (index 0), E = 5e+06 (index 0)" in out
    a = ds["area_fraction"].isel(H=0, E=0, zeta=-1).values
    assert " ".join(f"{v:.6g}" for v in a) in out
    assert main(["info", str(path), "--point", "H=2", "--point", "E=1"]) == 0
    out = capsys.readouterr().out
    assert "H = 0.8 (index 2), E = 1e+07 (index 1)" in out
    a = ds["area_fraction"].isel(H=2, E=1, zeta=-1).values
    assert " ".join(f"{v:.6g}" for v in a) in out


@pytest.mark.parametrize("pick", ["H=3", "T=0", "H=x"])
def test_a_bad_point_is_one_line(sweep_nc, capsys, pick):
    assert main(["info", str(sweep_nc[0]), "--point", pick]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--point" in err


def test_validate_prints_a_readable_summary_not_a_dict(capsys):
    assert main(["validate", str(ROOT / "examples" / "elastic.toml")]) == 0
    err = capsys.readouterr().err.splitlines()
    assert err[0].endswith("elastic.toml is valid")
    assert err[1:] == [
        "  loads: 3; magnification: 41 points from 1 to 100000",
        "  plugins: spectrum self_affine, coefficient elastic, boundary elastic",
        "  analyses: contact_area",
    ]
    assert main(["validate", str(ROOT / "examples" / "sweep.toml"), "--json"]) == 0
    captured = capsys.readouterr()
    assert "a sweep of 6 points (H = spectrum.H (3 values), E = material.E (2 values))" in (
        captured.err
    )
    assert json.loads(captured.out)["material"]["E"] == ["5000000.0 Pa", "10000000.0 Pa"]
