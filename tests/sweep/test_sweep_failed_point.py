"""A sweep in which one point fails: the failed point is flagged (status and message) and filled
with NaN, the sweep dimension stays on every variable, and the other point equals its own solve.

Scene: the adhesion example (jkr) at a tensile load that roughness forbids at a work of adhesion
of 0.03 J/m^2 (gamma_eff(1) <= 0, the contact would detach at once) but allows at 0.05 J/m^2.
"""

from __future__ import annotations

import copy
import json
import tomllib
from pathlib import Path

import numpy as np
import pytest

import xpersson

EXAMPLE = (
    Path(__file__).resolve().parents[2]
    / "plugins"
    / "xpersson-adhesion"
    / "examples"
    / "pdms_on_glass.toml"
)
W = ["0.03 J/m**2", "0.05 J/m**2"]


def _scene(work_of_adhesion: object) -> dict:
    pytest.importorskip("xpersson_adhesion")
    data = tomllib.loads(EXAMPLE.read_text(encoding="utf-8"))
    data["load"]["p0"] = ["-6 kPa", "10 kPa"]
    data["output"]["zeta_per_decade"] = 2
    data["boundary"]["work_of_adhesion"] = copy.deepcopy(work_of_adhesion)
    return data


@pytest.mark.parametrize("chunk", [1, 2])
def test_failed_point_is_flagged_and_the_other_equals_its_own_solve(chunk, tmp_path):
    with pytest.raises(xpersson.SceneError, match="outside the allowed range"):
        xpersson.solve(_scene(W[0]))
    one = xpersson.solve(_scene(W[1]))
    for ds in (
        xpersson.solve(_scene(W), chunk=chunk),
        xpersson.solve(_scene(W), chunk=chunk, output=tmp_path / f"parts{chunk}"),
    ):
        assert ds.point_status.values.tolist() == [2, 0]
        assert ds.attrs["status"] == "failed"
        msgs = json.loads(ds.attrs["xpersson_point_messages"])
        assert [m["point"] for m in msgs] == [{"work_of_adhesion": 0.03}]
        assert msgs[0]["status"] == "failed"
        assert msgs[0]["message"].startswith("SceneError: ")
        assert "load.p0" in msgs[0]["message"] and "outside the allowed range" in msgs[0]["message"]
        for name in ("area_fraction", "w_eff", "pull_off_stress"):
            # one solved point says nothing about a dependence: the dimension stays
            assert "work_of_adhesion" in ds[name].dims, name
            assert np.isnan(ds[name].sel(work_of_adhesion=0.03).values).all(), name
            assert "NaN means:" in ds[name].attrs["comment"], name  # documented, as every NaN
            np.testing.assert_array_equal(
                ds[name].sel(work_of_adhesion=0.05).values, one[name].values
            )


@pytest.mark.parametrize("chunk", [1, 2])
def test_in_memory_combine_equals_xarray_combine_nested(chunk, monkeypatch):
    """The preallocated fill of block Datasets equals ``xarray.combine_nested`` over the
    blocks, failed block (NaN, point_status) and strings included."""
    data = _scene(W)
    data["material"]["nu"] = [0.3, 0.4, 0.5]
    fast = xpersson.solve(data, chunk=chunk)
    from xpersson.sweep import filling

    def refuse(self):  # the fill gives the blocks back: xarray joins them
        self.restore()

    monkeypatch.setattr(filling.Filling, "dataset", refuse)
    slow = xpersson.solve(data, chunk=chunk)
    assert fast.sizes["nu"] == 3 and fast.point_status.shape == (3, 2)
    assert set(fast.attrs) == set(slow.attrs)
    slow.attrs = fast.attrs  # the two solves differ in run times and creation dates only
    assert fast.identical(slow)


def test_sweep_whose_every_point_is_refused_raises_a_scene_error():
    """Every point refused by the boundary's check (tensile load beyond -sigma_a(1) at both
    works of adhesion): a SceneError naming the first point and the parameter, not a crash."""
    data = _scene(["0.02 J/m**2", "0.03 J/m**2"])
    data["load"]["p0"] = ["-6 kPa"]
    with pytest.raises(
        xpersson.SceneError,
        match=r"every point of the sweep was refused; "
        r"first \(work_of_adhesion = 0.02\): .*load\.p0.*allowed range",
    ):
        xpersson.solve(data)
