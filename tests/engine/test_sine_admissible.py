"""The ``sine`` series' outputs are admissible probabilities: areas in [0, 1], absorbed
fractions >= 0, densities >= 0, whatever the round-off of the series (``fuzz.py --methods 1
--seed 191``: an area of 1 + 2e-16 near ``zeta = 1`` and densities of -7e-21 1/Pa failed the
core output check, and the solve with them)."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from xpersson.engine import Wall, solve


@settings(max_examples=60, deadline=None)
@given(
    p0=st.floats(1e-3, 1e3),
    lower=st.floats(0.0, 0.999),
    upper=st.one_of(st.none(), st.floats(1.001, 1e3)),
    t0=st.floats(1e-12, 1e-2),
    rtol=st.floats(1e-9, 1e-3),
)
def test_sine_outputs_are_admissible(p0, lower, upper, t0, rtol):
    tau = np.concatenate(([0.0], np.geomspace(t0 * p0 * p0, 10.0 * p0 * p0, 12)))
    up = None if upper is None else Wall.absorbing(upper * p0)
    p_out = np.linspace(lower * p0, (upper or 3.0) * p0, 37)
    r = solve(tau, p0, Wall.absorbing(lower * p0), up, rtol=rtol, method="sine", p_out=p_out)
    assert np.all((r.area >= 0.0) & (r.area <= 1.0))
    assert np.all(r.absorbed_lower >= 0.0) and np.all(r.absorbed_upper >= 0.0)
    assert np.all(r.absorbed_lower + r.absorbed_upper <= 1.0)
    assert np.all(r.P >= 0.0)
    assert np.all(r.error_estimate >= 0.0)
