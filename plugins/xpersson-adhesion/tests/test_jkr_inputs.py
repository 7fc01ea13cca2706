"""Bad input is refused before any work, naming the parameter, its unit and the allowed range;
the plugin contract (xpersson.testing.check_plugin); the Tabor-parameter warning."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from adhesion_testlib import PDMS, with_

from xpersson.scene import SceneError
from xpersson_adhesion import AdhesionLimitWarning, JKRBoundary

JKR = {"model": "jkr", "work_of_adhesion": "0.05 J/m**2"}


@pytest.mark.parametrize(
    ("boundary", "load", "words"),
    [
        (
            {**JKR, "work_of_adhesion": "-0.01 J/m**2"},
            None,
            ["boundary.work_of_adhesion", "J/m**2", "[0, inf]"],
        ),
        ({**JKR, "c_a": 0.0}, None, ["boundary.c_a", "(0, inf]"]),
        ({**JKR, "c_a": -2.0}, None, ["boundary.c_a", "outside the allowed range"]),
        (
            {**JKR, "sigma_a": ["1 kPa", "-2 kPa"], "sigma_a_zeta": [1.0, 1e5]},
            None,
            ["boundary.sigma_a", "Pa", "[0, inf]"],
        ),
        (
            {**JKR, "sigma_a": ["1 kPa", "2 kPa", "3 kPa"], "sigma_a_zeta": [1.0, 1e4, 1e3]},
            None,
            ["boundary.sigma_a_zeta", "strictly increasing"],
        ),
        (
            {**JKR, "sigma_a": ["1 kPa", "2 kPa"], "sigma_a_zeta": [1.0, 10.0]},
            None,
            ["boundary.sigma_a_zeta", "must span", "[1, 100000]"],
        ),
        ({**JKR, "sigma_a": ["1 kPa", "2 kPa"]}, None, ["boundary.sigma_a_zeta", "[1]"]),
        ({**JKR, "range": "0 nm"}, None, ["boundary.range", "m", "(0, inf]"]),
        (JKR, {"p0": ["-1 MPa", "1 kPa"]}, ["load.p0", "-1e+06 Pa", "-sigma_a(zeta=1)"]),
        ({**JKR, "sigma_a": ["1 kPa"]}, {"p0": "-1 kPa"}, ["load.p0", "-1000 Pa", "> -sigma_a"]),
    ],
)
def test_bad_input_names_parameter_unit_and_range(solve, boundary, load, words):
    scene = with_(PDMS, boundary=boundary)
    if load is not None:
        scene["load"] = load
    with pytest.raises((SceneError, ValueError)) as info:
        solve(scene)
    msg = str(info.value)
    for w in words:
        assert w in msg, f"{w!r} not in {msg!r}"


@pytest.mark.parametrize(
    ("params", "words"),
    [
        ({"work_of_adhesion": -1.0}, ["work_of_adhesion", "J/m^2", "[0, inf]"]),
        ({"work_of_adhesion": 0.1, "c_a": 0.0}, ["c_a", "(0, inf]"]),
        (
            {
                "work_of_adhesion": 0.1,
                "sigma_a": np.array([1.0, 2.0]),
                "sigma_a_zeta": np.array([2.0, 1.0]),
            },
            ["sigma_a_zeta", "strictly increasing"],
        ),
        (
            {
                "work_of_adhesion": 0.1,
                "sigma_a": np.array([1.0, -2.0]),
                "sigma_a_zeta": np.array([1.0, 2.0]),
            },
            ["sigma_a", "Pa", "[0, inf]"],
        ),
    ],
)
def test_bad_input_python_api(params, words):
    with pytest.raises(ValueError) as info:
        JKRBoundary(**params)
    for w in words:
        assert w in str(info.value)


def test_compressive_only_boundaries_refuse_tensile_loads(solve):
    with pytest.raises(SceneError, match=r"load.p0.*outside the allowed range \(0, 1e\+13\] Pa"):
        solve(with_(PDMS, boundary={"model": "elastic"}, load={"p0": ["-1 kPa", "1 kPa"]}))
    with pytest.raises(SceneError, match="spacing"):
        solve(with_(PDMS, load={"p0": {"start": "-1 kPa", "stop": "1 kPa", "num": 3}}))


def test_tabor_warning_when_the_limit_is_contradicted(solve):
    with pytest.warns(AdhesionLimitWarning, match="'dmt' limit"):
        solve(
            with_(
                PDMS,
                load={"p0": "1 kPa"},
                solver={"rtol": 1e-3},
                boundary={**JKR, "work_of_adhesion": "1e-4 J/m**2", "range": "10 nm"},
            )
        )
    with warnings.catch_warnings():
        warnings.simplefilter("error", AdhesionLimitWarning)
        ds = solve(with_(PDMS, load={"p0": "1 kPa"}))  # soft PDMS, 0.05 J/m^2: JKR is right
    assert np.median(ds["tabor_parameter"].values) > 1


@pytest.mark.fast_paths
def test_check_plugin_contract():
    from xpersson.testing import check_plugin

    for params in ({"work_of_adhesion": 0.05}, {"work_of_adhesion": 0.0, "sigma_a": [2e3]}):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", AdhesionLimitWarning)
            report = check_plugin(JKRBoundary, params, balance_tol=1e-5)
        assert report["metadata"] == "ok" and report["pickle"] == "ok"


def test_dataset_metadata(solve):
    ds = solve(PDMS)
    for name, spec in JKRBoundary.outputs.items():
        assert ds[name].attrs["units"] == spec.attrs()["units"]
        assert ds[name].dims == spec.dims
        if spec.valid_min is not None:
            assert float(ds[name].min()) >= spec.valid_min
        if spec.valid_max is not None:
            assert float(ds[name].max()) <= spec.valid_max
    # the engine's diagnostics reach the Dataset
    assert set(ds["solver_status"].values) == {"success"}
    assert float(np.max(np.abs(ds["probability_balance"]))) < 1e-5
