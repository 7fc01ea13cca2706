"""Archives you can trust (issue 24): checksums on every variable, one-line errors for corrupt,
truncated or foreign files, and a ``reproduce`` that compares coordinates exactly and never
passes on an empty comparison or reads a file an archive names."""

from __future__ import annotations

import json
import random
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import xpersson
from xpersson.cli import main
from xpersson.errors import ArchiveError
from xpersson.io import compare

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "elastic.toml"


@pytest.fixture(scope="module")
def archive(tmp_path_factory):
    path = tmp_path_factory.mktemp("a") / "a.nc"
    assert main(["run", str(EXAMPLE), "-o", str(path), "--quiet"]) == 0
    return path


def _write_marked(path: Path) -> np.ndarray:
    """An archive whose variable ``x`` holds a byte pattern found once in the file."""
    x = np.arange(4096, dtype=float) * np.pi
    ds = xr.Dataset({"x": ("n", x, {"units": "m"})}, attrs={"title": "marked"})
    xpersson.to_netcdf(ds, path)
    return x


@pytest.mark.parametrize("offset", [0.1, 0.5, 0.9])
def test_a_flipped_byte_in_a_variable_is_an_error_naming_it(tmp_path, offset):
    path = tmp_path / "m.nc"
    x = _write_marked(path)
    data = bytearray(path.read_bytes())
    start = bytes(data).find(x.tobytes())
    assert start > 0
    k = start + int(offset * x.nbytes)
    data[k] ^= 0x10
    path.write_bytes(data)
    with pytest.raises(ArchiveError, match=r"m\.nc: variable 'x'"):
        xpersson.open_dataset(path)


def test_digests_catch_what_hdf5_checksums_cannot_see(tmp_path):
    """An attribute or a value changed through the library (HDF5's own checksums are then
    recomputed) fails the digest of the variable, or of the global attributes."""
    netCDF4 = pytest.importorskip("netCDF4")
    path = tmp_path / "u.nc"
    _write_marked(path)
    with netCDF4.Dataset(path, "a") as nc:
        nc["x"].units = "km"
    with pytest.raises(ArchiveError, match=r"variable 'x' fails its checksum"):
        xpersson.open_dataset(path)
    _write_marked(path := tmp_path / "v.nc")
    with netCDF4.Dataset(path, "a") as nc:
        nc["x"][7] = 0.0
    with pytest.raises(ArchiveError, match=r"variable 'x' fails its checksum"):
        xpersson.open_dataset(path)
    _write_marked(path := tmp_path / "g.nc")
    with netCDF4.Dataset(path, "a") as nc:
        nc.title = "changed"
    with pytest.raises(ArchiveError, match="global attributes fail their checksum"):
        xpersson.open_dataset(path)


def test_zeros_written_into_an_archive_never_pass_silently(archive, tmp_path):
    ref = xpersson.open_dataset(archive)
    data = archive.read_bytes()
    rng = random.Random(24)
    caught = 0
    for _ in range(30):
        bad = bytearray(data)
        k = rng.randrange(len(bad) - 4096)
        bad[k : k + 4096] = bytes(4096)
        path = tmp_path / "z.nc"
        path.write_bytes(bad)
        try:
            ds = xpersson.open_dataset(path)
        except ArchiveError as exc:
            assert str(exc).startswith(str(path)) and "\n" not in str(exc)
            caught += 1
        else:  # zeros over unused bytes: the contents must be untouched
            assert ds.identical(ref)
    assert caught >= 20


@pytest.mark.parametrize("command", ["info", "plot", "reproduce"])
@pytest.mark.parametrize("kind", ["truncated", "garbage", "foreign", "missing", "bad_attrs"])
def test_cli_answers_a_bad_file_with_one_line(archive, tmp_path, capsys, command, kind):
    path = tmp_path / f"{kind}.nc"
    if kind == "truncated":
        path.write_bytes(archive.read_bytes()[:5000])
    elif kind == "garbage":
        path.write_bytes(b"CDF\x01" + bytes(range(256)) * 4)
    elif kind == "foreign":
        xr.Dataset({"a": ("x", [1.0, 2.0])}).to_netcdf(path)
    elif kind == "bad_attrs":
        ds = xpersson.open_dataset(archive)
        ds.attrs["xpersson_plugins"] = "[not json"
        xpersson.to_netcdf(ds, path)
    args = {"info": [], "plot": ["-o", str(tmp_path / "f.png")]}.get(
        command, ["-o", str(tmp_path / "r.nc")]
    )
    assert main([command, str(path), *args]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"xpersson: error: {path}"), err


def test_compare_checks_coordinates_exactly_first():
    ds = xr.Dataset(
        {"v": ("x", np.array([1.0, 2.0, 3.0]))}, coords={"x": np.array([0.0, 1.0, 2.0])}
    )
    assert compare(ds, ds.copy(deep=True)) == (2, [])
    shifted = ds.assign_coords(x=ds.x + 1e-12)
    n, diffs = compare(ds, shifted)
    assert diffs == ["coordinate x: differs (compared exactly)"]
    changed = ds.copy(deep=True)
    changed["v"].values[1] *= 1 + 1e-6
    n, diffs = compare(ds, changed, rtol=1e-9)
    assert n == 2 and len(diffs) == 1 and "1 of 3 values" in diffs[0] and "x=1" in diffs[0]
    assert compare(ds, changed, rtol=1e-5)[1] == []
    n, diffs = compare(xr.Dataset(), xr.Dataset())
    assert n == 0 and diffs == ["nothing to compare: no coordinate or variable in common"]
    n, diffs = compare(ds, ds.rename({"v": "w"}))
    assert sorted(diffs) == ["variable v: only in the old", "variable w: only in the new"]


def test_reproduce_reports_a_changed_variable(archive, tmp_path, capsys):
    ds = xpersson.open_dataset(archive)
    ds["area_fraction"] = ds["area_fraction"] * (1 + 1e-6)
    changed = xpersson.to_netcdf(ds, tmp_path / "c.nc")
    assert main(["reproduce", str(changed), "-o", str(tmp_path / "r.nc")]) == 4
    err = capsys.readouterr().err
    assert "variable area_fraction:" in err and "DIFFERS" in err


def test_reproduce_reads_no_file_an_archive_names(archive, tmp_path, capsys):
    secret = tmp_path / "secret.txt"
    secret.write_text("1 2\nTOP-SECRET-CONTENT\n", encoding="utf-8")
    ds = xpersson.open_dataset(archive)
    scene = json.loads(ds.attrs["xpersson_scene"])
    scene["spectrum"] = {"model": "tabulated", "file": str(secret)}
    ds.attrs["xpersson_scene"] = json.dumps(scene)
    hostile = xpersson.to_netcdf(ds, tmp_path / "h.nc")
    assert main(["reproduce", str(hostile), "-o", str(tmp_path / "r.nc")]) == 2
    err = capsys.readouterr().err
    assert "spectrum.file" in err and "--read-files" in err
    assert "TOP-SECRET" not in err
    assert not (tmp_path / "r.nc").exists()
    args = ["reproduce", str(hostile), "-o", str(tmp_path / "r.nc"), "--read-files"]
    assert main(args) == 2  # read on request; the file's lines are still not printed
    err = capsys.readouterr().err
    assert "secret.txt" in err and "TOP-SECRET" not in err
