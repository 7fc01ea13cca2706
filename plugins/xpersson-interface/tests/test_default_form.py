"""``s_factor = "auto"``, the default of mean_gap and contact_stiffness (chosen by accuracy
against the validation campaign's BEM): Yang-Persson on an uncorrected area, else the closure."""

from __future__ import annotations

import numpy as np
import pytest
from interface_testlib import scene

import xpersson
from xpersson.physics.closures import GAMMA_DEFAULT
from xpersson.scene import Scene
from xpersson_interface.plugins import ContactStiffness, GapPDF, MeanGap

LOADS = [1e3, 1e5]


@pytest.mark.parametrize("cls", [MeanGap, ContactStiffness])
def test_auto_is_the_default_and_gap_pdf_keeps_the_closure(cls):
    assert cls.parameters["s_factor"].default == "auto"
    assert GapPDF.parameters["s_factor"].default == "closure"  # no campaign evidence there


def test_auto_resolves_to_yang_persson_on_persson01_and_is_recorded():
    auto = {"mean_gap": {}, "contact_stiffness": {}}
    yp = {n: {"s_factor": "yang_persson"} for n in auto}
    rs = Scene(scene(LOADS, analyses=auto)).resolve()
    for name in auto:
        params = rs.resolved["analyses"][name]
        assert params["s_factor"] == "yang_persson" and params["gamma"] == GAMMA_DEFAULT
    a = xpersson.solve(scene(LOADS, analyses=auto))
    b = xpersson.solve(scene(LOADS, analyses=yp))
    for name in ("mean_gap", "contact_stiffness"):
        np.testing.assert_array_equal(a[name].values, b[name].values)


@pytest.mark.parametrize("closure", ["yp08", "xu24"])
def test_auto_keeps_a_closure_that_corrects_the_area(closure):
    auto = {"contact_stiffness": {}}
    rs = Scene(scene(LOADS, closure=closure, analyses=auto)).resolve()
    assert rs.resolved["analyses"]["contact_stiffness"]["s_factor"] == "closure"
    explicit = {"contact_stiffness": {"s_factor": "closure"}}
    a = xpersson.solve(scene(LOADS, closure=closure, analyses=auto))
    b = xpersson.solve(scene(LOADS, closure=closure, analyses=explicit))
    np.testing.assert_array_equal(a["contact_stiffness"].values, b["contact_stiffness"].values)


def test_auto_with_gamma_on_a_closure_is_refused():
    bad = {"contact_stiffness": {"gamma": 0.5}}
    with pytest.raises(xpersson.scene.SceneError, match="gamma applies to s_factor"):
        Scene(scene(LOADS, closure="yp08", analyses=bad)).resolve()
