"""Sweeps on a real dask.distributed LocalCluster (two worker processes), failing points,
netCDF parts re-opened lazily, and the CLI."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from xpersson_sweep_testlib import scene

import xpersson
from xpersson.cli import main

distributed = pytest.importorskip("distributed")

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
VOLATILE = ("history", "date_created", "xpersson_solver")


def _same(a: xr.Dataset, b: xr.Dataset) -> None:
    """Bit-for-bit equal values, coordinates and attributes (except timestamps/timings)."""
    xr.testing.assert_identical(
        a.drop_attrs(deep=False).assign_attrs(
            {k: v for k, v in a.attrs.items() if k not in VOLATILE}
        ),
        b.drop_attrs(deep=False).assign_attrs(
            {k: v for k, v in b.attrs.items() if k not in VOLATILE}
        ),
    )


def test_2x3x50_sweep_on_two_worker_processes_equals_serial(client):
    serial = xpersson.solve(EXAMPLES / "sweep.toml")
    assert serial.area_fraction.shape == (3, 2, 50, 51)
    par = xpersson.solve(EXAMPLES / "sweep.toml", scheduler=client, chunk=1)
    assert len(client.scheduler_info()["workers"]) == 2
    assert "area_fraction_model_error_status" in par  # attached on the workers too
    _same(serial, par)


def test_failing_point_is_recorded_and_the_rest_completes(client):
    sc = scene(boundary={"model": "plastic", "sigma_Y": ["0.5 MPa", "5 MPa", "50 MPa"]})
    ds = xpersson.solve(sc, scheduler=client, chunk=1)
    assert ds.point_status.values.tolist() == [2, 0, 0]
    assert ds.attrs["status"] == "failed" and "1 of 3 sweep points" in ds.attrs["status_message"]
    msgs = json.loads(ds.attrs["xpersson_point_messages"])
    assert msgs[0]["point"] == {"sigma_Y": 5e5} and "sigma_Y" in msgs[0]["message"]
    assert np.isnan(ds.area_fraction.isel(sigma_Y=0)).all()
    one = xpersson.solve(scene(boundary={"model": "plastic", "sigma_Y": "5 MPa"}))
    np.testing.assert_array_equal(
        ds.area_fraction.sel(sigma_Y=5e6).values, one.area_fraction.values
    )


def test_parts_reopen_lazily_and_equal_the_in_memory_result(tmp_path, client):
    sc = scene(
        spectrum={"H": [0.6, 0.7, 0.8]},
        material={"E": ["5 MPa", "10 MPa"]},
        output={"pressure_pdf": True, "p_points": 32, "zeta_per_decade": 2},
    )
    mem = xpersson.solve(sc)
    out = xpersson.solve(sc, scheduler=client, output=tmp_path / "parts", chunk=2)
    assert len(list((tmp_path / "parts").glob("part-*.nc"))) == 3
    lazy = xpersson.open_dataset(tmp_path / "parts")
    assert lazy.P.chunks is not None  # dask-backed, not loaded
    _same(mem, lazy.load())
    _same(mem, out.load())


def test_cli_run_scheduler_parts_and_validate(tmp_path, client, capsys):
    target = tmp_path / "sweep"
    code = main(
        [
            "run",
            str(EXAMPLES / "sweep.toml"),
            "-o",
            f"{target}/",
            "--scheduler",
            client.scheduler.address,
            "--chunk",
            "3",
            "--quiet",
            "--set",
            'load.p0=["0.1 MPa"]',
        ]
    )
    assert code == 0
    ds = xpersson.open_dataset(target)
    assert ds.area_fraction.dims == ("H", "E", "p0", "zeta") and ds.sizes["p0"] == 1
    assert main(["validate", str(EXAMPLES / "sweep.toml")]) == 0
    assert "a sweep of 6 points" in capsys.readouterr().err
    code = main(["run", str(EXAMPLES / "elastic.toml"), "-o", f"{tmp_path / 'x'}/"])
    assert code == 2


def test_stacked_spectrum_sweep_on_two_worker_processes_equals_serial(client):
    """Blocks of points stacked in one run (issue 25) on the workers: equal to serial."""
    sc = scene(spectrum={"H": [0.6, 0.7, 0.8, 0.9], "h_rms": ["0.5 um", "1 um", "2 um"]})
    serial = xpersson.solve(sc)
    par = xpersson.solve(sc, scheduler=client, chunk=3)  # 4 blocks of 3 stacked points
    _same(serial, par)


def test_blocks_after_the_fill_stops_keep_their_shared_memory_variables(client):
    """Seed 29, scene 85 of ``fuzz.py --sweeps 1 --parallel processes``: blocks whose layouts
    differ (gap_pdf's u grid depends on the point) stop the fill; the blocks that arrived
    after it had lost P, which their workers had written into shared memory: NaN at 2-3 of
    the 4 points, with status success. Now every point equals the serial sweep bit for bit."""
    data = {
        "spectrum": {"model": "self_affine", "H": [0.5457968754246835, 0.6457968754246834],
                     "q_L": "354717.92292565637 1/m", "q_r": "354717.92292565637 1/m",
                     "q_1": "10255778832.96368 1/m", "rms_slope": 0.08146546608445901},
        "material": {"E": "850274149.6808615 Pa",
                     "nu": [0.4933578389988561, 0.3933578389988561]},
        "load": {"p0": "230006141.03228334 Pa"},
        "output": {"zeta_per_decade": 16, "pressure_pdf": True, "p_points": 477},
        "solver": {"rtol": 8.921984394040833e-06},
        "coefficient": {"model": "elastic", "closure": "wm17"},
        "analyses": {"mean_gap": {}, "gap_pdf": {"method": "closed_form"},
                     "leakage": {"p_out": "25653.12227258165 Pa",
                                 "seal_length": "0.015026082024144984 m"}},
    }  # fmt: skip
    serial = xpersson.solve(data)
    for chunk in (1, 2):
        par = xpersson.solve(data, scheduler=client, chunk=chunk)
        assert not np.isnan(par["P"].values).any(), chunk
        for name in serial.data_vars:
            x, y = serial[name].values, par[name].transpose(*serial[name].dims).values
            if name == "gap_pdf":  # its last bits: whether a process has built its kernel
                scale = np.nanmax(np.abs(x))  # (README: within 9e-15 of the largest density)
                np.testing.assert_allclose(y, x, rtol=0, atol=1e-13 * scale)
                continue
            assert np.array_equal(x, y, equal_nan=x.dtype.kind == "f"), (name, chunk)
