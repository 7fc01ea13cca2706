"""Sweeps: any sweepable parameter takes a list or a range; one dimension per parameter."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from hypothesis import given, settings
from hypothesis import strategies as st
from xpersson_sweep_testlib import SlidingCoefficient, scene

import xpersson
from xpersson.plugins import ParamSpec
from xpersson.scene import SceneError
from xpersson.sweep import plain_paths
from xpersson.testing import registry_with

SWEEP_SCENE = scene(spectrum={"H": [0.6, 0.8]}, material={"E": ["5 MPa", "10 MPa", "20 MPa"]})


@pytest.fixture(scope="module")
def swept() -> xr.Dataset:
    return xpersson.solve(SWEEP_SCENE)


def _single(E: float, H: float) -> xr.Dataset:
    return xpersson.solve(scene(spectrum={"H": H}, material={"E": f"{E!r} Pa"}))


def test_dims_units_and_order(swept):
    assert swept.area_fraction.dims == ("H", "E", "p0", "zeta")
    assert swept["E"].attrs["units"] == "Pa" and swept["H"].attrs["units"] == "1"
    assert swept["E"].attrs["xpersson_parameter"] == "material.E"
    np.testing.assert_array_equal(swept["E"].values, [5e6, 1e7, 2e7])
    # variables that do not depend on a swept parameter keep only the dims they depend on
    assert swept.psd_C.dims == ("H", "q_psd")
    assert swept.E_star.dims == ("E",)
    assert swept.point_status.dims == ("H", "E") and int(swept.point_status.max()) == 0


@pytest.mark.parametrize("plain", [False, True])
def test_sweep_equals_stacked_individual_solves(swept, plain):
    """Point by point (``plain_paths``): bit for bit; batched (several loads per point solved
    as one batch of equivalent loads, contact similarity): to the contract's 1e-12."""
    if plain:
        with plain_paths():
            swept = xpersson.solve(SWEEP_SCENE)
    for H in (0.6, 0.8):
        for E in (5e6, 1e7, 2e7):
            one = _single(E, H)
            for name in ("area_fraction", "non_contact_fraction", "G", "psd_C", "E_star"):
                var = swept[name]
                got = var.sel({k: v for k, v in {"E": E, "H": H}.items() if k in var.dims})
                if plain:
                    np.testing.assert_array_equal(got.values, one[name].values, err_msg=name)
                else:
                    np.testing.assert_allclose(got.values, one[name].values, 1e-12, 0, name)


@pytest.mark.parametrize(("H", "nu"), [([1.0], 0.25), ([0.3, 0.9, 0.6], 0.4)])
def test_zipped_group_equals_individual_solves(H, nu):
    nus = [nu + 0.01 * i for i in range(len(H))]
    sc = scene(spectrum={"H": H}, material={"nu": nus})
    sc["sweep"] = {"mode": "zip"}
    ds = xpersson.solve(sc)
    assert ds.area_fraction.dims == ("H", "p0", "zeta")  # named after the first parameter
    assert ds["nu"].dims == ("H",)
    for i, (h, n) in enumerate(zip(H, nus, strict=True)):
        one = xpersson.solve(scene(spectrum={"H": h}, material={"nu": n}))
        np.testing.assert_array_equal(ds.area_fraction.isel(H=i).values, one.area_fraction.values)


def test_plugin_declared_dims_v_and_T():
    sc = scene(
        coefficient={
            "model": "sliding",
            "velocity": ["0 m/s", "1 m/s"],
            "temperature": {"start": "250 K", "stop": "350 K", "num": 3, "spacing": "linear"},
        }
    )
    with registry_with(coefficients={"sliding": SlidingCoefficient}):
        ds = xpersson.solve(sc)
        one = xpersson.solve(
            scene(coefficient={"model": "sliding", "velocity": "1 m/s", "temperature": "300 K"})
        )
    assert ds.area_fraction.dims == ("v", "T", "p0", "zeta")
    assert ds["v"].attrs["units"] == "m s^-1" and ds["T"].attrs["units"] == "K"
    np.testing.assert_array_equal(ds["T"].values, [250.0, 300.0, 350.0])
    np.testing.assert_array_equal(
        ds.area_fraction.sel(v=1.0, T=300.0).values, one.area_fraction.values
    )
    # each point saw its own scalar values: tau scales as (1 + v) T / 293 K
    tau = ds.diffusion_time.isel(zeta=slice(1, None))
    np.testing.assert_allclose(tau.isel(v=1, T=2) / tau.isel(v=0, T=0), 2 * 350 / 250, rtol=1e-12)


def test_naming_rule_falls_back_to_the_dotted_path():
    ds = xpersson.solve(scene(spectrum={"h_rms": ["0.5 um", "1 um"]}))
    assert "spectrum_h_rms" in ds.dims and ds.h_rms.dims == ("spectrum_h_rms",)
    np.testing.assert_allclose(ds.h_rms.values, [0.5e-6, 1e-6], rtol=1e-12)


