"""A load written as one number and one SI symbol (``"100.37 kPa"``) is converted without the
bound checks' regular expressions (``units._plain_si``, issue 36): every text it takes meets
those bounds, and it gives the float of the checked path, bit for bit."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from xpersson.units import _plain_si, _simple_si, check_expression

PIECES = st.sampled_from(
    ["1", "0", "-", "+", ".", "e", "E", "5", "37", " ", "kPa", "Pa", "MPa", "m", "um", "*", "/"]
    + ["^2", "**", "(", ")", "1/m", "µm", "x", "\t"]
)


@settings(max_examples=300, deadline=None)
@given(st.lists(PIECES, min_size=1, max_size=8).map("".join), st.sampled_from(["Pa", "m"]))
def test_a_plain_text_meets_every_bound_and_converts_as_the_checked_path(text, unit):
    got = _plain_si(text, unit)
    if got is None:
        return
    check_expression(text.strip(), "load.p0")  # raises if a bound were broken
    want = _simple_si(text, unit)
    assert want is not None
    assert np.float64(got).tobytes() == np.float64(want).tobytes()


def test_loads_as_users_write_them_take_the_plain_path():
    assert _plain_si("100.37 kPa", "Pa") == 100370.0
    assert _plain_si(" 5e3 Pa ", "Pa") == 5000.0
    assert _plain_si("-0 Pa", "Pa") == 0.0 and str(_plain_si("-0 Pa", "Pa")) == "0.0"
    for other in ("1.2.3 Pa", "2 3 Pa", "1 N/m**2", "1 m", "1e3"):
        assert _plain_si(other, "Pa") is None  # the general path (its messages, pint)
