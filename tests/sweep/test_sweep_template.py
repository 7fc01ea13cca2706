"""A stacked block's template: the first point's Dataset assembled from the stacked run
(``StackedRun.point_dataset``) is what that point's own run gives (variables, values, dims,
attributes), so the sweep need not solve the point a second time."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from xpersson_sweep_testlib import scene

from xpersson.api import as_scene
from xpersson.pipeline import run, stacked

#: the run's timings and stamps (not results)
VOLATILE = {"history", "date_created", "xpersson_solver"}


def assert_same_dataset(own, ref) -> None:
    """Bit for bit the same variables (values, dims, dtypes, attributes) and attributes."""
    assert list(own.variables) == list(ref.variables)
    for name, var in ref.variables.items():
        got = own.variables[name]
        assert got.dims == var.dims and got.dtype == var.dtype, name
        if var.dtype.kind == "f":
            np.testing.assert_array_equal(got.values.view("u8"), var.values.view("u8"), name)
        else:
            np.testing.assert_array_equal(got.values, var.values, name)
        assert got.attrs.keys() == var.attrs.keys(), name
        assert repr(got.attrs) == repr(var.attrs), name
    assert {k: v for k, v in own.attrs.items() if k not in VOLATILE} == {
        k: v for k, v in ref.attrs.items() if k not in VOLATILE
    }


def _points(**sections):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return [as_scene(scene(**s)).resolve() for s in sections["each"]]


@pytest.mark.parametrize("analyses", [{}, {"contact_area": {}}])
def test_the_first_points_dataset_is_its_own_run(analyses):
    points = _points(each=[{"spectrum": {"H": H}, "analyses": analyses} for H in (0.6, 0.75, 0.9)])
    assert stacked.stack_reason(points) is None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        got = stacked.run_stacked(points)
        ref = run(points[0], squeeze=False)
    own = got.point_dataset()
    assert own is not None and own.attrs["status"] == "success"
    assert_same_dataset(own, ref)


def test_a_first_point_that_did_not_succeed_gives_no_template(monkeypatch):
    points = _points(each=[{"spectrum": {"H": H}} for H in (0.6, 0.9)])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        got = stacked.run_stacked(points)

    def failed_check(ds):  # the first point's own run: its first load fails the core check
        ds.variables["solver_status"].values[0] = "balance_violated"
        return {0: "forced"}

    monkeypatch.setattr(stacked.checks, "check_core", failed_check)
    assert got.point_dataset() is None  # the block then goes point by point
