"""A scene section of plain values is converted once per process (``scene.sections``, issue 36:
one cache look-up instead of one per value): the same dict as ``convert_params`` gives, errors
raised every time, ``True`` and ``1`` kept apart, and the same with the caches off."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import xpersson
from xpersson.cache import cache
from xpersson.scene import SceneError
from xpersson.scene._convert import convert_params
from xpersson.scene._sections import convert_section
from xpersson.specs import ParamSpec

SPECS = {
    "p": ParamSpec(unit="Pa", bounds=(0.0, None), inclusive=(False, True)),
    "n": ParamSpec(unit="1", kind="int", default=3, bounds=(1, 10)),
    "flag": ParamSpec(unit="1", kind="bool", default=False),
    "x": ParamSpec(unit="1", default=0.5, bounds=(0.0, 1.0)),
}
VALUES = st.fixed_dictionaries(
    {"p": st.sampled_from(["1 kPa", "2.5 MPa", "3.0 Pa", "7 Pa", "1e-3 GPa"])},
    optional={
        "n": st.integers(1, 10),
        "flag": st.booleans(),
        "x": st.floats(0.0, 1.0, allow_nan=False),
    },
)


@settings(max_examples=60, deadline=None)
@given(raw=VALUES, off=st.booleans())
def test_a_section_converts_as_convert_params(raw, off):
    with xpersson.set_options(cache=not off):
        for _ in range(2):  # a first and a kept conversion
            got = convert_section(SPECS, raw, "sec")
            want = convert_params(SPECS, raw, "sec")
            assert got == want and list(got) == list(want)
            assert all(type(got[k]) is type(want[k]) for k in want)


def test_errors_are_raised_every_time_and_true_is_not_one():
    """``flag = 1`` is refused after ``flag = true`` was converted (equal as dict keys);
    an out-of-range value raises its message on every call (never kept)."""
    cache("scene.sections").clear()
    assert convert_section(SPECS, {"p": "1 kPa", "flag": True}, "sec")["flag"] is True
    with pytest.raises(SceneError, match="sec.flag: expected true or false, got 1"):
        convert_section(SPECS, {"p": "1 kPa", "flag": 1}, "sec")
    for _ in range(2):
        with pytest.raises(SceneError, match="sec.x: 2 .* outside the allowed range"):
            convert_section(SPECS, {"p": "1 kPa", "x": 2.0}, "sec")
    defaults = convert_section(SPECS, {"p": "1 kPa", "n": 4}, "sec")
    assert defaults["flag"] is SPECS["flag"].default and defaults["x"] == 0.5
