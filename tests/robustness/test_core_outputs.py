"""Fuzz regressions: the cn path's probabilities stay in [0, 1] with a finite error estimate,
and the pipeline checks the engine's core outputs like every plugin output."""

from __future__ import annotations

import dataclasses
import importlib
import warnings

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

import xpersson
from xpersson import checks, pipeline
from xpersson.engine._project import project as _project
from xpersson.plugins._registry import get_registry


def _plastic(
    spectrum: dict, E: str, nu: float, p0: str, zpd: int, rtol: float, Y1: str, n: float, **extra
) -> dict:
    return {
        "spectrum": {"model": "self_affine", **spectrum},
        "material": {"E": E, "nu": nu},
        "load": {"p0": p0},
        "output": {"zeta_per_decade": zpd},
        "solver": {"rtol": rtol},
        "boundary": {"model": "plastic_scale_dependent", "Y1": Y1, "n": n},
        **extra,
    }


# fuzz campaign scene 325: the work budget ran out after an unpaired finer grid (error inf)
SCENE_BUDGET = _plastic(
    {
        "H": 0.618768119255756,
        "q_L": "6792.99610389103 1/m",
        "q_r": "25681.861090831702 1/m",
        "q_1": "5886956071.971901 1/m",
        "rms_slope": 2.6245626995912836,
    },
    "429480.1890168989 Pa",
    0.1444138777200737,
    "0.013672229170790152 Pa",
    8,
    0.0007897298142343878,
    "0.05617793999513956 Pa",
    0.6631961848278108,
)

# fuzz campaign scene 475: non_contact_fraction 1 + 7.7e-12 (round-off of the absorbed sums)
SCENE_OVER_ONE = _plastic(
    {
        "H": 0.5609626087902464,
        "q_L": "837.1762758191403 1/m",
        "q_r": "837.1762758191403 1/m",
        "q_1": "3899.7862790436775 1/m",
        "h_rms": "8.311803081854393e-06 m",
    },
    "24202268906.920994 Pa",
    0.07171633074791195,
    "9.387676807454028 Pa",
    7,
    7.899766898280746e-08,
    "39.35763152939182 Pa",
    0.3335619457845592,
    analyses={"contact_area": {}},
)


def _in_unit(ds, name: str) -> None:
    v = ds[name].values
    assert np.all(np.isfinite(v)), name
    assert v.min() >= 0.0 and v.max() <= 1.0, (name, v.min(), v.max())


def test_budget_spent_leaves_a_finite_error_estimate():
    reg = get_registry()
    rs = pipeline.as_scene(SCENE_BUDGET).resolve(reg)
    # a small work budget reproduces the fuzz path quickly (an unpaired N = 600 grid was last;
    # since the stiff window's substeps (engine._stiff) 1e6 node-steps meet rtol here)
    rs = dataclasses.replace(rs, solver_options={"max_work": 3e5})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = pipeline.run(rs)
    err = ds["error_estimate"].values
    assert np.all(np.isfinite(err)) and err.min() >= 0.0
    assert ds.attrs["status"] == "max_steps"  # honest: the budget did not reach rtol
    _in_unit(ds, "area_fraction")
    _in_unit(ds, "non_contact_fraction")


def test_non_contact_fraction_never_exceeds_one():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = xpersson.solve(SCENE_OVER_ONE)
    _in_unit(ds, "area_fraction")
    _in_unit(ds, "non_contact_fraction")
    assert np.all(np.isfinite(ds["error_estimate"].values))
    # the projection keeps area + non-contact = 1 within the error estimate
    total = ds["area_fraction"].values + ds["non_contact_fraction"].values
    assert np.all(np.abs(total - 1.0) <= ds["error_estimate"].values + 1e-9)


_prob = st.floats(-1e-6, 1.0 + 1e-6, allow_nan=False)


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(_prob, _prob, _prob), min_size=1, max_size=8))
def test_projection_is_admissible_and_moves_only_the_inadmissible(rows):
    a, lo, up = (np.array(c) for c in zip(*rows, strict=True))
    (pa, plo, pup), dist = _project(a, lo, up)
    assert np.all((pa >= 0) & (pa <= 1) & (plo >= 0) & (pup >= 0) & (plo + pup <= 1.0))
    ok = (lo >= 0) & (up >= 0) & (lo + up <= 1.0)
    assert np.array_equal(plo[ok], lo[ok]) and np.array_equal(pup[ok], up[ok])
    inside = (a >= 0) & (a <= 1)
    assert np.array_equal(pa[inside], a[inside])
    assert np.allclose(dist["area"], np.abs(pa - a), rtol=0, atol=0)


ELASTIC = {
    "spectrum": {
        "model": "self_affine",
        "H": 0.8,
        "q_L": "1e4 1/m",
        "q_1": "1e7 1/m",
        "rms_slope": 0.5,
    },
    "material": {"E": "1e9 Pa", "nu": 0.3},
    "load": {"p0": ["1e6 Pa", "2e6 Pa"]},
    "output": {"zeta_per_decade": 4},
}


def test_core_output_violation_is_a_status_not_a_silent_value(monkeypatch):
    run_module = importlib.import_module("xpersson.pipeline.run")  # the module, not run()
    assemble = run_module.assemble

    def corrupt(*args):
        ds = assemble(*args)
        ds["area_fraction"].values[1, -1] = 1.5  # an engine bug on the second load
        return ds

    monkeypatch.setattr(run_module, "assemble", corrupt)
    with warnings.catch_warnings(record=True):
        warnings.simplefilter("always")
        ds = xpersson.solve(ELASTIC)
    assert list(ds["solver_status"].values) == ["success", "balance_violated"]
    assert ds.attrs["status"] == "balance_violated"
    msg = ds.attrs["status_message"]
    assert "area_fraction" in msg and "valid_max" in msg and "p0 = 2e+06 Pa" in msg


def test_core_check_passes_a_clean_solve_and_flags_non_finite_errors():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = xpersson.solve(ELASTIC)
    assert ds.attrs["status"] == "success"
    ds = ds.copy(deep=True)
    assert checks.check_core(ds) == {}
    ds["error_estimate"].values[0, 2] = np.inf
    found = checks.check_core(ds)
    assert list(found) == [0] and "error_estimate" in found[0] and "non-finite" in found[0]
    assert ds["solver_status"].values[0] == "balance_violated"
