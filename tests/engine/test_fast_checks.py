"""The engine's one-pass checks (issue 36): the exact path's pre-check of a moving wall (three
of the linear probe's times reject a bent wall before the 257-point probe, and never a wall the
probe would accept) and the output times' validity test (the same verdict as the three checks
it stands for)."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from xpersson.engine import Wall
from xpersson.engine._exactpath import _bent
from xpersson.engine._problem import _valid_times


@settings(max_examples=60, deadline=None)
@given(
    y0=st.floats(-1e6, -1e-3),
    v=st.floats(-1e3, 1e3),
    tau_max=st.floats(1e-3, 1e9),
    bend=st.sampled_from([0.0, 1e-16, 1e-14, 1e-13, 3e-13, 1e-12, 1e-9, 1e-3, 1.0]),
)
def test_a_wall_the_probe_accepts_is_never_called_bent(y0, v, tau_max, bend):
    """Affine walls with a quadratic bend of relative size ``bend``: whenever the full probe
    accepts one as linear, the pre-check lets it through; a large bend is caught by both."""
    scale = max(abs(y0), abs(v) * tau_max)

    def position(t):
        s = np.asarray(t, dtype=float) / tau_max
        return y0 + v * np.asarray(t, dtype=float) + bend * scale * s * (1.0 - s)

    wall = Wall.absorbing(position)
    linear = wall.linear_motion(tau_max) is not None
    if linear:
        assert not _bent(wall, tau_max)
    if bend >= 1e-9:
        assert _bent(wall, tau_max) and not linear


_TIME = st.sampled_from([0.0, -0.0, -1.0, 1e-300, 0.5, 1.0, 2.0, 1e300, np.inf, -np.inf, np.nan])


@settings(max_examples=300, deadline=None)
@given(rows=st.lists(st.lists(_TIME, min_size=1, max_size=5), min_size=1, max_size=3))
def test_the_one_pass_time_check_agrees_with_the_three_checks(rows):
    width = min(len(r) for r in rows)
    tau = np.array([r[:width] for r in rows], dtype=float)
    for t in (tau, tau[0]):
        with np.errstate(invalid="ignore"):
            valid = bool(
                np.all(np.isfinite(t)) and not np.any(t < 0) and not np.any(np.diff(t) <= 0)
            )
        assert _valid_times(t) == valid
