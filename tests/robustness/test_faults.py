"""Issue 37: the reader, the disk and the forger (the fast subset of ``benchmarks/faults.py``).

One section per class of failure; every test failed on the code before the issue.
"""

from __future__ import annotations

import sys
from pathlib import Path

import pytest
import xarray as xr

import xpersson
from xpersson.errors import ArchiveError
from xpersson.sweep import parts

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "sweep"))
from xpersson_sweep_testlib import scene  # noqa: E402


def _scene(e3: str = "20 MPa") -> dict:
    return scene(material={"E": ["5 MPa", "10 MPa", e3]}, output={"zeta_per_decade": 2})


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    folder = tmp_path_factory.mktemp("snap") / "s"
    xpersson.solve(_scene(), output=folder, chunk=1)
    return folder, xpersson.open_dataset(folder).load()


# -- 1. snapshot reads ------------------------------------------------------------------------
@pytest.mark.parametrize("kept", [True, False])
def test_a_folder_overwritten_after_opening_is_never_read_as_the_other_study(
    study, tmp_path, monkeypatch, kept
):
    import shutil

    src, ref = study
    folder = tmp_path / "s"
    shutil.copytree(src, folder)
    if not kept:  # every part re-read (and re-verified) when loaded
        monkeypatch.setattr(parts, "SNAPSHOT_BYTES", -1)
    with xr.set_options(file_cache_maxsize=1):  # as with more parts than xarray keeps open
        ds = xpersson.open_dataset(folder)
        xpersson.solve(_scene("21 MPa"), output=folder, chunk=1, overwrite=True)
        if kept:
            assert ds.load().identical(ref)  # what was opened, not what is there now
        else:
            with pytest.raises(ArchiveError, match=r"part-0000\d\.nc: part changed after"):
                ds.load()


# -- 2. every OS error is a message -----------------------------------------------------------
_FSIZE = """
import resource, sys
from xpersson.cli import main
resource.setrlimit(resource.RLIMIT_FSIZE, (4096, 4096))
sys.exit(main(sys.argv[1:]))
"""


