"""Material sweeps solved as batches of equivalent loads (contact similarity) equal the
point-by-point path to rounding; plugins that do not declare it are solved point by point."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from xpersson_sweep_testlib import scene

import xpersson
from xpersson.builtin.elastic import ElasticBoundary
from xpersson.sweep import batched, plain_paths
from xpersson.sweep.stacking import _row_digests
from xpersson.testing import registry_with

MATERIAL_SCENE = scene(
    spectrum={"H": [0.6, 0.9]},
    material={"E": ["2 MPa", "5 MPa", "40 MPa"], "nu": [0.2, 0.45]},
    load={"p0": "3e4 Pa"},
    analyses={"contact_area": {}},
    coefficient={"closure": "yp08"},
)


def _both(data, monkeypatch, **kw):
    with plain_paths():
        point = xpersson.solve(data, **kw)
    return point, xpersson.solve(data, **kw)


@pytest.mark.fast_paths
@pytest.mark.parametrize("chunk", [None, 5])
def test_batched_material_sweep_equals_point_by_point(monkeypatch, chunk):
    from xpersson.sweep import blocks

    with plain_paths():
        point = xpersson.solve(MATERIAL_SCENE, chunk=chunk)

    def no_fallback(*a, **k):  # a block that falls back would pass the comparison silently
        raise AssertionError("a block fell back to point by point")

    monkeypatch.setattr(blocks, "run", no_fallback)
    batch = xpersson.solve(MATERIAL_SCENE, chunk=chunk)
    assert list(batch.variables) == list(point.variables)
    for name, var in point.variables.items():
        got = batch[name]
        assert got.dims == var.dims, name  # constant dimensions found alike
        if var.dtype.kind == "f":
            np.testing.assert_allclose(got.values, var.values, rtol=1e-12, atol=1e-300)
        else:
            np.testing.assert_array_equal(got.values, var.values)
    skip = {"history", "date_created", "xpersson_solver"}
    assert {k: v for k, v in batch.attrs.items() if k not in skip} == {
        k: v for k, v in point.attrs.items() if k not in skip
    }


class _Undeclared(ElasticBoundary):
    """The elastic wall in a subclass that does not declare its ``fast_paths`` again."""

    summary = "elastic wall, similarity not declared (test double)"


def test_undeclared_plugin_is_solved_point_by_point(monkeypatch):
    data = scene(material={"E": ["5 MPa", "20 MPa"]}, boundary={"model": "undeclared"})
    calls = []
    with registry_with(boundaries={"undeclared": _Undeclared}):
        monkeypatch.setattr(batched, "_similar_run", lambda *a: calls.append(a))
        xpersson.solve(data)
        assert calls == []  # the undeclared subclass never reaches the batched path
        monkeypatch.undo()
        point, batch = _both(data, monkeypatch)
    xr.testing.assert_identical(point.drop_attrs(), batch.drop_attrs())


@pytest.mark.parametrize(
    ("units", "power"),
    [
        ("Pa", 1), ("Pa2", 2), ("Pa^2", 2), ("Pa-1 m", -1), ("Pa^-1 m", -1), ("1", 0),
        ("m4", 0), (None, 0), ("J m^-2", 1), ("N m^-1", 1), ("W m^-2 K^-1", 1), ("m s^-1", 0),
        ("S m^-2", 0), ("K", 0), ("Pa m^-1", 1),
    ],
)  # fmt: skip
def test_pressure_power(units, power):
    assert batched.pressure_power(units) == power


def test_row_digests_equal_rows_equal_fingerprints():
    rng = np.random.default_rng(1)
    rows = rng.normal(size=(6, 7))
    rows[4] = rows[1]
    d = _row_digests(rows)
    assert d[4] == d[1] and len(set(d)) == 5
    rows[4, 3] = np.nextafter(rows[4, 3], np.inf)  # one ulp apart: another fingerprint
    assert _row_digests(rows)[4] != d[1]


def test_processes_on_a_small_study_falls_back_to_serial_with_a_message(monkeypatch):
    """No cluster is started for a study cheaper than the stated start-up cost."""
    import distributed

    from xpersson.sweep import schedule

    def refuse(*args, **kwargs):
        raise AssertionError("a cluster was started for a study smaller than its start-up")

    monkeypatch.setattr(distributed, "LocalCluster", refuse)
    data = scene(material={"E": ["5 MPa", "20 MPa"]}, load={"p0": "3e4 Pa"})
    with pytest.warns(xpersson.XperssonWarning, match=r"starting the worker processes and sending"):
        got = xpersson.solve(data, scheduler="processes")
    xr.testing.assert_identical(got.drop_attrs(), xpersson.solve(data).drop_attrs())
    monkeypatch.setattr(schedule, "CLUSTER_STARTUP_S", 0.0)  # a study that pays: the cluster
    monkeypatch.setattr(schedule, "PARALLEL_MIN_S", 0.0)
    with pytest.raises(AssertionError, match="cluster was started"):
        xpersson.solve(data, scheduler="processes")


def test_batched_result_does_not_depend_on_the_blocks():
    """Every block scales from the same reference point: any cut of the grid gives the same
    bits (serial, threads and dask blocks alike)."""
    whole = xpersson.solve(MATERIAL_SCENE)
    for chunk in (1, 4, 7):
        cut = xpersson.solve(MATERIAL_SCENE, chunk=chunk)
        xr.testing.assert_identical(whole.drop_attrs(), cut.drop_attrs())


@pytest.mark.fast_paths
@pytest.mark.parametrize("outer", ["material", "spectrum"])
@pytest.mark.parametrize("loads", ["3e4 Pa", ["1e4 Pa", "3e4 Pa", "1e5 Pa"]])
def test_rows_written_into_the_sweep_arrays_equal_copied_rows(monkeypatch, outer, loads):
    """An in-memory sweep writes batched rows straight into its arrays (the fill's sink);
    with the sink giving no rows, each block is copied in: the same bits, whichever dimension
    is outer, with one load (squeezed) or several."""
    sweep_first = {"material": {"E": ["2 MPa", "5 MPa", "40 MPa"], "nu": 0.5}}
    data = scene(spectrum={"H": [0.6, 0.75, 0.9]}, load={"p0": loads}, **sweep_first)
    if outer == "spectrum":  # the spectrum's dimension first (material dims innermost)
        data = {"spectrum": data["spectrum"], **{k: v for k, v in data.items() if k != "spectrum"}}
    else:
        data = {"material": data["material"], **{k: v for k, v in data.items() if k != "material"}}
    from xpersson.sweep.filling import Filling

    given = []
    rows = Filling.rows
    monkeypatch.setattr(Filling, "rows", lambda *a: given.append(rows(*a)) or given[-1])
    direct = xpersson.solve(data, chunk=4)
    assert any(r is not None for r in given)  # the rows did go to the sweep's arrays
    monkeypatch.setattr(Filling, "rows", lambda *a: None)  # every block copied in
    copied = xpersson.solve(data, chunk=4, scheduler="threads")
    assert list(direct.variables) == list(copied.variables)
    for name, var in copied.variables.items():
        assert direct[name].dims == var.dims, name
        np.testing.assert_array_equal(direct[name].values, var.values, err_msg=name)
