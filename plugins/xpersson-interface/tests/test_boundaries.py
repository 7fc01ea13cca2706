"""Analyses x boundaries: declared traits decide, non-elastic forms and refusals (issue 10)."""

from __future__ import annotations

import numpy as np
import pytest
from interface_testlib import scene

import xpersson
from xpersson.scene import SceneError

LOADS = [2e4, 1e5, 4e5]


def _plastic(sigma_y):
    return {"model": "plastic", "sigma_Y": f"{sigma_y!r} Pa"}


def test_infinite_hardness_recovers_the_elastic_energy():
    ana = {"elastic_energy": {}, "contact_area": {}}
    el = xpersson.solve(scene(LOADS, analyses=ana))
    pl = xpersson.solve(scene(LOADS, boundary=_plastic(1e13), analyses=ana))
    np.testing.assert_allclose(pl["elastic_energy"], el["elastic_energy"], rtol=1e-8)
    np.testing.assert_allclose(pl["mean_contact_pressure"], el["mean_contact_pressure"], rtol=1e-8)


def test_finite_hardness_energy_is_bounded_and_monotone():
    """Derived limits: the yield wall only removes elastic area, A_el(sigma_Y) <= A_elastic and
    A_el grows with sigma_Y, so U_el(sigma_Y) <= U_elastic and U_el increases with sigma_Y."""
    ana = {"elastic_energy": {}}
    el = xpersson.solve(scene(LOADS, analyses=ana))["elastic_energy"].values
    U = [
        xpersson.solve(scene(LOADS, boundary=_plastic(s), analyses=ana))["elastic_energy"].values
        for s in (5e5, 1e6, 4e6)
    ]
    assert np.all(U[0] < U[1]) and np.all(U[1] < U[2]) and np.all(U[2] <= el * (1 + 1e-12))
    assert np.all(np.asarray(U) > 0)


def test_mean_contact_pressure_uses_the_load_bearing_area():
    """Elastic + plastic contact carries p0: p0 <= p0/(A_el + A_pl) <= sigma_Y (was 30-156 MPa)."""
    sy = 6e5
    ds = xpersson.solve(scene(LOADS, boundary=_plastic(sy), analyses={"contact_area": {}}))
    pm = ds["mean_contact_pressure"].values
    p0 = np.asarray(LOADS)[:, None]
    assert np.all(pm >= p0 * (1 - 1e-12)) and np.all(pm <= sy * (1 + 1e-9))
    # at the finest scale nearly all of the load is plastic: the mean pressure nears sigma_Y
    assert pm[:, -1].min() > 0.9 * sy


@pytest.mark.parametrize("name", ["mean_gap", "contact_stiffness", "gap_pdf", "leakage"])
@pytest.mark.parametrize("boundary", ["plastic", "plastic_scale_dependent"])
def test_gap_analyses_refuse_plastic_naming_both(name, boundary):
    bnd = _plastic(1e6) if boundary == "plastic" else {
        "model": boundary, "Y1": "1 MPa", "n": 0.2}  # fmt: skip
    with pytest.raises(SceneError) as err:
        xpersson.solve(scene(LOADS, boundary=bnd, analyses={name: {}}))
    msg = str(err.value)
    assert f"analyses.{name}" in msg and f"boundary {boundary!r}" in msg
    assert "load_similar" in msg


def test_yang_persson_form_on_a_corrected_area_is_refused():
    with pytest.raises(SceneError, match="already corrects the area"):
        xpersson.solve(scene(LOADS, closure="yp08",
                             analyses={"mean_gap": {"s_factor": "yang_persson"}}))  # fmt: skip
    with pytest.raises(SceneError, match="gamma applies to s_factor = 'yang_persson'"):
        xpersson.solve(scene(LOADS, analyses={"elastic_energy": {"gamma": 0.45}}))


def test_declared_support_is_listed_by_plugins_show():
    from xpersson.cli_plugins import describe

    d = describe("analyses", "mean_gap")
    assert "elastic" in d["boundaries"]["supported"]
    assert "plastic" in d["boundaries"]["refused"]
    assert d["boundary_traits"] == ["load_similar", "repulsive"]
    d = describe("analyses", "elastic_energy")
    assert {"elastic", "plastic"} <= set(d["boundaries"]["supported"])
    assert describe("boundaries", "plastic")["traits"] == ["repulsive"]


def test_a_boundary_installed_later_is_judged_by_its_declaration(xpersson_registry):
    """A new boundary (e.g. adhesion, issue 11) needs no edit here: its traits decide."""
    from xpersson.builtin.elastic import ElasticBoundary

    class Sticky(ElasticBoundary):
        summary = "test double: elastic wall declaring no repulsion"
        traits = frozenset({"load_similar"})

    class Repulsive(ElasticBoundary):
        summary = "test double: elastic wall with every trait"

    sc = scene([1e5], boundary={"model": "sticky"}, analyses={"mean_gap": {}})
    xpersson_registry(boundaries={"sticky": Sticky, "rep": Repulsive})
    with pytest.raises(SceneError, match="repulsive"):
        xpersson.solve(sc)
    sc["boundary"] = {"model": "rep"}
    assert xpersson.solve(sc)["mean_gap"].values.ravel()[0] > 0


def test_the_archive_records_form_and_gamma():
    import json

    ds = xpersson.solve(scene([1e5], analyses={"mean_gap": {"s_factor": "yang_persson"},
                                               "elastic_energy": {}}))  # fmt: skip
    rec = json.loads(ds.attrs["xpersson_scene"])["analyses"]
    assert rec["mean_gap"]["s_factor"] == "yang_persson" and rec["mean_gap"]["gamma"] == 0.42
    assert rec["elastic_energy"]["s_factor"] == "closure"
    assert json.loads(ds.attrs["xpersson_scene"])["coefficient"]["closure"] == "persson01"


def test_a_missing_variable_names_who_could_provide_it(xpersson_registry):
    from xpersson.plugins import Analysis, VarSpec

    class PlasticShare(Analysis):
        summary = "test double: needs the plastic area"
        requires = ("plastic_area_fraction",)
        provides = ("share",)
        outputs = {"share": VarSpec(("p0",), "1", "plastic share")}

    xpersson_registry(analyses={"share": PlasticShare})
    with pytest.raises(SceneError, match=r"boundary 'plastic' \(xpersson-plasticity\)"):
        xpersson.solve(scene([1e5], analyses={"share": {}}))
