"""``dmt`` loads solved together: the same ``p_rep`` as a cold solve of each load, to the
requested tolerance, in fewer evaluations; the reference's bracket around a guess."""

from __future__ import annotations

import warnings

import numpy as np
from adhesion_testlib import with_

import xpersson
from xpersson.testing import material, scene
from xpersson_adhesion import AdhesionLimitWarning
from xpersson_adhesion._dmt_reference import _bracket_near

LOADS = ["2 kPa", "6 kPa", "12 kPa", "20 kPa"]
BASE = scene(material=material("1 MPa"), p0=LOADS, zeta_per_decade=4)
DMT = {"model": "dmt", "work_of_adhesion": "0.005 J/m**2", "range": "2 nm"}


def _solve(data):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AdhesionLimitWarning)
        return xpersson.solve(data)


def test_warm_started_loads_equal_cold_solves_to_rtol():
    rtol = 1e-7
    together = _solve(with_(BASE, boundary=DMT, solver={"rtol": rtol}))
    for k, p0 in enumerate(LOADS):
        alone = _solve(with_(BASE, boundary=DMT, solver={"rtol": rtol}, load={"p0": p0}))
        np.testing.assert_allclose(
            together["p_rep"].values[k], alone["p_rep"].values, rtol=4 * rtol
        )
        assert together["dmt_residual"].values[k] <= rtol
    # loads solved together share the exact evaluations of p_att (the solver's samples do not
    # depend on the loads): the batch costs less than its loads solved one by one
    assert _evaluations(LOADS) < sum(_evaluations([p0]) for p0 in LOADS)


def _evaluations(loads):
    from xpersson_adhesion import dmt

    made = []
    original = dmt.solve_loads

    def counting(amap, p0):
        out = original(amap, p0)
        made.append(amap.evaluations)
        return out

    dmt.solve_loads = counting
    try:
        _solve(with_(BASE, boundary=DMT, solver={"rtol": 1e-7}, load={"p0": loads}))
    finally:
        dmt.solve_loads = original
    return sum(made)


def test_bracket_near_holds_the_sign_change():
    root = 3.7

    def g(p):
        return p - root

    for guess in (3.69999, 3.7, 3.8, 1.0, 9.0):
        a, b = _bracket_near(g, 0.5, 10.0, guess)
        assert 0.5 <= a < b <= 10.0 and g(a) < 0 <= g(b)
