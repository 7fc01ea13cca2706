"""List-valued velocity and temperature become the Dataset dimensions v and T (core sweeps)."""

from __future__ import annotations

import numpy as np
import pytest
from visco_testlib import scene

import xpersson

FRICTION = {"friction": {"tau_f": "0.5 MPa", "shear_law": "velocity"}}
WLF = {"shift": "wlf", "T_ref": "293.15 K", "C1": 7.84, "C2": "114.75 K"}


def test_velocity_and_temperature_lists_become_dimensions(tmp_path):
    pytest.importorskip("xpersson.sweep")
    v = ["1e-4 m/s", "1 cm/s", "1 m/s"]
    T = ["273.15 K", "313.15 K"]
    ds = xpersson.solve(scene({"velocity": v, "temperature": T, **WLF}, analyses=FRICTION))
    assert ds["mu"].dims == ("v", "T", "p0")
    assert ds["mu_visc_cumulative"].dims == ("v", "T", "p0", "zeta")
    assert ds["v"].attrs["units"] == "m s^-1" and ds["T"].attrs["units"] == "K"
    np.testing.assert_allclose(ds["v"].values, [1e-4, 1e-2, 1.0], rtol=1e-15)
    np.testing.assert_allclose(ds["T"].values, [273.15, 313.15], rtol=1e-15)
    # each point equals the scalar solve of that (v, T)
    for i, vi in enumerate(v):
        for j, Tj in enumerate(T):
            one = xpersson.solve(
                scene({"velocity": vi, "temperature": Tj, **WLF}, analyses=FRICTION)
            )
            for name in ("mu", "mu_visc", "area_fraction", "loss_integral"):
                np.testing.assert_array_equal(ds[name].isel(v=i, T=j).values, one[name].values)
    # physics across the dimensions: below the peak a colder rubber has more friction
    assert np.all(ds["mu_visc"].isel(v=0, T=0) > ds["mu_visc"].isel(v=0, T=1))
    path = tmp_path / "vT.nc"
    xpersson.to_netcdf(ds, path)
    back = xpersson.open_dataset(path)
    np.testing.assert_array_equal(back["mu"].values, ds["mu"].values)
    assert back["v"].attrs["units"] == "m s^-1"


def test_velocity_range():
    pytest.importorskip("xpersson.sweep")
    ds = xpersson.solve(
        scene({"velocity": {"start": "1e-6 m/s", "stop": "1 m/s", "num": 4}}, analyses=FRICTION)
    )
    np.testing.assert_allclose(ds["v"].values, np.geomspace(1e-6, 1.0, 4), rtol=1e-12)
    assert ds["mu_visc"].dims == ("v", "p0")
    assert np.all(np.diff(ds["mu_visc"].values, axis=0) > 0)  # below the peak: increasing
