"""Properties of the jkr wall over generated inputs (hypothesis), on the engine's exact path."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.special import erf, erfc

from xpersson.engine import solve
from xpersson.plugins import DiffusionClock
from xpersson_adhesion import JKRBoundary


def _clock(tau_max: float) -> DiffusionClock:
    return DiffusionClock(
        lambda z: tau_max * (np.asarray(z, float) - 1.0) / 99.0,
        lambda z: np.full(np.shape(z), tau_max / 99.0),
        100.0,
    )


@given(
    sigma=st.floats(1e-3, 1e3),
    frac=st.floats(-0.999, 10.0),
    tau_max=st.floats(1e-4, 1e4),
)
@settings(max_examples=40, deadline=None)
def test_constant_table_wall_is_the_image_solution(sigma, frac, tau_max):
    p0 = frac * sigma
    clock = _clock(tau_max)
    wall = JKRBoundary(work_of_adhesion=0.0, sigma_a=np.array([sigma])).wall(None, clock)
    tau = tau_max * np.array([1e-3, 0.1, 1.0])
    res = solve(tau, p0, wall)
    x = (p0 + sigma) / (2.0 * np.sqrt(tau))
    np.testing.assert_allclose(res.area, erf(x), rtol=1e-12, atol=1e-300)
    np.testing.assert_allclose(res.non_area, erfc(x), rtol=1e-12, atol=1e-300)
    np.testing.assert_allclose(res.load, p0 + sigma * erfc(x), rtol=1e-10, atol=1e-12 * sigma)
    assert np.all(np.diff(res.area) <= 0)  # contact only detaches


@given(s0=st.floats(0.0, 10.0), c=st.floats(1e-3, 10.0), p0=st.floats(0.05, 5.0))
@settings(max_examples=40, deadline=None)
def test_table_affine_in_tau_is_the_linear_wall(s0, c, p0):
    tau_max = 2.0
    clock = _clock(tau_max)
    zeta = np.linspace(1.0, 100.0, 12)
    sigma = s0 + c * np.asarray(clock.tau_of_zeta(zeta))
    wall = JKRBoundary(work_of_adhesion=0.0, sigma_a=sigma, sigma_a_zeta=zeta).wall(None, clock)
    assert wall.linear_motion(tau_max) is not None
    np.testing.assert_allclose(wall.linear_motion(tau_max), (-s0, -c), rtol=1e-12, atol=1e-12)


def test_instance_pickles_after_building_its_wall():
    import pickle

    inst = JKRBoundary(
        work_of_adhesion=0.0, sigma_a=np.array([1.0, 2.0]), sigma_a_zeta=np.array([1.0, 100.0])
    )
    clock = _clock(1.0)  # holds lambdas: the cached wall must not travel with the instance
    inst.wall(None, clock)
    assert pickle.loads(pickle.dumps(inst)) == inst
