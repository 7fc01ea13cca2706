"""The pipeline hands the engine the whole batch; fixed costs once per process; memory budget."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

import xpersson
from xpersson import memory, provenance
from xpersson.cache import cache
from xpersson.engine import exact, solve
from xpersson.pipeline import assemble
from xpersson.schema import COORDS, CORE_VARIABLES, stamp
from xpersson.units import to_si

SCENE = {
    "spectrum": {
        "model": "self_affine",
        "H": 0.8,
        "q_L": "1e3 1/m",
        "q_r": "1e4 1/m",
        "q_1": "1e8 1/m",
        "h_rms": "1 um",
    },
    "material": {"E": "10 MPa", "nu": 0.5},
    "load": {"p0": {"start": "1 kPa", "stop": "1 MPa", "num": 40}},
}


def test_many_loads_equal_the_closed_form_per_load():
    ds = xpersson.solve(SCENE)
    tau = ds.diffusion_time.values
    ref = exact.one_wall_area(tau[None, :], ds.p0.values[:, None])
    np.testing.assert_allclose(ds.area_fraction.values, ref, rtol=1e-14)
    one = solve(tau, float(ds.p0[7]))
    np.testing.assert_array_equal(ds.area_fraction.values[7], one.area)
    assert list(ds.solver_status.values) == ["success"] * 40


def test_dataset_built_directly_is_identical_to_the_public_constructor(monkeypatch):
    scene = dict(SCENE, output={"pressure_pdf": True, "p_points": 16})
    fast = xpersson.solve(scene)

    def slow(data, coords):
        ds = xr.Dataset(data, coords=coords)
        stamp(ds, COORDS)
        stamp(ds, CORE_VARIABLES)
        return ds

    monkeypatch.setattr(assemble, "_dataset", slow)
    ref = xpersson.solve(scene)
    for ds in (fast, ref):
        for key in ("history", "date_created", "xpersson_solver"):
            ds.attrs.pop(key)
    xr.testing.assert_identical(fast, ref)


def test_environment_and_units_are_computed_once_per_process():
    store = provenance._environment_json.cache
    store.clear()
    cache("provenance.kind_attributes").clear()  # the attributes a kind of scene shares
    with xpersson.set_options(cache=True):  # also in CI's run with the caches off
        xpersson.solve(SCENE)
        xpersson.solve(SCENE)
    assert store.info().misses == 1
    a = to_si(["1 MPa", "2 MPa"], "Pa", "load.p0", array=True)
    a[0] = -1.0  # the cached conversion is not shared with the caller
    b = to_si("1 MPa", "Pa", "load.p0")
    assert b == 1e6 and to_si(["1 MPa", "2 MPa"], "Pa", "x", array=True)[0] == 1e6


def test_request_above_the_memory_budget_is_refused_before_work(monkeypatch):
    calls = []
    monkeypatch.setattr(xpersson.engine, "solve_batch", lambda *a, **k: calls.append(1))
    scene = dict(SCENE, output={"pressure_pdf": True, "p_points": 4000})
    memory.set_budget("1 MB")
    try:
        with pytest.raises(memory.MemoryBudgetError) as info:
            xpersson.solve(scene)
    finally:
        memory.set_budget(None)
    text = str(info.value)
    for words in (
        "MB",
        "40 loads",
        "4000 pressures",
        "output.p_points",
        "in parts",
        "XPERSSON_MEMORY_BUDGET",
    ):
        assert words in text
    assert not calls


def test_memory_budget_configuration(monkeypatch):
    monkeypatch.setenv("XPERSSON_MEMORY_BUDGET", "2 GiB")
    assert memory.budget() == 2 * 2**30
    monkeypatch.setenv("XPERSSON_MEMORY_BUDGET", "lots")
    with pytest.raises(ValueError, match="XPERSSON_MEMORY_BUDGET"):
        memory.budget()
    monkeypatch.delenv("XPERSSON_MEMORY_BUDGET")
    assert 0 < memory.budget() <= memory.available()
    assert memory.estimate(10, 51, 256) > memory.estimate(10, 51)


def test_elastic_balances_are_identities_said_so_in_their_attrs():
    ds = xpersson.solve(SCENE)
    for name in ("load_balance", "probability_balance"):
        assert np.all(ds[name].values == 0.0)
        assert "exactly 0, not evaluated" in ds[name].attrs["comment"]
        assert ds[name].attrs["units"] == "1"  # the CF attributes are kept
    plastic = xpersson.solve(
        dict(
            SCENE,
            boundary={"model": "plastic", "sigma_Y": "2 MPa"},
            load={"p0": ["0.1 MPa", "1 MPa"]},
        )
    )
    comment = plastic["probability_balance"].attrs["comment"]
    assert "not evaluated" not in comment and "absorbed" in comment  # evaluated: a check
    assert np.max(np.abs(plastic["probability_balance"].values)) < 1e-10


def test_self_affine_spectrum_is_built_once_and_frozen():
    with xpersson.set_options(cache=True):  # shared: also in CI's run with the caches off
        a = xpersson.Scene(SCENE).resolve().psd
        b = xpersson.Scene(SCENE).resolve().psd
    assert a is b and a.frozen
    with pytest.raises(AttributeError, match="frozen"):
        a.C_r = 1.0
    with pytest.raises(ValueError):
        a._Ca[0] = 1.0  # noqa: SLF001 - the arrays are read-only
    other = xpersson.Scene(dict(SCENE, spectrum=dict(SCENE["spectrum"], H=0.7))).resolve().psd
    assert other is not a
    # cached moments equal a fresh computation
    fresh = type(a)(a.C_r, a.H, a.q_L, a.q_r, a.q_1)
    assert a.h_rms() == fresh.h_rms() and a.rms_slope() == fresh.rms_slope()
    assert a.moment(1.0, 2e3, 5e4) == fresh.moment(1.0, 2e3, 5e4)
