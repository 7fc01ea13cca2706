"""Lists of quantity strings converted at once (issue 36): the same floats and the same error
messages as value by value."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import xpersson
from xpersson.scene import SceneError
from xpersson.scene._convert import loads
from xpersson.units import strings_to_si, to_si

PREFIXES = ["", "k", "M", "G", "m", "u", "n"]


@settings(max_examples=60, deadline=None)
@given(
    st.lists(
        st.tuples(
            st.floats(1e-3, 1e12, allow_nan=False, allow_infinity=False),
            st.sampled_from(PREFIXES),
            st.sampled_from(["{}{}Pa", "{} {}Pa", "  {}  {}Pa  ", "{} {}N/m**2"]),
        ),
        min_size=1,
        max_size=20,
    )
)
def test_strings_to_si_equals_to_si_of_each(entries):
    values = [form.format(repr(x), pre) for x, pre, form in entries]
    got = strings_to_si(values, "Pa")
    want = [to_si(v, "Pa", "w") for v in values]
    if got is not None:  # None: the caller converts value by value (pint units)
        assert got.tolist() == want  # bit for bit


@pytest.mark.parametrize(
    "values",
    [["1 MPa", "2 m"], ["1 MPa", "nan MPa"], ["1 MPa", "1.2.3 MPa"], ["1 MPa", 2.0], ["1_0 Pa"]],
)
def test_values_it_cannot_read_go_value_by_value(values):
    assert strings_to_si(values, "Pa") is None


@pytest.mark.parametrize(
    ("values", "match"),
    [
        (["1 MPa", "2 m"], r"load\.p0\[1\]: .*dimension"),
        (["1 MPa", "-2 MPa"], r"load\.p0\[1\]: -2e\+06 Pa is outside the allowed range"),
        (["1 MPa", "1e400 MPa"], r"load\.p0\[1\]: must be finite"),
        (["1 MPa", "m**9**9 MPa"], r"load\.p0\[1\]"),
        (["2 MPa", "1 MPa"], r"load\.p0: loads must be strictly increasing"),
    ],
)
def test_bad_load_lists_keep_their_messages(values, match):
    with pytest.raises(SceneError, match=match):
        loads(values)


def test_a_list_of_load_strings_solves_as_value_by_value(monkeypatch):
    """The whole solve from a list of strings equals the value-by-value conversion's."""
    from xpersson.scene import _convert

    listed = [f"{float(p) / 1e3!r} kPa" for p in np.geomspace(1e3, 1e6, 200)]
    spec = {"model": "self_affine", "H": 0.8, "q_L": "1e3 1/m", "q_1": "1e7 1/m", "h_rms": "1 um"}
    data = {"spectrum": spec, "material": {"E": "10 MPa", "nu": 0.5}, "load": {"p0": listed}}
    fast = xpersson.solve(data)
    monkeypatch.setattr(_convert, "strings_to_si", lambda values, unit: None)
    slow = xpersson.solve(data)
    np.testing.assert_array_equal(fast.p0.values, slow.p0.values)
    np.testing.assert_array_equal(fast.area_fraction.values, slow.area_fraction.values)
    assert fast.attrs["xpersson_scene"] == slow.attrs["xpersson_scene"]


@settings(max_examples=60, deadline=None)
@given(
    st.lists(st.floats(1e-3, 1e12, allow_nan=False, allow_infinity=False), min_size=1, max_size=30),
    st.sampled_from(PREFIXES),
    st.sampled_from(["{:r}", "{:.3e}", "{:.0f}", "{:g}"]),
)
def test_one_unit_lists_equal_to_si_of_each(xs, pre, number):
    """A list in one unit (the one-join path of ``strings_to_si``): to_si's floats, bit for bit."""
    values = [f"{number.replace(':r', '!r').format(x)} {pre}Pa" for x in xs]
    got = strings_to_si(values, "Pa")
    assert got is not None
    assert got.tolist() == [to_si(v, "Pa", "w") for v in values]


def test_a_list_in_pascals_is_archived_as_written_and_reproduces_bit_for_bit():
    """Loads listed in Pa are stored as the user wrote them (no 1000 formatted strings); the
    stored scene solves again to the same loads and areas; other units are stored in Pa."""
    import json

    listed = ["1e3 Pa", "2500 Pa", "1.0e4 Pa", "123456.789 Pa"]
    spec = {"model": "self_affine", "H": 0.8, "q_L": "1e3 1/m", "q_1": "1e7 1/m", "h_rms": "1 um"}
    data = {"spectrum": spec, "material": {"E": "10 MPa", "nu": 0.5}, "load": {"p0": listed}}
    ds = xpersson.solve(data)
    stored = json.loads(ds.attrs["xpersson_scene"])
    assert stored["load"]["p0"] == listed
    again = xpersson.solve(stored)
    np.testing.assert_array_equal(again.p0.values, [1e3, 2500.0, 1e4, 123456.789])
    np.testing.assert_array_equal(again.area_fraction.values, ds.area_fraction.values)
    data["load"]["p0"] = ["1 kPa", "2.5 kPa"]
    stored = json.loads(xpersson.solve(data).attrs["xpersson_scene"])
    assert stored["load"]["p0"] == ["1000.0 Pa", "2500.0 Pa"]