def test_collisions_and_bad_sweeps_are_refused():
    class Clash(SlidingCoefficient):
        parameters = {
            **SlidingCoefficient.parameters,
            "speed2": SlidingCoefficient.parameters["velocity"],
            "fixed": ParamSpec("1", default=1.0, description="not sweepable"),
        }

    with registry_with(coefficients={"clash": Clash}), pytest.raises(SceneError, match="'v'"):
        xpersson.solve(
            scene(
                coefficient={
                    "model": "clash",
                    "velocity": ["1 m/s", "2 m/s"],
                    "speed2": ["1 m/s", "2 m/s"],
                }
            )
        )
    with (
        registry_with(coefficients={"clash": Clash}),
        pytest.raises(SceneError, match=r"coefficient\.fixed: this parameter is not sweepable"),
    ):
        xpersson.solve(scene(coefficient={"model": "clash", "fixed": [1.0, 2.0]}))
    with pytest.raises(SceneError, match="output.zeta_per_decade"):
        xpersson.solve(scene(output={"zeta_per_decade": [2, 3]}))
    with pytest.raises(SceneError, match="same number of values"):
        xpersson.solve(
            {
                **scene(spectrum={"H": [0.6, 0.8]}, material={"nu": [0.3, 0.4, 0.5]}),
                "sweep": {"mode": "zip"},
            }
        )
    with pytest.raises(SceneError, match=r"material\.E\[1\].*outside"):
        xpersson.solve(scene(material={"E": ["1 MPa", "-1 MPa"]}))
    with pytest.raises(SceneError, match="magnification grid"):
        xpersson.solve(scene(spectrum={"q_1": ["1e7 1/m", "1e8 1/m"]}))
    ds = xpersson.solve(
        scene(
            spectrum={"q_1": ["1e7 1/m", "1e8 1/m"]}, output={"zeta_max": 1e4, "zeta_per_decade": 4}
        )
    )
    assert ds.area_fraction.dims == ("q_1", "p0", "zeta")


def test_progress_bar_counts_points_on_stderr(capsys):
    xpersson.solve(scene(spectrum={"H": [0.6, 0.8]}), progress=True)
    err = capsys.readouterr().err
    assert "xpersson sweep" in err and "2/2" in err
    xpersson.solve(scene(spectrum={"H": [0.6, 0.8]}), progress=False)
    assert capsys.readouterr().err == ""


def test_order_table_and_reproduce_keep_the_dimension_order(tmp_path):
    sc = scene(spectrum={"H": [0.6, 0.8]}, material={"E": ["5 MPa", "10 MPa"]})
    sc["sweep"] = {"order": ["material.E", "spectrum.H"]}
    ds = xpersson.solve(sc)
    assert ds.area_fraction.dims == ("E", "H", "p0", "zeta")
    from xpersson.cli import main

    xpersson.to_netcdf(ds, tmp_path / "a.nc")
    assert main(["reproduce", str(tmp_path / "a.nc"), "-o", str(tmp_path / "b.nc")]) == 0
    again = xpersson.open_dataset(tmp_path / "b.nc")
    assert again.area_fraction.dims == ds.area_fraction.dims
    with pytest.raises(SceneError, match="sweep.order"):
        xpersson.solve({**sc, "sweep": {"order": ["material.nu"]}})


def test_unknown_scheduler_is_refused_before_any_work():
    with pytest.raises(ValueError, match="scheduler: 'gpu' is not allowed"):
        xpersson.solve(scene(spectrum={"H": [0.6, 0.8]}), scheduler="gpu")


def test_threads_scheduler_equals_serial(swept):
    threads = xpersson.solve(SWEEP_SCENE, scheduler="threads", chunk=1)
    for name in swept.variables:
        xr.testing.assert_identical(threads[name], swept[name])


@pytest.mark.parametrize("workers", [1, 2])
def test_threads_scheduler_uses_the_requested_number_of_threads(swept, workers, monkeypatch):
    import threading

    from xpersson.sweep import execute

    seen: set[int] = set()
    original = execute.run_block

    def recording(*args, **kwargs):
        seen.add(threading.get_ident())
        return original(*args, **kwargs)

    monkeypatch.setattr(execute, "run_block", recording)
    threads = xpersson.solve(SWEEP_SCENE, scheduler="threads", chunk=1, workers=workers)
    assert 1 <= len(seen) <= workers  # six one-point blocks, at most `workers` threads
    assert threading.get_ident() not in seen
    xr.testing.assert_identical(threads.area_fraction, swept.area_fraction)


