"""A declared fast path that fails is reported, never hidden (issue 33, part 4).

The rule (:mod:`xpersson.sweep._fastfail`): the block is solved point by point, which isolates
a failing point; when every point then succeeds, the fast path failed where the plain path did
not, and the sweep warns, records it in the attribute ``xpersson_fast_path_failures`` (and in
the block's part) and returns the plain path's values. A genuinely bad point is recorded as a
failed point, as before, with no fast-path report.
"""

from __future__ import annotations

import json
import warnings
from typing import Any

import numpy as np
import pytest
from xpersson_sweep_testlib import scene

import xpersson
from xpersson.builtin.elastic import ElasticCoefficient
from xpersson.plugins import FastPaths, ParamSpec
from xpersson.sweep import plain_paths
from xpersson.testing import registry_with

ATTR = "xpersson_fast_path_failures"


class _Fragile(ElasticCoefficient):
    """The elastic coefficient that raises at ``fragile`` > 1 (a genuinely bad point)."""

    summary = "elastic coefficient failing at fragile > 1 (test double)"
    parameters = {
        **ElasticCoefficient.parameters,
        "fragile": ParamSpec("1", default=0.0, sweepable=True, dim="fragile", description="x"),
    }
    fast_paths = FastPaths(
        contact_similarity=True,
        stacked_params=frozenset({"fragile"}),
        shared_tau={"closure": "persson01"},
    )

    def tau(self, ctx: Any, zeta: np.ndarray) -> np.ndarray:
        if self.params["fragile"] > 1:
            raise ValueError("fragile: this point cannot be solved")
        if ctx.p0.size > 1 and self.params["fragile"] < 0:  # only the batched loads path
            raise RuntimeError("broken batch of loads")
        return super().tau(ctx, zeta)


class _BrokenStacked(_Fragile):
    """Its declared stacked path raises; its plain path works."""

    summary = "elastic coefficient whose stacked path raises (test double)"
    fast_paths = FastPaths(stacked_params=frozenset({"fragile"}), shared_tau=True)

    def tau_stacked(self, ctxs: Any, points: Any, zeta: np.ndarray) -> Any:
        raise RuntimeError("broken stacked path")


def _solve(data: dict[str, Any], **kw: Any) -> Any:
    with registry_with(coefficients={"fragile": _Fragile, "broken_stacked": _BrokenStacked}):
        return xpersson.solve(data, **kw)


def _plain(data: dict[str, Any], **kw: Any) -> Any:
    with plain_paths():
        return _solve(data, **kw)


@pytest.mark.fast_paths
@pytest.mark.parametrize("scheduler", [None, "threads"])
def test_a_raising_stacked_path_is_reported_with_the_plain_values(scheduler, tmp_path):
    data = scene(coefficient={"model": "broken_stacked", "fragile": [0.1, 0.2, 0.3]})
    for kw in ({}, {"output": tmp_path / f"parts-{scheduler}"}):
        with pytest.warns(xpersson.XperssonWarning, match="fast path 'stacked_params'") as rec:
            ds = _solve(data, scheduler=scheduler, chunk=3, **kw)  # one block of 3 points
        text = str(rec[0].message) if len(rec) == 1 else "\n".join(str(r.message) for r in rec)
        assert "_BrokenStacked" in text and "RuntimeError: broken stacked path" in text
        failures = json.loads(ds.attrs[ATTR])
        assert failures and all("_BrokenStacked" in f for f in failures)
        assert ds.point_status.values.tolist() == [0, 0, 0]
        plain = _plain(data)
        np.testing.assert_array_equal(ds.area_fraction.values, plain.area_fraction.values)
        assert ATTR not in plain.attrs  # the plain path has no fast path to fail


@pytest.mark.fast_paths
def test_the_failure_is_kept_in_the_part_of_a_resumed_run(tmp_path):
    data = scene(coefficient={"model": "broken_stacked", "fragile": [0.1, 0.2]})
    with pytest.warns(xpersson.XperssonWarning, match="fast path"):
        first = _solve(data, output=tmp_path / "run", chunk=2)
    again = _solve(data, output=tmp_path / "run", chunk=2)  # every part reused: nothing solved
    assert again.attrs[ATTR] == first.attrs[ATTR]


@pytest.mark.fast_paths
def test_a_raising_batch_of_equivalent_loads_is_reported():
    data = scene(
        coefficient={"model": "fragile", "fragile": -1.0},
        material={"E": ["2 MPa", "5 MPa", "40 MPa"]},
        load={"p0": "3e4 Pa"},
    )
    with pytest.warns(xpersson.XperssonWarning, match="fast path 'contact_similarity'") as rec:
        ds = _solve(data)
    assert any("RuntimeError: broken batch of loads" in str(r.message) for r in rec)
    assert "_Fragile" in ds.attrs[ATTR]
    np.testing.assert_array_equal(ds.area_fraction.values, _plain(data).area_fraction.values)


def test_a_genuinely_bad_point_is_recorded_as_before_without_a_report():
    data = scene(coefficient={"model": "fragile", "fragile": [0.5, 2.0, 0.7]})
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        ds = _solve(data)
    assert not [r for r in rec if "fast path" in str(r.message)]
    assert ATTR not in ds.attrs
    assert ds.point_status.values.tolist() == [0, 2, 0]
    msgs = json.loads(ds.attrs["xpersson_point_messages"])
    assert len(msgs) == 1 and "fragile: this point cannot be solved" in msgs[0]["message"]
    plain = _plain(data)
    np.testing.assert_array_equal(ds.area_fraction.values, plain.area_fraction.values)
