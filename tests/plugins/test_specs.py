"""Class-definition checks of plugin metadata (messages name the class and the field)."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

from xpersson.plugins import REQUIRED, Analysis, Boundary, ParamSpec, SpecError, VarSpec


@pytest.mark.parametrize(
    ("spec", "message"),
    [
        (ParamSpec("Pa", default=-1.0, bounds=(0.0, None)), "outside the declared range"),
        (ParamSpec("Pa", bounds=(2.0, 1.0)), "lower bound 2.0 exceeds upper bound 1.0"),
        (ParamSpec("Pa", bounds=(float("nan"), None)), "bounds must be numbers or None"),
        (ParamSpec("", default=1.0), "unit must be a non-empty"),
        (ParamSpec("1", default="x", kind="choice", choices=("a",)), "not among the choices"),
        (ParamSpec("1", default="a", kind="choice", choices="a"), "choices must be a tuple"),
        (ParamSpec("1", default=1, kind="bool"), "needs a bool default"),
        (ParamSpec("1", default=1.0, kind="widget"), "kind must be one of"),
        (ParamSpec("Pa", default=1.0, sweepable="yes"), "sweepable must be True or False"),
        (ParamSpec("Pa", example=-5.0, bounds=(0.0, None)), "example -5.0 lies outside"),
    ],
)
def test_malformed_paramspec(spec, message):
    with pytest.raises(SpecError, match=rf"Wall\.parameters\['x'\]: .*{message}"):
        type("Wall", (Boundary,), {"summary": "s", "parameters": {"x": spec}})


@pytest.mark.parametrize(
    ("attrs", "message"),
    [
        ({"summary": ""}, "summary must be a non-empty"),
        ({"api_version": True}, "api_version must be a positive int"),
        ({"references": "10.1/x"}, "references must be a tuple"),
        ({"references": ("10.1063/1.1388626", "Persson 2001")}, r"\['Persson 2001'\] are not"),
        ({"parameters": {"x": 1.0}}, r"parameters\['x'\] must be a ParamSpec"),
        ({"outputs": {"v": VarSpec(("p0",), "", "v")}}, r"outputs\['v'\]: units must be"),
        ({"outputs": {"v": VarSpec("p0", "1", "v")}}, "dims must be a tuple of str"),
    ],
)
def test_malformed_class_metadata(attrs, message):
    with pytest.raises(SpecError, match=rf"Wall.*{message}"):
        type("Wall", (Boundary,), {"summary": "s", **attrs})


def test_analysis_requires_provides_checks():
    with pytest.raises(SpecError, match=r"provides \['v'\] without declaring them in outputs"):
        type("Ana", (Analysis,), {"summary": "s", "provides": ("v",)})
    with pytest.raises(SpecError, match=r"\['v'\] both required and provided"):
        type(
            "Ana",
            (Analysis,),
            {
                "summary": "s",
                "requires": ("v",),
                "provides": ("v",),
                "outputs": {"v": VarSpec(("p0",), "1", "v")},
            },
        )
    with pytest.raises(SpecError, match="requires must be a tuple of variable names"):
        type("Ana", (Analysis,), {"summary": "s", "requires": "area_fraction"})


def test_sample_and_required():
    assert ParamSpec("Pa").sample is REQUIRED and ParamSpec("Pa").required
    assert ParamSpec("Pa", example=3.0).sample == 3.0
    assert ParamSpec("Pa", default=1.0, example=3.0).sample == 1.0
    assert pickle.loads(pickle.dumps(REQUIRED)) is REQUIRED


def test_instances_compare_with_array_parameters():
    Tab = type(
        "Tab",
        (Boundary,),
        {"summary": "s", "parameters": {"t": ParamSpec("Pa", default=None, array=True)}},
    )
    a, b = Tab(t=np.array([1.0, 2.0])), Tab(t=np.array([1.0, 2.0]))
    assert a == b and a != Tab(t=np.array([1.0, 3.0]))