def _pint_si(text: str, unit: str) -> float:
    """``text`` in ``unit`` by pint alone (no fast path): the reference of every list parse."""
    from xpersson.units import ureg

    return float(ureg().Quantity(text.strip()).to(unit).magnitude)


NUMBER_FORMATS = ["{!r}", "{:.17g}", "{:.3e}", "{:.6E}", "{:.0f}", "{:g}", "{:+.5e}", "{:.2f}"]
UNITS = [("Pa", ""), ("Pa", "k"), ("Pa", "M"), ("Pa", "G"), ("Pa", "m"), ("N/m**2", "")]
SPACES = ["{} {}", "{}{}", "  {}  {}  ", "{}\t{}"]


@settings(max_examples=150, deadline=None)
@given(
    st.lists(
        st.tuples(
            st.floats(1e-6, 1e12, allow_nan=False, allow_infinity=False),
            st.sampled_from(NUMBER_FORMATS),
            st.sampled_from(UNITS),
            st.sampled_from(SPACES),
        ),
        min_size=1,
        max_size=25,
    ),
    st.booleans(),
)
def test_list_parse_is_pint_value_by_value_bit_for_bit(entries, one_unit):
    """Generated numbers (repr, fixed, exponent in e/E with signs), units with and without
    prefixes and spacings: the list parse equals pint's conversion of each value, bit for bit
    (or the list goes value by value: ``None``); a list in one (prefixed) pascal unit always
    parses at once; the scene's loads are the same floats."""
    if one_unit:
        entries = [(x, fmt, entries[0][2], "{} {}") for x, fmt, _, _ in entries]
    values = [space.format(fmt.format(x), pre + unit) for x, fmt, (unit, pre), space in entries]
    if any(float(fmt.format(x)) == 0.0 for x, fmt, _, _ in entries):
        return  # "0.00 Pa": valid text, but outside load.p0's range (tested elsewhere)
    got = strings_to_si(values, "Pa")
    want = np.array([_pint_si(v, "Pa") for v in values])
    if one_unit and entries[0][2][0] == "Pa":  # (prefixed) pascals in one unit: at once
        assert got is not None
    if got is not None:
        np.testing.assert_array_equal(got.view(np.int64), want.view(np.int64))
    if np.all(np.diff(want) > 0) and want.max() <= 1e13:  # valid loads: the scene's floats
        arr, _ = loads(values)
        np.testing.assert_array_equal(arr.view(np.int64), want.view(np.int64))


@pytest.mark.parametrize(
    "bad",
    ["x Pa", "2 m", "3", "1e400 Pa", "-2 Pa", "2 Pa\n3 Pa", "1e3 Pa**2", "1e3 Pq", "1.2.3 Pa"]
    + ["2 Pa 3", "1.2 .3 Pa"],
)
def test_one_bad_entry_of_a_long_list_is_named_with_the_unit_and_range(bad):
    """One malformed, wrong-dimension, unitless, infinite or negative entry among 1000: one
    error naming the entry, the unit and the allowed range, every time (a cached list parse
    never hides it)."""
    values = [f"{float(p)!r} Pa" for p in np.geomspace(1e3, 1e6, 1000)]
    values[617] = bad
    for _ in range(2):
        with pytest.raises(SceneError, match=r"^load\.p0\[617\]: .*\(0, 1e\+13\] Pa$"):
            loads(values)


def test_a_cached_list_parse_gives_each_caller_its_own_array():
    """The same list parsed twice (the second from ``units.string_lists``): equal floats, and
    the array is the caller's to change (writing into it changes no later parse)."""
    values = [f"{x!r} kPa" for x in np.linspace(1.0, 2.0, 50).tolist()]
    first = strings_to_si(values, "Pa")
    first[:] = -1.0
    again = strings_to_si(list(values), "Pa")
    np.testing.assert_array_equal(again, [to_si(v, "Pa", "w") for v in values])
    assert again.flags.writeable


@pytest.mark.parametrize(("text", "number"), [("1.2.3 Pa", "1.2"), ("1e3.5 kPa", "1e3")])
def test_a_number_with_a_second_decimal_point_is_refused(text, number):
    """pint reads ``"1.2.3 Pa"`` as 1.2 x .3 = 0.36 Pa (two numbers, multiplied): refused,
    naming the number it read and the parameter's range."""
    with pytest.raises(SceneError, match=rf"load\.p0: .*{number!r}.*\(0, 1e\+13\] Pa$"):
        loads(text)


@pytest.mark.parametrize("text", ["-0 Pa", "-0.0 kPa", "-0e3 MPa", "0 Pa", "-0 N/m**2"])
def test_a_zero_is_positive_zero_on_every_path(text):
    """pint reads "-0" as the integer 0 and "-0.0" as -0.0; every path gives +0.0 (a zero
    written into an archive is "0", not "-0"), the list path as the single one."""
    import math

    import pint

    fast = strings_to_si([text, "1 Pa"], "Pa")  # None: pint units, converted one by one
    values = [to_si(text, "Pa", "w"), *([] if fast is None else fast[:1])]
    values.append(to_si(pint.Quantity(-0.0, "Pa"), "Pa", "w"))
    values.extend(to_si([text, "1 hPa"], "Pa", "w", array=True)[:1])
    assert [math.copysign(1.0, v) for v in values] == [1.0] * len(values)