@settings(max_examples=150, deadline=None)
@given(
    shape=st.lists(st.integers(1, 9), min_size=1, max_size=3),
    per_block=st.integers(1, 60),
    multiple=st.integers(1, 3),
    workers=st.integers(1, 3),
)
def test_blocks_tile_the_grid_evenly_and_workers_get_equal_shares(
    shape, per_block, multiple, workers
):
    from types import SimpleNamespace

    from xpersson.sweep.blocks import _assign, blocks_of

    dims = tuple(f"d{i}" for i in range(len(shape)))
    plan = SimpleNamespace(
        shape=tuple(shape),
        dims=dims,
        coords=lambda: {
            d: (d, np.arange(n, dtype=float), {}) for d, n in zip(dims, shape, strict=True)
        },
    )
    blocks = blocks_of(plan, per_block, multiple)
    cover = np.zeros(shape, int)
    for b in blocks:
        cover[tuple(slice(a, c) for a, c in zip(b.start, b.stop, strict=True))] += 1
        assert b.size <= per_block and b.coords["d0"][1].size == b.shape[0]
    assert (cover == 1).all()  # every point in exactly one block
    for d in range(len(shape)):  # pieces along any dimension differ by at most one
        lengths = [b.shape[d] for b in blocks]
        assert max(lengths) - min(lengths) <= 1
    split = [d for d in range(len(shape)) if any(b.shape[d] < shape[d] for b in blocks)]
    if split:  # the innermost cut dimension: a multiple of `multiple` pieces where it can
        count = len({b.start[split[-1]] for b in blocks})
        assert count % multiple == 0 or count == shape[split[-1]]
    sizes = sorted({b.size for b in blocks})
    owner = _assign(blocks, workers)
    load = [
        sum(b.size for b, w in zip(blocks, owner, strict=True) if w == k) for k in range(workers)
    ]
    assert sum(load) == int(np.prod(shape)) and max(load) - min(load) <= sizes[-1]


@pytest.mark.parametrize("batched", [False, True])
@pytest.mark.parametrize("chunk", [1, 4])
def test_single_load_sweep_equals_individual_solves(chunk, batched):
    """Points with one scalar load: stacked unsqueezed, the block squeezed once (p0 a scalar
    coordinate), identical to each point's own solve point by point; solved as a batch of
    equivalent loads (contact similarity, :mod:`xpersson.sweep.batched`) equal to 1e-13; the
    model error's ancillary variables included (identical: the bands do not depend on E)."""
    data = scene(
        spectrum={"H": [0.6, 0.8]},
        material={"E": ["5 MPa", "20 MPa"]},
        load={"p0": "1e5 Pa"},
        analyses={"contact_area": {}},
    )
    if batched:
        swept = xpersson.solve(data, chunk=chunk)
    else:
        with plain_paths():
            swept = xpersson.solve(data, chunk=chunk)
    assert swept.area_fraction.dims == ("H", "E", "zeta") and swept.p0.dims == ()
    for H in (0.6, 0.8):
        for E in ("5 MPa", "20 MPa"):
            one = xpersson.solve(
                scene(
                    spectrum={"H": H},
                    material={"E": E},
                    load={"p0": "1e5 Pa"},
                    analyses={"contact_area": {}},
                )
            )
            got = swept.sel(H=H, E=float(E.split()[0]) * 1e6)
            for name in one.data_vars:
                if name in ("E", "H"):
                    continue
                have = got[name].drop_vars(["E", "H"], errors="ignore")
                if batched and have.dtype.kind == "f":
                    xr.testing.assert_allclose(have, one[name], rtol=1e-13, atol=1e-300)
                    assert have.attrs == one[name].attrs
                else:
                    xr.testing.assert_identical(have, one[name])


def test_block_sizes_serial_and_on_workers():
    """Serial in memory: blocks of BLOCK_CURVES curves (points x loads), at least
    SERIAL_BLOCK_POINTS curves; on workers with a measured serial time: tasks of about TASK_S,
    2 to 16 per worker, no larger than a serial block; without one: a quarter of each
    worker's share; chunk= wins."""
    from types import SimpleNamespace

    from xpersson.sweep.schedule import (
        BLOCK_CURVES,
        SERIAL_BLOCK_POINTS,
        TASK_S,
        points_per_block,
    )

    for size in (1, 150, SERIAL_BLOCK_POINTS, 4 * SERIAL_BLOCK_POINTS + 4, 10_000, 10**5):
        plan = SimpleNamespace(size=size)
        assert points_per_block(plan, 1, None) == -(-size // 4)  # no estimate: unchanged
        for loads in (1, 10, 100):
            serial = points_per_block(plan, 1, None, serial_in_memory=True, loads=loads)
            assert serial == max(BLOCK_CURVES // loads, min(size, SERIAL_BLOCK_POINTS // loads), 1)
            assert serial == size or serial * loads >= min(BLOCK_CURVES, SERIAL_BLOCK_POINTS)
        for estimate, tasks in ((0.1, 4), (3 * TASK_S, 4), (10 * TASK_S, 10), (1e3, 32)):
            got = points_per_block(plan, 2, None, estimate=estimate)
            cap = points_per_block(plan, 1, None, serial_in_memory=True)  # a serial block
            assert got == max(1, min(cap, -(-size // tasks)))
        assert points_per_block(plan, 1, 7, serial_in_memory=True) == 7  # chunk= wins
