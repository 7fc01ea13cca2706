"""Levels of one time plan marched together (``_moving._march_levels``, used by ``cn`` for one
load) and the per-thread scratch buffers of the march (``_scratch``)."""

from __future__ import annotations

import numpy as np
import pytest

from xpersson.engine import Wall, _cn, _moving, _scratch, solve

TAU = np.logspace(-3, 0, 7)
KEYS = ("area", "abs_l", "abs_u", "load", "mom_l", "mom_u")


def _captured(monkeypatch, lower, upper=None, **kw):
    """(pbs, plan, grids, args) of every joint march of a solve, and the solve's result."""
    seen = []
    orig = _cn._march_levels

    def spy(pbs, plan, grids, *args):
        seen.append((pbs, plan, list(grids), args))
        return orig(pbs, plan, grids, *args)

    monkeypatch.setattr(_cn, "_march_levels", spy)
    res = solve(TAU, 0.5, lower, upper, method="cn", **kw)
    return seen, res


@pytest.mark.parametrize(
    "walls",
    [
        (Wall.absorbing(lambda t: -(0.2 + t)), None),  # the exact moving wall
        (Wall.absorbing(0.0), Wall.yield_closure(lambda t: 0.6 + 2 * t, lambda t: 2 + 0 * t)),
    ],
    ids=["moving", "yield"],
)
def test_levels_marched_together_equal_each_marched_alone(monkeypatch, walls):
    """Bit for bit: the systems do not couple (identity rows between them), and every level
    sees the same operations as in its own march (outputs, wall sums, steps)."""
    seen, res = _captured(monkeypatch, *walls, rtol=1e-6)
    assert res.status == "success" and seen
    for pbs, plan, grids, args in seen:
        grids = grids + [(n_ // m * 3, 3) for n_, m in grids[:1] if m == 1]  # a third level
        together = _moving._march_levels(pbs, plan, grids, *args)
        for (n, m), out in zip(grids, together, strict=True):
            alone = _moving._march(pbs, plan, n, m, *args)
            assert out["nsteps"] == alone["nsteps"] and out["n_nodes"] == n + 1
            for key in KEYS:
                np.testing.assert_array_equal(out[key], alone[key], err_msg=key)


def test_steps_counted_before_the_march_are_the_steps_taken(monkeypatch):
    """The budgets are checked per level before a joint march, with the steps each level will
    take: the count equals the sum over the levels marched (also when a budget ends it)."""
    wall = Wall.absorbing(lambda t: -(0.2 + 5 * t))
    for opts in ({}, {"levels": 3}, {"max_work": 2e4}):
        grids = {}
        orig = _cn._Grids._march

        def spy(self, todo, orig=orig, grids=grids):
            orig(self, todo)
            grids["lv"] = self

        monkeypatch.setattr(_cn._Grids, "_march", spy)
        res = solve(TAU, 0.5, wall, method="cn", rtol=1e-8, options=opts)
        lv = grids["lv"]
        assert lv.nsteps == sum(r["nsteps"] for r in lv.cache.values()) == res.nsteps
        assert (res.status == "success") == (opts == {})


def test_scratch_pool_reuses_its_buffers_and_is_not_shared_when_busy():
    with _scratch.pool() as p:
        a = p.empty("x", (3, 4))
        a[...] = 1.0
        b = p.empty("x", (2, 2))  # the same memory, asked again
        assert np.shares_memory(a, b) and b.shape == (2, 2)
        with _scratch.pool() as q:  # nested (a reporter that solves): fresh memory
            c = q.empty("x", (3, 4))
            assert not np.shares_memory(a, c)
    with _scratch.pool() as p2:
        assert p2 is p and np.shares_memory(p2.empty("x", (3, 4)), a)
        big = p2.empty("x", (10, 10))  # grown
        assert big.shape == (10, 10) and big.base.size >= 100
