"""Archives of viscoelastic solves: round trip and re-solve from the stored scene."""

from __future__ import annotations

import json

import numpy as np
from visco_testlib import scene

import xpersson


def test_archive_round_trip_and_reproduce(tmp_path):
    sc = scene(
        {
            "velocity": "2 cm/s",
            "modulus": "prony",
            "delta_E": ["1 GPa", "0.5 GPa"],
            "relaxation_times": ["1 us", "1 ms"],
            "shift": "arrhenius",
            "activation_energy": "60 kJ/mol",
            "temperature": "300 K",
        },
        analyses={"friction": {"tau_f": "0.3 MPa", "correction": "s_factor"}},
    )
    ds = xpersson.solve(sc)
    path = tmp_path / "visco.nc"
    xpersson.to_netcdf(ds, path)
    back = xpersson.open_dataset(path)
    for name in (
        "mu",
        "mu_visc_cumulative",
        "loss_integral",
        "effective_modulus",
        "sliding_speed",
        "shift_factor",
    ):
        np.testing.assert_array_equal(back[name].values, ds[name].values)
        assert back[name].attrs["units"] == ds[name].attrs["units"]
        assert back[name].attrs["valid_min"] == 0.0
    stored = json.loads(back.attrs["xpersson_scene"])
    again = xpersson.solve(stored)
    np.testing.assert_array_equal(again["mu"].values, ds["mu"].values)
