"""A yield wall released from the ``cn`` window once it has left it (``_Plan.release``, set
by :func:`xpersson.engine._cn_control._release`): the window's regimes (numpy and the
compiled loop's Python source, bit for bit) and the solve's answer against the wall kept."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from xpersson.engine import Wall, solve_batch
from xpersson.engine._cn_edges import window_edges
from xpersson.engine._cn_plan import _edges_batch, _joint_plan, _start_time
from xpersson.engine._problem import make_problem, window_k

TAU = np.logspace(-2.0, 1.0, 13)  # output times [Pa^2]
P0 = (0.7, 1.0)  # loads [Pa]


def _runaway(t):
    """A yield wall [Pa] that grows much faster than the window's ``sqrt(2 tau)``: it enters
    the window of the load 1 Pa (at ``atol`` 1e-12) by 0.8 ``sqrt(2 tau)`` near tau = 0.8
    Pa^2, leaves it at 1.3 Pa^2 and ends 10x beyond its edge."""
    return 7.5 + 3.5 * np.asarray(t, dtype=float) ** 2


def _runaway_speed(t):
    return 7.0 * np.asarray(t, dtype=float)


UPPER = Wall.yield_closure(_runaway, _runaway_speed)


def _window(release: bool, fast) -> object:
    atol = 1e-12
    pb = make_problem(TAU, np.array(P0), Wall.absorbing(0.0), UPPER, atol, None, None, 10**6,
                      {}, batch=True)  # fmt: skip
    pbs = [pb.load(i) for i in range(len(P0))]
    k = window_k(atol)
    plan = _joint_plan(pbs, k, 24.0, _start_time(pbs, k), [])
    plan = dataclasses.replace(plan, release=release)
    return _edges_batch(pbs, plan, plan.base, fast)


@pytest.mark.parametrize("release", [False, True])
def test_window_regimes_numpy_equal_compiled_source(release):
    """The compiled loop's Python source gives the numpy path's window bit for bit, with and
    without the release."""
    ref, got = _window(release, None), _window(release, window_edges)
    np.testing.assert_array_equal(got.real_upper, ref.real_upper)
    for want, have in zip((*ref.start, *ref.end), (*got.start, *got.end), strict=True):
        np.testing.assert_array_equal(have, want)


def test_released_wall_is_real_only_inside_the_window():
    """Kept, the wall stays real from its entry on; released, it is real exactly while it is
    inside the window and the upper edge is the artificial one after it left."""
    kept, released = _window(False, None), _window(True, None)
    for q in range(len(P0)):
        real = kept.real_upper[q]
        first = int(np.argmax(real))
        assert real.any() and real[first:].all()
        rel = released.real_upper[q]
        assert rel[: first + 1].tolist() == real[: first + 1].tolist()
        assert not rel[-1] and rel.sum() < real.sum()  # left the window before the end


def test_release_keeps_the_answer_within_tolerance(monkeypatch):
    """The solve releases the wall (its plastic area, ~5e-13, is negligible) and agrees with
    the march of the wall kept (``RELEASE = 0``) at a tight tolerance to within its own."""
    from xpersson.engine import _cn_control

    released = []
    orig = _cn_control._release

    def spy(lv, judge):
        orig(lv, judge)
        released.append(lv.release)

    monkeypatch.setattr(_cn_control, "_release", spy)
    walls = (Wall.absorbing(0.0), UPPER)
    got = solve_batch(TAU, np.array(P0), walls, rtol=1e-6, atol=1e-12, method="cn")
    assert released == [True] and np.all(np.asarray(got.status) == "success")
    monkeypatch.setattr(_cn_control, "RELEASE", 0.0)
    ref = solve_batch(TAU, np.array(P0), walls, rtol=1e-7, atol=1e-12, method="cn")
    assert released[1:] == [False] and np.all(np.asarray(ref.status) == "success")
    area, a_ref = np.asarray(got.area), np.asarray(ref.area)
    assert np.all(np.abs(area - a_ref) <= 1e-6 * np.abs(a_ref) + 1e-12)
    assert np.all(np.abs(area - a_ref) <= np.asarray(got.error_estimate))
