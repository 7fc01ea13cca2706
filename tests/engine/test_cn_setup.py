"""The per-level and per-solve set-up of ``cn`` on the compiled path (issue 36): the level
times of :func:`xpersson.engine._cn_edges.level_times` and the batch start time equal the
numpy path's bit for bit."""

from __future__ import annotations

import numpy as np
import pytest
from test_march_reference import CASES, TAU

from xpersson.engine import _compiled
from xpersson.engine._api import make_problem
from xpersson.engine._cn_edges import level_times
from xpersson.engine._cn_plan import _first_start, _level_times, _start_time
from xpersson.engine._walls import Wall


def _bases(seed: int):
    rng = np.random.default_rng(seed)
    yield np.array([3.0]), 4, 2  # one time: no step (the Rannacher halves cut to none)
    yield np.array([1.0, 2.0]), 1, 5  # fewer steps than halves asked for
    for _ in range(60):
        n = int(rng.integers(1, 40))
        base = np.unique(rng.uniform(0.0, 1.0, n + 1) * 10 ** rng.uniform(-3, 8) + 1.0)
        yield base, int(rng.integers(1, 9)), int(rng.integers(0, 4))


@pytest.mark.parametrize("seed", [0, 1])
def test_level_times_loop_is_numpy_bitwise(seed):
    """The loop (here as plain Python; compiled below) subdivides and halves as numpy does."""
    for base, nsub, n_ie in _bases(seed):
        t, theta = _level_times(base, nsub, n_ie)
        got = _level_times(base, nsub, n_ie, (), level_times)
        np.testing.assert_array_equal(got[0], t)
        np.testing.assert_array_equal(got[1], theta)
        assert got[0].size == theta.size + 1 and (np.diff(t) > 0).all()


def test_compiled_level_times_are_numpy_bitwise_and_zones_stay_numpy(compiled_on):
    assert _compiled.build() and _compiled.built("times") is not None
    fast = _compiled.built("times")
    for base, nsub, n_ie in _bases(2):
        want, got = _level_times(base, nsub, n_ie), _level_times(base, nsub, n_ie, (), fast)
        np.testing.assert_array_equal(got[0], want[0])
        np.testing.assert_array_equal(got[1], want[1])
    # a graded zone: the numpy path whatever is given (its pow is not recompiled)
    base, zones = np.linspace(1.0, 3.0, 9), ((1.5, 2.5),)
    want = _level_times(base, 4, 2, zones)
    got = _level_times(base, 4, 2, zones, lambda *a: pytest.fail("the loop ran in a zone"))
    np.testing.assert_array_equal(got[0], want[0])


@pytest.mark.parametrize("name", ["two walls, batch", "yield closure, batch", "fixed upper"])
def test_batch_start_time_is_the_smallest_load_start(name):
    """One evaluation of the shared walls gives each load's own start time (as a lone load
    computes it), and the batch starts at the smallest."""
    lower, upper, p0 = CASES[name]
    pb = make_problem(TAU, np.array(p0), lower, upper, 1e-6, None, None, 10**6, {}, batch=True)
    loads = [pb.load(i) for i in range(len(p0))]
    alone = [_start_time([p], 3.0) for p in loads]
    assert _start_time(loads, 3.0) == min(alone)
    for p, want in zip(loads, alone, strict=True):  # the lone load's own scan, by hand
        cand = p.tau_max * np.logspace(-18, 0, 721)
        lo, up = p.wall_positions(cand)
        s = np.sqrt(2.0 * cand)
        assert _first_start(p.p0, cand, 3.0 * s, lo, up, p.tau_max, True) == want
        # no upper wall (None) is the same scan as an upper wall at +inf
        inf = np.full(lo.shape, np.inf)
        args = (p.p0, cand, 3.0 * s, lo)
        assert _first_start(*args, None, p.tau_max, True) == _first_start(
            *args, inf, p.tau_max, True
        )


def test_batch_start_time_with_walls_not_shared():
    """Loads whose walls differ (not one batch's): each scanned with its own walls."""
    a = make_problem(TAU, 1.0, Wall.absorbing(0.5), None, 1e-6, None, None, 10**6, {})
    b = make_problem(TAU, 1.0, Wall.absorbing(0.0), None, 1e-6, None, None, 10**6, {})
    assert _start_time([a, b], 3.0) == min(_start_time([a], 3.0), _start_time([b], 3.0))
    assert _start_time([a], 3.0) < _start_time([b], 3.0)  # (the nearer wall enters sooner)


def test_compiled_level_times_with_zones_that_grade_no_substep_are_numpy_bitwise(compiled_on):
    """The loop also runs where a zone subdivides no step (one substep per step, or no step
    inside it): only the zones' implicit-Euler steps are patched in, the numpy path's
    numbers; a zone that grades substeps still takes the numpy path."""
    assert _compiled.build()
    fast = _compiled.built("times")
    rng = np.random.default_rng(3)
    ran = []

    def loop(*args):
        ran.append(True)
        fast(*args)

    for base, nsub, n_ie in _bases(3):
        i, j = sorted(rng.integers(0, base.size, 2).tolist())
        zones = ((float(base[i]), float(base[j])),)  # (j = i: a zone without a step)
        ran.clear()
        want, got = (
            _level_times(base, nsub, n_ie, zones),
            _level_times(base, nsub, n_ie, zones, loop),
        )
        np.testing.assert_array_equal(got[0], want[0])
        np.testing.assert_array_equal(got[1], want[1])
        assert bool(ran) == (nsub == 1 or i == j or base.size == 1)


def test_decades_and_sorted_unique_are_numpy_bitwise():
    """The plans' helpers give numpy's logspace and unique bit for bit."""
    from xpersson.engine._grid import decades, sorted_unique

    rng = np.random.default_rng(4)
    for _ in range(200):
        stop, n = float(rng.uniform(0.0, 20.0)), int(rng.integers(2, 800))
        assert decades(stop, n).tobytes() == np.logspace(0.0, stop, n).tobytes()
        x = rng.random(int(rng.integers(0, 60))) * 10 ** rng.uniform(-3, 12)
        x = np.concatenate([x, x[: int(rng.integers(0, x.size + 1))]])
        assert sorted_unique(x.copy()).tobytes() == np.unique(x).tobytes()
