"""A load written as one number and one SI symbol (``"100.37 kPa"``) is converted without the
bound checks' regular expressions (``units._plain_si``, issue 36): every text it takes meets
those bounds, and ``to_si`` gives what its checked path gives, the same float bit for bit or
the same error."""

from __future__ import annotations

from unittest import mock

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from xpersson import units
from xpersson.units import UnitError, _plain_si, _simple_si, check_expression, to_si

PIECES = st.sampled_from(
    ["1", "0", "-", "+", ".", "e", "E", "5", "37", " ", "kPa", "Pa", "MPa", "m", "um", "*", "/"]
    + ["^2", "**", "(", ")", "1/m", "µm", "x", "\t"]
    # unicode digits and spaces, NaN/inf words, overflowing exponents, second numbers
    + ["\u0663", "\uff11", "\u00b2", "\u2003", "\u00a0", "\x1c", "nan", "inf", "e999", "e-400"]
    + ["1" * 120, "μm", "Mpa", "2 3", "1.2.3", "e+", "\n"]
)
#: texts near a plain load: unicode digits and spaces (``\d``, ``\s``), a second decimal point,
#: exponents of any size, prefixes that are none, a power, a second number after the unit
NEAR = st.from_regex(
    r"\s{0,2}[-+]?\d{0,3}(\.\d{0,2})?(\.\d)?([eE][-+]?\d{1,3})?\s{0,2}(k|M|u|µ|μ|e|x)?"
    r"(Pa|m|s|pa|N)(\*\*2|\^2|/m|2)?(\s{0,2}\d)?\s{0,2}",
    fullmatch=True,
)
TEXTS = st.one_of(st.lists(PIECES, min_size=1, max_size=8).map("".join), NEAR)


@settings(max_examples=300, deadline=None)
@given(TEXTS, st.sampled_from(["Pa", "m"]))
def test_a_plain_text_meets_every_bound_and_converts_as_the_checked_path(text, unit):
    got = _plain_si(text, unit)
    if got is None:
        return
    check_expression(text.strip(), "load.p0")  # raises if a bound were broken
    want = _simple_si(text, unit)
    assert want is not None
    assert np.float64(got).tobytes() == np.float64(want).tobytes()


def _outcome(text: str, unit: str) -> tuple[str, object]:
    """``to_si``'s float bits, or its error's type and message."""
    try:
        return "value", np.float64(to_si(text, unit, "load.p0")).tobytes()
    except (UnitError, ArithmeticError) as exc:
        return type(exc).__name__, str(exc)


@settings(max_examples=300, deadline=None)
@given(TEXTS, st.sampled_from(["Pa", "m"]))
@example("1e999 Pa", "Pa")
@example("\u0663 kPa", "Pa")
@example("\u2003-0 Pa\u2003", "Pa")
@example(" " * 150 + "1 Pa" + " " * 60, "Pa")
def test_to_si_with_the_shortcut_is_to_si_without_it(text, unit):
    """Any text, shortcut or not: the same float or the same error as the checked path
    (``check_expression``, then the simple-SI or pint conversion)."""
    fast = _outcome(text, unit)
    with mock.patch.object(units, "_plain_si", lambda value, unit: None):
        checked = _outcome(text, unit)
    assert fast == checked, text


def test_to_si_takes_the_shortcut_for_loads_as_users_write_them():
    """The texts of loads reach no bound check (the regular expressions of
    ``check_expression``) and no pint: a ``to_si`` that called either would fail here."""
    boom = mock.Mock(side_effect=AssertionError("the checked path was taken"))
    with (
        mock.patch.object(units, "check_expression", boom),
        mock.patch.object(units, "_to_si", boom),
    ):
        assert to_si("100.37 kPa", "Pa", "load.p0") == 100370.0
        assert to_si(" 5e3 Pa ", "Pa", "load.p0") == 5000.0
        assert to_si("2 um", "m", "spectrum.h_rms") == 2e-6
        with pytest.raises(AssertionError, match="checked path"):
            to_si("1 N/m**2", "Pa", "load.p0")  # not one symbol: the checked path
    assert boom.call_count == 1


def test_loads_as_users_write_them_take_the_plain_path():
    assert _plain_si("100.37 kPa", "Pa") == 100370.0
    assert _plain_si(" 5e3 Pa ", "Pa") == 5000.0
    assert _plain_si("-0 Pa", "Pa") == 0.0 and str(_plain_si("-0 Pa", "Pa")) == "0.0"
    for other in ("1.2.3 Pa", "2 3 Pa", "1 N/m**2", "1 m", "1e3"):
        assert _plain_si(other, "Pa") is None  # the general path (its messages, pint)
