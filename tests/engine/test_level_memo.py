"""The per-level shortcuts of ``cn`` (memoised node sets and Richardson weights, each wall
evaluated once per level) give the numbers of the direct computations, bit for bit."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from xpersson.engine import Wall
from xpersson.engine import _cn_control as ctl
from xpersson.engine._cn_plan import _faces, _probe_times, _track_wall, _wall_speeds
from xpersson.engine._grid import clustered
from xpersson.engine._level import level_nodes
from xpersson.options import cache_enabled


@pytest.mark.parametrize("n, stretch", [(24, 1.0), (97, 1.0), (10, 0.0)])
def test_memoised_nodes_equal_fresh_ones_and_are_read_only(n, stretch):
    x, xf, dxf, w = level_nodes(n, stretch)
    fresh = (clustered(n, stretch), *_faces(clustered(n, stretch)))
    for got, want in zip((x, xf, dxf, w), fresh, strict=True):
        np.testing.assert_array_equal(got, want)
        assert not got.flags.writeable  # read-only with the caches on and off
    assert (level_nodes(n, stretch).x is x) == cache_enabled()  # memoised (caches on)


def test_memoised_richardson_weights_are_a_private_copy():
    w = ctl.richardson_weights((1, 2, 3))
    w[:] = 0.0  # the caller's copy: the memo is not changed
    np.testing.assert_allclose(ctl.richardson_weights([1, 2, 3]), [1 / 24, -16 / 15, 81 / 40])


def _walls():
    moving = Wall.absorbing(lambda t: -(0.2 + np.sqrt(t)))
    kinked = Wall.absorbing(lambda t: -(0.2 + np.maximum(t - 0.3, 0.0) ** 1.5))
    return [
        moving,
        kinked.with_breakpoints([0.3]),
        Wall.absorbing(0.0),
        Wall.yield_closure(lambda t: 0.6 + 2 * t, lambda t: 2 + 0 * t),
        None,
    ]


@pytest.mark.parametrize("wall", _walls(), ids=["sqrt", "breakpoint", "fixed", "yield", "none"])
def test_one_call_of_a_wall_per_level_equals_separate_calls(wall):
    """Positions at the step midpoints and times, and the speeds just before / after each time
    (central differences, one-sided at breakpoints), from one call of the wall."""
    taus = np.concatenate([np.linspace(0.01, 0.3, 7), np.linspace(0.3, 2.0, 9)[1:]])
    mid = 0.5 * (taus[:-1] + taus[1:])
    calls = []
    if wall is not None and not wall.is_fixed:
        f = wall.position
        wall = dataclasses.replace(wall, position=lambda t: calls.append(1) or f(t))
    p_m, p_t, vb, va = _track_wall(wall, mid, taus)
    if wall is None:
        assert np.all(np.isinf(p_m)) and np.all(np.isinf(p_t)) and not vb.any() and not va.any()
        return
    n_calls = len(calls)
    np.testing.assert_array_equal(p_m, wall.at(mid))
    np.testing.assert_array_equal(p_t, wall.at(taus))
    want_b, want_a = _wall_speeds(wall, taus)
    np.testing.assert_array_equal(vb, want_b)
    np.testing.assert_array_equal(va, want_a)
    if not wall.is_fixed:
        assert n_calls == 1  # the probes (and the positions at breakpoints) ride along
        if wall.breakpoints:
            assert not np.array_equal(want_b, want_a)  # one-sided at the breakpoint
    if wall.dposition is not None:
        assert _probe_times(wall, taus) is None
