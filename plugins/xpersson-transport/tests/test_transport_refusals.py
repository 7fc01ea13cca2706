"""Bad input and unsupported boundaries are refused before any work, naming what is wrong."""

from __future__ import annotations

import pytest
from transport_testlib import AIR, electrical, scene, thermal

import xpersson
from xpersson.plugins import get_registry
from xpersson.scene import SceneError
from xpersson_transport.plugins import ElectricalContact, ThermalContact


@pytest.fixture
def no_engine(monkeypatch):
    """Make any engine run fail: the refusals below must come before it."""
    from xpersson import engine

    def no_work(*args, **kwargs):
        raise AssertionError("the engine ran before the scene was refused")

    monkeypatch.setattr(engine, "solve_batch", no_work)


@pytest.mark.parametrize(
    ("analysis", "params", "pattern"),
    [
        ("electrical_contact", electrical(rho1=-1e-8),
         r"analyses\.electrical_contact\.resistivity_1: .*-1e-08 ohm\*m.*\(0, inf\] ohm\*m"),
        ("electrical_contact", {"resistivity_2": "1e-8 ohm*m"},
         r"analyses\.electrical_contact\.resistivity_1.*required"),
        ("thermal_contact", thermal(k2=0.0), r"conductivity_2.*\(0, inf\] W/\(m\*K\)"),
        ("thermal_contact", thermal(gap_medium="gas"),
         r"gas_conductivity \[W/\(m\*K\)\] is required when gap_medium = 'gas'.*\[0, inf\]"),
        ("thermal_contact", thermal(gap_medium="gas", gas_conductivity="0.026 W/(m*K)"),
         r"gas_mean_free_path \[m\] is required .*\(0, inf\] m"),
        ("thermal_contact", thermal(**dict(AIR, gas_mean_free_path="0 m")),
         r"gas_mean_free_path: .*\(0, inf\] m"),
        ("thermal_contact", thermal(accommodation_1=1.5), r"accommodation_1: .*\(0, 1\]"),
        ("electrical_contact", electrical(film_thickness="2 nm"),
         r"film_resistivity \[ohm\*m\] is required when film_thickness > 0"),
        ("thermal_contact", thermal(film_thickness="2 nm"),
         r"film_conductivity \[W/\(m\*K\)\] is required when film_thickness > 0"),
        ("electrical_contact", electrical(film_thickness="-1 nm"), r"film_thickness: .*\[0, inf\]"),
        ("thermal_contact", thermal(gamma=0.5), r"gamma applies to s_factor = 'yang_persson'"),
    ],
)  # fmt: skip
def test_bad_input_refused_before_work(no_engine, analysis, params, pattern):
    with pytest.raises(SceneError, match=pattern):
        xpersson.solve(scene([1e5], {analysis: params}))


_PLASTIC = {"model": "plastic", "sigma_Y": "1 MPa"}
_JKR = {"model": "jkr", "work_of_adhesion": "0.05 J/m**2"}


@pytest.mark.parametrize("analysis", ["electrical_contact", "thermal_contact"])
@pytest.mark.parametrize(("boundary", "trait"), [(_PLASTIC, "load_similar"),
                                                 (_JKR, "repulsive")])  # fmt: skip
def test_plastic_and_adhesive_boundaries_refused_before_work(no_engine, analysis, boundary, trait):
    """The scene is refused at resolve time; the core checks the required contact_stiffness
    (xpersson-interface) first, so its message names that analysis, the boundary and the trait."""
    params = electrical() if analysis == "electrical_contact" else thermal()
    with pytest.raises(SceneError) as err:
        xpersson.solve(scene([1e5], {analysis: params}, boundary=boundary))
    msg = str(err.value)
    assert "analyses.contact_stiffness" in msg and f"boundary {boundary['model']!r}" in msg
    assert trait in msg


_WHY = [
    ("plastic", "unloading stiffness"),
    ("plastic_scale_dependent", "unloading stiffness"),
    ("jkr", "adhesive"),
    ("dmt", "adhesive"),
]


@pytest.mark.parametrize("cls", [ElectricalContact, ThermalContact])
@pytest.mark.parametrize(("boundary", "why"), _WHY)
def test_own_reason_names_both_plugins(cls, boundary, why):
    """The analyses' own reason for each refused boundary (``supports``/``check_scene``)."""
    bnd = get_registry().load("boundaries", boundary)
    msg = cls.supports(bnd, None)
    assert msg is not None and why in msg
    assert "xpersson-transport" in msg and "xpersson-interface" in msg
    assert cls.supports(get_registry().load("boundaries", "elastic"), None) is None
