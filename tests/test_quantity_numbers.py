"""A quantity string holds one number (issue 36): pint reads ``"2 Pa 3"`` or ``"1.2 .3 Pa"``
as a product of its numbers (6 Pa, 0.36 Pa); such strings are refused wherever the scene
parses a quantity, naming the parameter, the entry, the unit and the range, while every valid
format (exponents in units, prefixes, scientific notation, a sign) parses as pint reads it."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from xpersson.errors import UnitError
from xpersson.scene import SceneError
from xpersson.scene._convert import convert_param, loads
from xpersson.scene._core import CORE
from xpersson.units import check_expression, to_si, ureg

POSITIVE = st.floats(1e-6, 1e12, allow_nan=False, allow_infinity=False)
NUMBER_FORMATS = ["{!r}", "{:.17g}", "{:.3e}", "{:.6E}", "{:.0f}", "{:g}", "{:.2f}"]
#: two numbers ``a``, ``b`` and a unit ``u`` in one text: juxtaposed, multiplied, divided
TWO_NUMBERS = [
    "{a} {b} {u}",
    "{a} {u} {b}",
    "{a}*{b} {u}",
    "{a} * {b} {u}",
    "{a} {u}*{b}",
    "{a}/{b} {u}",
    "{a} {u}/{b}",
    "  {a}   {b}   {u}  ",
    "{a}\t{b} {u}",
]
PASCALS = ["Pa", "kPa", "MPa", "GPa", "N/m**2", "N/m^2", "N*m**-2"]


def _number(x: float, fmt: str, dot: bool) -> str:
    """``x`` as ``fmt`` writes it; ``dot``: without its leading ``0`` (``".3"``)."""
    text = fmt.replace("{!r}", "{}").format(x) if fmt == "{!r}" else fmt.format(x)
    return text[1:] if dot and text.startswith("0.") else text


@settings(max_examples=80, deadline=None)
@given(
    POSITIVE,
    POSITIVE,
    st.sampled_from(NUMBER_FORMATS),
    st.sampled_from(NUMBER_FORMATS),
    st.booleans(),
    st.sampled_from(["", "-", "+"]),
    st.sampled_from(TWO_NUMBERS),
    st.sampled_from(PASCALS),
)
def test_a_string_of_two_numbers_and_a_unit_is_always_refused(a, b, fa, fb, dot, sign, form, u):
    """Any two numbers with a pressure unit, however placed: refused by ``to_si`` and by the
    scene (one value, and one entry of a list of loads), naming the entry, unit and range."""
    text = form.format(a=_number(a, fa, False), b=sign + _number(b, fb, dot), u=u)
    with pytest.raises(UnitError, match=r"^material\.E: .* holds 2 numbers"):
        to_si(text, "Pa", "material.E")
    with pytest.raises(SceneError, match=r"^material\.E: .* numbers.*range \(0, 1e\+13\] Pa$"):
        convert_param(CORE["material"]["E"], text, "material.E")
    values = [f"{x!r} Pa" for x in np.geomspace(1e3, 1e6, 40).tolist()]
    values[17] = text
    with pytest.raises(SceneError, match=r"^load\.p0\[17\]: .* holds 2 numbers.*1e\+13\] Pa$"):
        loads(values)


@pytest.mark.parametrize(
    ("text", "product"),
    [("2 Pa 3", 6.0), ("1.2 .3 Pa", 0.36), ("2 3 Pa", 6.0), ("1/2 Pa", 0.5), ("3 Pa/2", 1.5)],
)
def test_pint_would_combine_the_numbers(text, product):
    """What the refusal prevents: pint's silent reading of the numbers as one product."""
    assert float(ureg().Quantity(text).to("Pa").magnitude) == pytest.approx(product)
    with pytest.raises(SceneError, match=r"^load\.p0: .* holds 2 numbers"):
        loads(text)


#: (unit text, SI unit): exponents, per-units with their ``1``, prefixes
VALID_UNITS = [
    ("Pa", "Pa"),
    ("kPa", "Pa"),
    ("MPa", "Pa"),
    ("N/m**2", "Pa"),
    ("N/m^2", "Pa"),
    ("N*m**-2", "Pa"),
    ("1/m", "1/m"),
    ("1/um", "1/m"),
    ("1 / nm", "1/m"),
    ("m^-1", "1/m"),
    ("m**-1", "1/m"),
    ("1/(m*s)", "1/m/s"),
    ("um**2", "m**2"),
    ("m**4", "m**4"),
    ("J/m**2", "J/m**2"),
    ("kg*m/s**2", "N"),
    ("m**(1/2)", "m**0.5"),
]


@settings(max_examples=100, deadline=None)
@given(
    POSITIVE,
    st.sampled_from(NUMBER_FORMATS + ["{:+.5e}"]),
    st.sampled_from(["", "-", "+"]),
    st.sampled_from(VALID_UNITS),
    st.sampled_from(["{} {}", "{}{}", "  {}  {}  "]),
)
def test_every_valid_format_parses_as_pint_reads_it_bit_for_bit(x, fmt, sign, units, space):
    """One number (sign, scientific notation in e/E) and a unit with exponents, prefixes or
    a per-unit ``1``: accepted, and the float is pint's, bit for bit."""
    unit, si = units
    number = _number(x, fmt, False)
    number = number if number[0] in "+-" else sign + number
    if space == "{}{}" and unit[0].isdigit():
        return  # "51/m" is the number 51 per metre: another quantity, tested elsewhere
    text = space.format(number, unit)
    check_expression(text.strip(), "x")
    want = float(ureg().Quantity(text.strip()).to(si).magnitude)
    got = to_si(text, si, "x")
    assert got == want  # "-0 Pa": -0.0 by float() (as before), 0.0 by pint: equal, not bitwise
    if want != 0.0:
        assert np.float64(got).view(np.int64) == np.float64(want).view(np.int64)
