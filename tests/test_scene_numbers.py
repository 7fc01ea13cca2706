"""A scene's numbers are converted once per parameter declaration and value (the process cache
``scene.numbers``, issue 36: the resolution of every solve converted them again): the kept
value is the conversion's, keyed on every field of the declaration, and a value that fails
raises its own message, naming where it was given, every time."""

from __future__ import annotations

import dataclasses

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import xpersson
from xpersson.cache import cache
from xpersson.scene import SceneError
from xpersson.scene._convert import _convert_number, convert_param
from xpersson.specs import ParamSpec

PRESSURE = ParamSpec(unit="Pa", bounds=(0.0, None), inclusive=(False, True))
STIFF = dataclasses.replace(PRESSURE, bounds=(1e6, None))  # the same unit, another range
COUNT = ParamSpec(unit="1", kind="int", default=3, bounds=(1, 10))


@given(
    value=st.one_of(
        st.floats(-1e9, 1e9, allow_nan=False),
        st.integers(-10, 20),
        st.sampled_from(["1 MPa", "0.5 kPa", "3", "-2 Pa", "1e7 Pa", "2 m", "x Pa", "7.5"]),
    ),
    spec=st.sampled_from([PRESSURE, STIFF, COUNT]),
)
@settings(max_examples=25, deadline=None)
def test_kept_conversion_equals_a_fresh_one(value, spec):
    def fresh():
        try:
            return "ok", _convert_number(spec, value, "section.key")
        except SceneError as exc:
            return "error", str(exc)

    want = fresh()
    for _ in range(2):  # the second time from the cache when the first succeeded
        try:
            got = ("ok", convert_param(spec, value, "section.key"))
        except SceneError as exc:
            got = ("error", str(exc))
        assert got == want and type(got[1]) is type(want[1])
    with xpersson.set_options(cache=False):
        try:
            off = ("ok", convert_param(spec, value, "section.key"))
        except SceneError as exc:
            off = ("error", str(exc))
    assert off == want


def test_the_declaration_is_part_of_the_key():
    assert convert_param(PRESSURE, "2 kPa", "load.p0") == 2000.0
    with pytest.raises(SceneError, match=r"material\.E: 2000 Pa is outside"):
        convert_param(STIFF, "2 kPa", "material.E")  # the same text, another range
    assert convert_param(COUNT, 4.0, "solver.n") == 4 and convert_param(COUNT, 4, "x") == 4


def test_a_failing_value_names_its_place_every_time():
    for where in ("material.E", "spectrum.h_rms", "material.E"):
        with pytest.raises(SceneError, match=rf"^{where.replace('.', '[.]')}: "):
            convert_param(PRESSURE, "-1 Pa", where)
    kept = cache("scene.numbers")
    before = len(kept)
    with pytest.raises(SceneError):
        convert_param(PRESSURE, "-3 Pa", "material.E")
    assert len(kept) == before  # errors are never kept


def test_a_declaration_without_a_content_key_converts_each_time():
    class Opaque:  # an example value no content key holds (a plugin's own object)
        pass

    spec = dataclasses.replace(PRESSURE, example=Opaque())
    assert convert_param(spec, "3 kPa", "boundary.x") == 3000.0
