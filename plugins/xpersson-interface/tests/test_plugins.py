"""Plugin classes: metadata, the end-to-end path through xpersson.solve, check_plugin."""

from __future__ import annotations

import numpy as np
import pytest
from interface_testlib import scene

import xpersson
from xpersson.plugins import Analysis
from xpersson_interface.plugins import ContactStiffness, ElasticEnergy, GapPDF, Leakage, MeanGap

ALL = {
    "elastic_energy": ElasticEnergy,
    "mean_gap": MeanGap,
    "contact_stiffness": ContactStiffness,
    "gap_pdf": GapPDF,
    "leakage": Leakage,
}
LOADS = [1e3, 1e4, 1e5, 3e6]


@pytest.mark.parametrize("name", list(ALL))
def test_metadata(name):
    cls = ALL[name]
    assert issubclass(cls, Analysis) and not cls.abstract
    assert set(cls.provides) == set(cls.outputs)
    for spec in cls.outputs.values():
        assert spec.units and spec.long_name
    assert cls.coefficient_traits == frozenset({"elastic_spectrum"})


@pytest.fixture(scope="module")
def ds():
    closure = {"s_factor": "closure"}  # physics.md §5.3's table is Persson 2007's form
    ana = {"mean_gap": closure, "contact_stiffness": closure, "elastic_energy": {},
           "gap_pdf": {"u_points": 48},
           "leakage": {"viscosity": "1 mPa*s", "n_bins": 60}}  # fmt: skip
    return xpersson.solve(scene(LOADS, analyses=ana))


def test_end_to_end_solve(ds):
    units = {
        "mean_gap": "m", "contact_stiffness": "Pa m^-1", "elastic_energy": "J m^-2",
        "elastic_energy_full": "J m^-2", "gap_pdf": "m^-1", "gap_contact_weight": "1",
        "gap_mean": "m", "leak_rate": "m^3 s^-1", "leak_u1": "m", "leak_sealed": "1",
        "leak_rate_emt": "m^3 s^-1",
    }  # fmt: skip
    for name, unit in units.items():
        assert ds[name].attrs["units"] == unit, name
        assert ds[name].attrs["long_name"]
    # physics.md §5.3 through the default scene (the analysis samples the solve densely)
    np.testing.assert_allclose(ds["mean_gap"].values[:3], [3.658462e-6, 1.297668e-6,
                                                           8.231990e-8], rtol=5e-6)  # fmt: skip
    np.testing.assert_allclose(ds["elastic_energy_full"].values, 5.931643e-2, rtol=1e-6)
    assert ds["gap_pdf"].dims == ("p0", "u") and ds["u"].attrs["units"] == "m"
    # contact fraction of the gap distribution = the core's area at the finest scale
    A = ds["area_fraction"].isel(zeta=-1).values
    np.testing.assert_allclose(ds["gap_contact_weight"].values, A, rtol=1e-12)
    assert ds["leak_sealed"].values.tolist() == [0, 0, 0, 1]
    # valid ranges are written as CF attributes
    assert ds["mean_gap"].attrs["valid_min"] == 0.0


def test_stiffness_without_singular_values(ds):
    """Near full contact K stays finite and grows (it was -inf or 6e74 before)."""
    K = ds["contact_stiffness"].values
    assert np.all(np.isfinite(K)) and np.all(np.diff(K) > 0)
    # low-load law K ~ p0 / u0 (u0 = 1.239822e-6 m, physics.md §5.3), within the O(1/ln) drift
    assert K[0] / LOADS[0] * 1.239822e-6 == pytest.approx(1.0, rel=0.1)


def test_diffusion_method_matches_closed_form():
    sc = scene([1e4, 1e5], analyses={"gap_pdf": {"u_points": 32, "method": "diffusion",
                                                 "n_bins": 150}})  # fmt: skip
    a = xpersson.solve(sc)
    sc["analyses"]["gap_pdf"]["method"] = "closed_form"
    b = xpersson.solve(sc)
    np.testing.assert_allclose(a["gap_mean"].values, b["gap_mean"].values, rtol=0.01)


def test_the_solved_curve_names_are_the_cores():
    """``solved_curve``, ``Solved``, ``dense_zeta`` and ``FORMS`` moved to the core
    (:mod:`xpersson.plugins.solved`, shared with xpersson-transport); the old names still work."""
    import xpersson_interface
    from xpersson.plugins import solved

    for name in ("solved_curve", "Solved", "dense_zeta", "FORMS"):
        assert getattr(xpersson_interface, name) is getattr(solved, name), name
