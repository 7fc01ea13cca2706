"""Sweep points stacked in one run (issue 25): equal to the point-by-point path to 1e-12,
used only where every plugin declares ``fast_paths.stacked_params`` and the points differ only
in declared parameters."""

from __future__ import annotations

import numpy as np
import pytest
from xpersson_sweep_testlib import scene

import xpersson
from xpersson.builtin.elastic import ElasticBoundary
from xpersson.pipeline import stacked
from xpersson.plugins import fast_paths_on
from xpersson.sweep import blocks, plain_paths
from xpersson.testing import registry_with

SPECTRUM_SCENE = scene(
    spectrum={"H": [0.6, 0.75, 0.9], "h_rms": ["0.5 um", "2 um"]},
    analyses={"contact_area": {}},
)
H_E_SCENE = scene(
    spectrum={"H": [0.55, 0.7, 0.85, 0.95]},
    material={"E": ["2 MPa", "5 MPa", "40 MPa"]},
    load={"p0": "3e4 Pa"},
    analyses={"contact_area": {}},
)


def _counted(monkeypatch) -> list[int]:
    """Count the stacked runs (and the points they solve); a run whose result the sweep does
    not use (the block solved point by point after it) is recorded as ``-1``."""
    calls: list[int] = []
    run, point_run = stacked.run_stacked, blocks.run

    def counting(points):
        calls.append(len(points))
        return run(points)

    def fallback(*args, **kw):
        if fast_paths_on():  # not the reference solve of the point-by-point path
            calls.append(-1)
        return point_run(*args, **kw)

    monkeypatch.setattr(stacked, "run_stacked", counting)
    monkeypatch.setattr(blocks, "run", fallback)
    return calls


def _both(data, monkeypatch, **kw):
    with plain_paths():
        point = xpersson.solve(data, **kw)
    return point, xpersson.solve(data, **kw)


def _assert_equal(point, batch):
    assert list(batch.variables) == list(point.variables)
    for name, var in point.variables.items():
        got = batch[name]
        assert got.dims == var.dims, name
        if var.dtype.kind == "f":
            np.testing.assert_allclose(got.values, var.values, rtol=1e-12, atol=1e-300)
        else:
            np.testing.assert_array_equal(got.values, var.values)
    skip = {"history", "date_created", "xpersson_solver"}
    assert {k: v for k, v in batch.attrs.items() if k not in skip} == {
        k: v for k, v in point.attrs.items() if k not in skip
    }


@pytest.mark.fast_paths
@pytest.mark.parametrize("chunk", [None, 4])
def test_spectrum_sweep_stacked_equals_point_by_point(monkeypatch, chunk):
    calls = _counted(monkeypatch)
    point, batch = _both(SPECTRUM_SCENE, monkeypatch, chunk=chunk)
    assert calls and sum(calls) == 6  # every point of the 3 x 2 sweep solved stacked
    _assert_equal(point, batch)
    assert batch.psd_C.dims[:2] == ("H", "spectrum_h_rms")  # the spectrum per point


@pytest.mark.fast_paths
def test_h_by_e_sweep_stacks_the_spectra_of_the_equivalent_loads(monkeypatch):
    calls = _counted(monkeypatch)
    point, batch = _both(H_E_SCENE, monkeypatch, chunk=6)
    assert calls == [2, 2]  # each block: its 2 H values in one run of the equivalent loads
    _assert_equal(point, batch)


class _Undeclared(ElasticBoundary):
    """The elastic wall in a subclass that does not declare its ``fast_paths`` again."""

    summary = "elastic wall, fast paths not declared (test double)"


@pytest.mark.fast_paths
def test_undeclared_plugin_is_not_stacked(monkeypatch):
    calls = _counted(monkeypatch)
    data = scene(spectrum={"H": [0.6, 0.8]}, boundary={"model": "undeclared"})
    with registry_with(boundaries={"undeclared": _Undeclared}):
        ds = xpersson.solve(data)
        with plain_paths():
            point = xpersson.solve(data)
    assert calls == [-1, -1]  # no stacked run: both points solved one by one
    np.testing.assert_array_equal(ds.area_fraction.values, point.area_fraction.values)


def test_points_differing_in_an_undeclared_parameter_are_not_stacked():
    from xpersson.pipeline import as_scene

    a = as_scene(scene(spectrum={"q_r": "1e4 1/m"})).resolve()
    b = as_scene(scene(coefficient={"closure": "yp08"})).resolve()
    d = as_scene(scene(spectrum={"q_r": "2e4 1/m"})).resolve()
    c = as_scene(scene(spectrum={"H": 0.6})).resolve()
    assert stacked.stack_reason([a, c]) is None
    assert "not declared in fast_paths.stacked_params" in stacked.stack_reason([a, b])
    assert stacked.stack_reason([a, d]) == "spectrum nodes"
    assert stacked.stack_reason([a]) == "one point"


@pytest.mark.parametrize("failed", [False, True])
def test_constant_dims_of_the_digests(failed):
    """A variable is reduced along the dimensions its digests never change along (the
    all-solved fast comparison and the per-row rule with failed points agree)."""
    from types import SimpleNamespace

    from xpersson.sweep.combine import _constant_dims

    plan = SimpleNamespace(shape=(4, 3), dims=("v", "T"))
    rng = np.random.default_rng(1)
    by_v = rng.integers(0, 2**62, 4)
    grids = {
        "const": np.full((4, 3), 7, dtype=object),
        "by_v": np.repeat(by_v[:, None], 3, axis=1).astype(object),
        "both": rng.integers(0, 2**62, (4, 3)).astype(object),
    }
    if failed:
        for g in grids.values():
            g[1, 2] = None
    results = []
    for start, stop in (((0, 0), (2, 3)), ((2, 0), (4, 3))):
        block = SimpleNamespace(start=start, stop=stop, shape=(2, 3))
        digests = {n: list(g[start[0] : stop[0]].ravel()) for n, g in grids.items()}
        results.append(SimpleNamespace(block=block, digests=digests))
    got = _constant_dims(plan, results)
    assert got == {"const": ["v", "T"], "by_v": ["T"]}
