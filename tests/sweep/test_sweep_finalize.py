"""sweep finalize: the constant sweep dimensions dropped in numpy equal xarray's reductions
(NaN and failed points skipped), the variables' order and attributes kept; a variable that
keeps a sweep dimension gets the failed point's NaN documented in its comment."""

from __future__ import annotations

import numpy as np
import xarray as xr

from xpersson.sweep.parts import finalize
from xpersson.sweep.stacking import GAP, POINT_STATUS


def _dataset() -> xr.Dataset:
    rng = np.random.default_rng(5)
    status = np.zeros((3, 2), dtype=np.int8)
    status[1, 0] = POINT_STATUS["failed"]
    curve = np.broadcast_to(rng.random(4), (3, 2, 4)).copy()  # constant along v and T
    curve[1, 0] = np.nan  # the failed point
    steps = np.broadcast_to(np.array([3, 7], dtype=np.int64), (3, 2, 2)).copy()
    steps[1, 0] = -1  # the failed point's fill value
    return xr.Dataset(
        {
            "varying": (("v", "T", "zeta"), rng.random((3, 2, 4)), {"units": "1"}),
            "curve": (("T", "v", "zeta"), curve.transpose(1, 0, 2), {"units": "Pa"}),
            "steps": (("v", "T", "n"), steps, {"units": "1"}),
            "label": (("v", "T"), np.full((3, 2), "elastic", dtype=object)),
            "point_status": (("v", "T"), status),
        },
        coords={"v": [1.0, 2.0, 3.0], "T": [273.0, 293.0], "zeta": np.arange(1.0, 5.0)},
    )


def test_finalize_drops_constant_dims_as_xarray_would():
    ds = _dataset()
    constant = {"curve": ["v", "T"], "steps": ["v", "T"], "label": ["v", "T"], "none": ["v"]}
    out = finalize(ds.copy(), constant, {"title": "t"})
    ok = ds["point_status"] != POINT_STATUS["failed"]
    want_curve = ds["curve"].max(["v", "T"], skipna=True)
    want_steps = ds["steps"].where(ok, ds["steps"].min()).max(["v", "T"]).astype(np.int64)
    xr.testing.assert_identical(out["curve"].variable, want_curve.variable.copy())
    assert out["curve"].attrs == {"units": "Pa"}
    np.testing.assert_array_equal(out["steps"].values, want_steps.values)
    assert out["steps"].dtype == np.int64 and out["steps"].dims == ("n",)
    assert out["label"].dims == () and out["label"].item() == "elastic"
    assert list(out.variables) == list(ds.variables)  # order kept
    want = ds["varying"].copy()
    want.attrs["comment"] = f"NaN means: {GAP}"  # the failed point (v, T) = (1, 0)
    xr.testing.assert_identical(out["varying"], want)
    assert out.attrs == {"title": "t"}
