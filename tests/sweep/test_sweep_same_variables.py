"""A scene's variables follow from its plugins and parameters, never from its values: the points
of a sweep, its fast and plain paths and the parts of a sweep folder hold the same variables
(found by ``benchmarks/fuzz.py --sweeps``, 2026-12-01: with the xu24 closure the effective
diffusion time was left out at a point in full contact, where it equals tau(zeta); the stacked
fast path kept it there, the plain path and a folder's parts filled it with undocumented NaN)."""

from __future__ import annotations

import copy

import numpy as np

import xpersson

#: xu24 on a nearly smooth surface: at H = 0.97 the contact is full at every magnification.
SCENE = {
    "spectrum": {"model": "self_affine", "H": [0.87, 0.97], "q_L": "22.5 1/m",
                 "q_r": "1048 1/m", "q_1": "3.35e8 1/m", "h_rms": "2.41e-9 m"},
    "material": {"E": "290 MPa", "nu": 0.4},
    "load": {"p0": "17 kPa"},
    "output": {"zeta_per_decade": 14},
    "solver": {"rtol": 5e-5},
    "coefficient": {"model": "elastic", "closure": "xu24"},
}  # fmt: skip


def _point(H: float) -> xpersson.Dataset:
    scene = copy.deepcopy(SCENE)
    scene["spectrum"]["H"] = H
    return xpersson.solve(scene)


def test_a_declared_closure_keeps_its_effective_time_where_it_equals_tau():
    full = _point(0.97)
    assert float(full["area_fraction"].isel(zeta=-1)) == 1.0  # full contact: S = 1
    eff = full["effective_diffusion_time"].values
    np.testing.assert_array_equal(eff, np.broadcast_to(full["diffusion_time"].values, eff.shape))
    assert "effective_diffusion_time" in _point(0.87)


def test_fast_plain_and_folder_sweeps_hold_the_same_values(tmp_path):
    fast = xpersson.solve(SCENE)
    with xpersson.set_options(fast_paths=False):
        plain = xpersson.solve(SCENE)
    zipped = copy.deepcopy(SCENE) | {"sweep": {"mode": "zip"}}
    zipped["material"]["nu"] = [0.4, 0.45]
    folder = xpersson.solve(zipped, output=tmp_path / "study")
    memory = xpersson.solve(zipped)
    for a, b in ((fast, plain), (memory, folder)):
        assert set(a.data_vars) == set(b.data_vars)
        for name in a.data_vars:
            x, y = a[name].values, b[name].transpose(*a[name].dims).values
            assert np.array_equal(x, y, equal_nan=x.dtype.kind == "f"), name
    for ds in (fast, memory):  # no NaN at the full-contact point
        eff = ds["effective_diffusion_time"].values
        assert not np.isnan(eff).any()