@pytest.mark.parametrize("sweep", [False, True])
def test_a_file_size_limit_is_one_line_exit_2_and_nothing_half_written(tmp_path, sweep):
    import subprocess

    (tmp_path / "s.toml").write_text(
        '[spectrum]\nmodel = "self_affine"\nH = 0.8\nq_L = "1e3 1/m"\nq_r = "1e4 1/m"\n'
        'q_1 = "1e8 1/m"\nh_rms = "1 um"\n[material]\nE = '
        + ('["5 MPa", "7 MPa"]' if sweep else '"5 MPa"')
        + '\nnu = 0.5\n[load]\np0 = "1e5 Pa"\n'
    )
    out = tmp_path / ("out/" if sweep else "out.nc")
    proc = subprocess.run(
        [sys.executable, "-c", _FSIZE, "run", str(tmp_path / "s.toml"), "-o", str(out)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    lines = proc.stderr.strip().splitlines()
    assert proc.returncode == 2, proc.stderr
    assert len(lines) == 1 and "File too large" in lines[0] and "Traceback" not in proc.stderr
    assert "out" in lines[0]
    left = [p.name for p in tmp_path.rglob("*") if p.suffix in (".nc", ".part")]
    assert left == []  # no archive, no part, no temporary


@pytest.mark.parametrize("code", ["ENOSPC", "EDQUOT", "EROFS", "EACCES"])
def test_disk_errors_of_to_netcdf_name_the_file_and_the_cause(study, tmp_path, monkeypatch, code):
    import errno
    import os

    from xpersson import archive
    from xpersson.cli import main

    _, ref = study
    num = getattr(errno, code)

    def fail(*args):
        raise OSError(num, os.strerror(num))

    # the netCDF library reports a full disk as "HDF error": the probe finds the cause
    monkeypatch.setattr(xr.Dataset, "to_netcdf", lambda *a, **k: _hdf())
    monkeypatch.setattr(archive.os, "write", fail)
    target = tmp_path / "x.nc"
    with pytest.raises(OSError, match=f"cannot write {target}: {os.strerror(num)}"):
        xpersson.to_netcdf(ref, target)
    assert list(tmp_path.iterdir()) == []
    monkeypatch.undo()
    monkeypatch.setattr(archive.os, "fsync", fail)  # a late failure: at the flush
    with pytest.raises(OSError, match=f"cannot write {target}: {os.strerror(num)}"):
        xpersson.to_netcdf(ref, target)
    assert list(tmp_path.iterdir()) == []
    monkeypatch.undo()
    # the CLI: one line, exit 2 (a read-only folder as root cannot be made: the cause injected)
    ro = tmp_path / "ro"
    ro.mkdir()
    monkeypatch.setattr(archive, "_create_temporary", _refuse(num))
    scene_file = tmp_path / "s.toml"
    scene_file.write_text(
        '[spectrum]\nmodel = "self_affine"\nH = 0.8\nq_L = "1e3 1/m"\nq_r = "1e4 1/m"\n'
        'q_1 = "1e8 1/m"\nh_rms = "1 um"\n[material]\nE = "5 MPa"\nnu = 0.5\n[load]\np0 = 1e5\n'
    )
    assert main(["run", str(scene_file), "-o", str(ro / "a.nc")]) == 2
    assert list(ro.iterdir()) == []


def _hdf():
    raise OSError(-101, "NetCDF: HDF error")


def _refuse(num: int):
    import os

    def create(target):
        raise OSError(num, os.strerror(num), str(target))

    return create


# -- 3. integrity that fails closed -----------------------------------------------------------
def _archive(study, tmp_path) -> Path:
    _, ref = study
    path = tmp_path / "a.nc"
    xpersson.to_netcdf(ref.isel(E=0), path)
    return path


def test_a_removed_digest_with_changed_values_is_an_error(study, tmp_path):
    netCDF4 = pytest.importorskip("netCDF4")
    path = _archive(study, tmp_path)
    with netCDF4.Dataset(path, "a") as nc:
        var = nc["area_fraction"]
        var.delncattr("xpersson_sha256")
        var[...] = var[...] * 0.5
    with pytest.raises(ArchiveError, match="'area_fraction' has no digest"):
        xpersson.open_dataset(path)


def test_an_archive_without_any_digest_opens_unverified_never_success(study, tmp_path):
    netCDF4 = pytest.importorskip("netCDF4")
    path = _archive(study, tmp_path)
    with netCDF4.Dataset(path, "a") as nc:
        for name in ("xpersson_archive_format", "xpersson_attrs_sha256"):
            nc.delncattr(name)
        for var in nc.variables.values():
            var.delncattr("xpersson_sha256")
    ds = xpersson.open_dataset(path)
    assert ds.attrs["status"] == "unverified"
    assert ds.attrs["status_message"].startswith("unverified: format version 1")


def test_an_index_that_calls_a_varying_variable_constant_is_refused(study, tmp_path):
    import json
    import shutil

    from xpersson.sweep import INDEX
    from xpersson.sweep.parts import seal_index

    src, ref = study
    assert "E" in ref["area_fraction"].dims  # varies with E
    folder = tmp_path / "s"
    shutil.copytree(src, folder)
    index = json.loads((folder / INDEX).read_text())
    index["constant"]["area_fraction"] = ["E"]  # a forger recomputing the index's sha256
    (folder / INDEX).write_text(json.dumps(seal_index(index)))
    with pytest.raises(ArchiveError, match="'area_fraction' varies along a sweep dimension"):
        xpersson.open_dataset(folder).load()


# -- 4. plugin outputs on the solved coordinates ----------------------------------------------
def _shifting(shift: float):
    from xpersson.plugins import Analysis, VarSpec

    def compute(self, ctx, ds):
        da = ds["area_fraction"].transpose("p0", "zeta").copy()
        return {"extra": da.assign_coords(zeta=da["zeta"].values * shift)}

    return type(
        "Shifting",
        (Analysis,),
        {
            "summary": "returns its output on a shifted zeta",
            "requires": ("area_fraction",),
            "provides": ("extra",),
            "outputs": {"extra": VarSpec(("p0", "zeta"), "1", "a copy")},
            "compute": compute,
        },
    )


@pytest.mark.parametrize("shift", [1.0, 1.0 + 1e-12, 1.5])
def test_an_output_on_shifted_coordinates_is_a_plugin_failure_naming_it(shift):
    from xpersson.checks import PluginFailure
    from xpersson.testing import registry_with

    sc = scene(analyses={"shifting": {}})
    sc.pop("sweep", None)
    sc["material"]["E"] = "5 MPa"
    with registry_with(analyses={"shifting": _shifting(shift)}):
        if shift == 1.0:
            ds = xpersson.solve(sc)
            assert (ds["extra"] == ds["area_fraction"].transpose(*ds["extra"].dims)).all()
            return
        with pytest.raises(PluginFailure, match=r"shifting.*'extra'.*coordinate 'zeta' differs"):
            xpersson.solve(sc)


# -- 6. inputs and environment under one budget -----------------------------------------------
@pytest.mark.parametrize(
    "text",
    [
        "1 " + " * ".join(["Tm**60"] * 3) + " / " + " / ".join(["m**60"] * 3),
        "1 (Ym**60*Ym**60*Ym**60)/(m**60*m**60*m**60)",
    ],
)
def test_products_of_large_powers_are_one_unit_error(text):
    from xpersson.units import UnitError, to_si

    with pytest.raises(UnitError, match="load.p0"):
        to_si(text, "1", "load.p0")


@pytest.mark.parametrize("value", ["1e999", "1e400 GB", "1.2.3", "nan", "-5"])
def test_an_overflowing_memory_budget_is_one_line_naming_the_variable(monkeypatch, value):
    from xpersson import memory

    monkeypatch.setenv("XPERSSON_MEMORY_BUDGET", value)
    with pytest.raises(ValueError, match="XPERSSON_MEMORY_BUDGET"):
        memory.budget()
    with pytest.raises(ValueError, match="memory budget"):
        memory.set_budget(float("inf"))


# -- 7. text that netCDF cannot give back -----------------------------------------------------
@pytest.mark.parametrize("bad", ["a\x00b", "tab\x01", "\ud800"])
def test_a_text_attribute_netcdf_cannot_store_is_refused_naming_it(study, tmp_path, bad):
    _, ref = study
    ds = ref.isel(E=0).copy(deep=True)
    ds.attrs["title"] = bad
    with pytest.raises(ValueError, match="global attribute 'title'"):
        xpersson.to_netcdf(ds, tmp_path / "a.nc")
    ds = ref.isel(E=0).copy(deep=True)
    ds["area_fraction"].attrs["comment_by_someone"] = bad
    with pytest.raises(ValueError, match="variable 'area_fraction', 'comment_by_someone'"):
        xpersson.to_netcdf(ds, tmp_path / "a.nc")
    assert list(tmp_path.iterdir()) == []


def test_the_cli_set_refuses_a_control_character_naming_the_key(tmp_path, capsys):
    from xpersson.cli import main

    f = tmp_path / "s.toml"
    f.write_text(
        '[spectrum]\nmodel = "self_affine"\nH = 0.8\nq_L = "1e3 1/m"\nq_r = "1e4 1/m"\n'
        'q_1 = "1e8 1/m"\nh_rms = "1 um"\n[material]\nE = "5 MPa"\nnu = 0.5\n[load]\np0 = 1e5\n'
    )
    assert main(["run", str(f), "-o", str(tmp_path / "a.nc"), "--set", "output.title=x\x00y"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--set output.title" in err[0] and "U+0000" in err[0]
    assert not (tmp_path / "a.nc").exists()


def test_two_index_entries_naming_one_part_are_refused_naming_both(study, tmp_path):
    import json
    import shutil

    from xpersson.sweep import INDEX
    from xpersson.sweep.parts import seal_index

    src, _ = study
    folder = tmp_path / "s"
    shutil.copytree(src, folder)
    index = json.loads((folder / INDEX).read_text())
    index["parts"][2]["name"] = index["parts"][0]["name"]
    (folder / INDEX).write_text(json.dumps(seal_index(index)))
    with pytest.raises(ArchiveError, match=r"parts\[0\] .* and parts\[2\] .* both name part-00000"):
        xpersson.open_dataset(folder)


# -- 5. time limits everywhere, with a default ------------------------------------------------
def test_a_sleeping_plugin_call_in_a_thread_is_interrupted():
    import threading
    import time as _time

    from xpersson.plugins import PluginTimeout, limited

    out = {}

    def work():
        t0 = _time.monotonic()
        try:
            with limited(0.2):
                _time.sleep(30)
        except PluginTimeout:
            out["after"] = _time.monotonic() - t0

    t = threading.Thread(target=work)
    t.start()
    t.join(10)
    assert not t.is_alive() and 0.2 <= out["after"] < 5


def test_a_default_limit_applies_to_spectrum_build_and_can_be_turned_off(monkeypatch):
    from xpersson.options import get_options, set_options
    from xpersson.plugins import current_limit

    assert current_limit() == 600.0 and get_options()["plugin_time_limit"] == 600.0
    with set_options(plugin_time_limit=False):
        assert current_limit() is None
    with set_options(plugin_time_limit=0.3):
        assert current_limit() == 0.3
        from xpersson.builtin import spectra  # noqa: F401 - any spectrum plugin

        calls = {}

        from xpersson.scene import _resolve

        def slow_build(spectrum, who):
            import time as _time

            with _resolve.calling(who, "build()"):
                calls["in"] = True
                _time.sleep(30)

        monkeypatch.setattr(_resolve, "_build_spectrum", slow_build)
        sc = scene(material={"E": "5 MPa"})
        sc.pop("sweep", None)
        with pytest.raises(TimeoutError, match=r"build\(\) exceeded the time limit of 0.3 s"):
            xpersson.solve(sc)
        assert calls["in"]
    monkeypatch.setenv("XPERSSON_PLUGIN_TIME_LIMIT", "1e999")
    with (
        set_options(plugin_time_limit=None),
        pytest.raises(ValueError, match="XPERSSON_PLUGIN_TIME_LIMIT"),
    ):
        current_limit()
    monkeypatch.delenv("XPERSSON_PLUGIN_TIME_LIMIT")
    set_options(plugin_time_limit=None)


def test_reproduce_reads_named_files_only_from_regular_files(tmp_path, capsys):
    import json
    import os

    from xpersson.cli import main

    sc = scene(material={"E": "5 MPa"})
    sc.pop("sweep", None)
    ds = xpersson.solve(sc)
    data = json.loads(ds.attrs["xpersson_scene"])
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    data["spectrum"] = {"model": "tabulated", "file": str(fifo)}
    ds.attrs["xpersson_scene"] = json.dumps(data)
    xpersson.to_netcdf(ds, tmp_path / "a.nc")
    args = ["reproduce", str(tmp_path / "a.nc"), "-o", str(tmp_path / "b.nc"), "--read-files"]
    assert main(args) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "spectrum.file names something that is not a regular file" in err[0]


def test_a_plugin_import_that_never_returns_is_interrupted(tmp_path, monkeypatch):
    from xpersson.plugins import PluginTimeout
    from xpersson.plugins._discovery import import_target

    (tmp_path / "xpersson_never_imports.py").write_text("import time\ntime.sleep(3600)\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    with xpersson.set_options(plugin_time_limit=0.3), pytest.raises(PluginTimeout):
        import_target("xpersson_never_imports:Plugin")
    assert "xpersson_never_imports" not in sys.modules


def test_a_failed_index_write_names_the_index_and_leaves_no_temporary(tmp_path, monkeypatch):
    import errno
    import os

    from xpersson.archive import WriteError
    from xpersson.sweep.parts import write_index

    def fsync(fd):
        raise OSError(errno.EROFS, os.strerror(errno.EROFS))

    monkeypatch.setattr(os, "fsync", fsync)
    with pytest.raises(WriteError, match=r"xpersson_index.json: Read-only file system"):
        write_index(tmp_path, {"state": "running"})
    monkeypatch.undo()
    assert list(tmp_path.iterdir()) == []
    ds = xr.Dataset({"a": ("x", [1.0])}, attrs={"%bad": "v"})
    with pytest.raises(ValueError, match="not a name netCDF accepts"):
        xpersson.to_netcdf(ds, tmp_path / "n.nc")
