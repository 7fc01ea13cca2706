"""The ``cn`` path's honesty on onset walls and at the end of the march (issue 36).

* A wall whose position is defined only up to the last output (clipped there, as the ``jkr``
  wall's clock is at ``zeta_max``) gives the answer of the same wall unclipped: the speed at
  the last time is a backward difference (a central one halved it, and the last output
  converged at first order).
* A wall at rest up to its onset (``still_until``): the outputs up to the onset are the
  one-wall closed form, and the march from there gives the answer of the march from the
  start.
* Seeded square-root onsets: the reported error estimate bounds the error against a
  tight-tolerance solve, worst case over the seeds.
"""

from __future__ import annotations

import numpy as np
import pytest

from xpersson.engine import Wall, exact, solve

P0 = 0.5
TAU = np.geomspace(1e-3, 1.0, 13)


def _onset(tb: float, c: float):
    """Wall at 0 until ``tb``, then ``-c sqrt(tau - tb)`` [Pa] (picklable closure not needed)."""

    def pos(t):
        return -c * np.sqrt(np.maximum(np.asarray(t, float) - tb, 0.0))

    return pos


def test_a_wall_clipped_at_the_last_output_equals_the_unclipped_wall():
    """Moving wall -0.2 - 0.3 tau, clipped past tau = 1 (the last output): the last output is
    the unclipped wall's (before the fix it erred ~1e-3 on this grid and missed rtol)."""
    free = Wall.absorbing(lambda t: -0.2 - 0.3 * np.asarray(t, float) ** 1.5)
    clipped = Wall.absorbing(lambda t: -0.2 - 0.3 * np.minimum(np.asarray(t, float), 1.0) ** 1.5)
    ref = solve(TAU, P0, free, method="cn", rtol=1e-8, atol=1e-12)
    res = solve(TAU, P0, clipped, method="cn", rtol=1e-5, atol=1e-12)
    assert res.status == "success" and ref.status == "success"
    err = np.abs(res.area - ref.area) - ref.error_estimate
    assert np.all(err <= 1e-5 * res.area + 1e-12)
    assert np.all(err <= np.maximum(res.error_estimate, 1e-13))


def test_still_wall_starts_from_the_closed_form_and_equals_the_full_march():
    tb = 0.05
    pos = _onset(tb, 0.4)
    still = Wall.absorbing(pos, breakpoints=[tb], still_until=tb)
    marched = Wall.absorbing(pos, breakpoints=[tb])
    a = solve(TAU, P0, still, method="cn", rtol=1e-7)
    b = solve(TAU, P0, marched, method="cn", rtol=1e-7)
    assert a.status == "success" and b.status == "success"
    before = TAU <= tb
    area, non, load = exact.one_wall(TAU[before], P0, 0.0)
    np.testing.assert_array_equal(a.area[before], area)
    np.testing.assert_allclose(a.absorbed_lower[before], non, rtol=0, atol=0)
    np.testing.assert_allclose(a.load[before], load, rtol=0, atol=0)
    # after the onset: the two agree within their tolerances; probability balance holds
    np.testing.assert_allclose(a.area, b.area, rtol=2e-7, atol=1e-12)
    np.testing.assert_allclose(a.area + a.absorbed_lower, 1.0, rtol=0, atol=1e-9)
    assert a.nsteps < b.nsteps  # the fixed-wall stretch is not marched


def test_still_until_is_checked():
    with pytest.raises(ValueError, match="still_until"):
        Wall.absorbing(_onset(0.1, 1.0), breakpoints=[0.1], still_until=-1.0)


@pytest.mark.parametrize("seed", range(4))
def test_error_estimate_bounds_the_error_after_a_square_root_onset(seed):
    """Seeded onset times and speeds (wall at rest until the onset): the error against a
    rtol 1e-8 solve is within the reported estimate (worst case over outputs) and within
    the tolerance."""
    rng = np.random.default_rng(seed)
    tb = float(10 ** rng.uniform(-2.5, -0.5))
    c = float(rng.uniform(0.2, 2.0))
    wall = Wall.absorbing(_onset(tb, c), breakpoints=[tb], still_until=tb)
    ref = solve(TAU, P0, wall, method="cn", rtol=1e-8, atol=1e-12)
    res = solve(TAU, P0, wall, method="cn", rtol=1e-5, atol=1e-12)
    assert res.status == "success" and ref.status == "success"
    err = np.abs(res.area - ref.area) - ref.error_estimate  # the reference's own error off
    tol = 1e-5 * np.abs(res.area) + 1e-12
    assert np.all(err <= tol)
    assert np.max(err / np.maximum(res.error_estimate, 1e-300)) <= 1.0


def test_one_wall_start_compiled_equals_numpy(monkeypatch, compiled_on):
    """The march from a one-wall start: the compiled kernel gives the numpy path's answer."""
    import xpersson
    from xpersson.engine import _compiled

    wall = Wall.absorbing(_onset(0.05, 0.4), breakpoints=[0.05], still_until=0.05)
    with xpersson.set_options(compiled=False):
        ref = solve(TAU, P0, wall, method="cn", rtol=1e-6)
    monkeypatch.setattr(_compiled, "MIN_WORK", 0)
    assert _compiled.kernel(1.0) is not None
    got = solve(TAU, P0, wall, method="cn", rtol=1e-6)
    for key in ("area", "absorbed_lower", "load"):
        want, have = getattr(ref, key), getattr(got, key)
        assert np.max(np.abs(have - want)) <= 1e-12 * np.max(np.abs(want)), key
    # the estimate is a difference of areas (of order 1): rounding on their scale
    diff = np.abs(got.error_estimate - ref.error_estimate)
    assert np.max(diff) <= 1e-12 * np.max(np.abs(ref.area))
