"""An analysis grid that depends on the point (``gap_pdf``'s ``u``, from the point's mean gap):
a sweep keeps every value on its own coordinate, the union of the points' grids, serial, in
parallel and in a folder alike (found by ``benchmarks/fuzz.py --sweeps --parallel threads``,
2026-12-01: serially the second point's densities were labelled with the first point's
separations; chunked or in a folder the grids were joined with undocumented NaN)."""

from __future__ import annotations

import copy

import numpy as np

import xpersson

SCENE = {
    "spectrum": {"model": "self_affine", "H": 0.8, "q_L": "1e3 1/m", "q_r": "1e3 1/m",
                 "q_1": "1e6 1/m", "h_rms": "1 um"},
    "material": {"E": ["1 MPa", "3 MPa"], "nu": 0.5},
    "load": {"p0": ["10 kPa", "50 kPa"]},
    "output": {"zeta_per_decade": 4},
    "analyses": {"gap_pdf": {"u_points": 64}},
}  # fmt: skip


def _point(E: str) -> xpersson.Dataset:
    scene = copy.deepcopy(SCENE)
    scene["material"]["E"] = E
    return xpersson.solve(scene)


def test_every_point_keeps_its_own_separations(tmp_path):
    sweep = xpersson.solve(SCENE)
    for k, E in enumerate(SCENE["material"]["E"]):
        one = _point(E)
        got = sweep["gap_pdf"].isel(E=k).sel(u=one["u"].values).transpose("p0", "u")
        np.testing.assert_array_equal(got.values, one["gap_pdf"].transpose("p0", "u").values)
    assert sweep.sizes["u"] == 127  # 2 x 64 points, u = 0 shared
    assert "NaN means: not on this sweep point's u grid" in sweep["gap_pdf"].attrs["comment"]
    for other in (
        xpersson.solve(SCENE, scheduler="threads", chunk=1, workers=2),
        xpersson.solve(SCENE, output=tmp_path / "study"),
    ):
        for name in sweep.data_vars:
            x, y = sweep[name].values, other[name].transpose(*sweep[name].dims).values
            assert np.array_equal(x, y, equal_nan=x.dtype.kind == "f"), name
        assert "not on this sweep point's u grid" in other["gap_pdf"].attrs["comment"]
