"""The exact path's pre-check of a moving wall (issue 36): three of the linear probe's times
reject a bent wall before the 257-point probe, and never a wall the probe would accept."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from xpersson.engine import Wall
from xpersson.engine._exactpath import _bent


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
