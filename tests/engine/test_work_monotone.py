"""A looser tolerance never costs more: ``cn``'s node-steps and finest grid do not grow as rtol
loosens, while every run's true error stays within its tolerance and below its own estimate.

Closed forms: a fixed absorbing wall (``erf``) on seeded scenes (3-6 decades of diffusion time,
A/A0 = 0.1 .. 1e-4 at the last output) and the linearly moving wall of
``benchmarks/engine_vs_peers.py``.  ``atol`` is fixed, so that the window (its half-width comes
from ``atol``) and with it the time plan of a grid are the same at every rtol: the node-steps
then differ only by the levels the error control chose.  Before the second-order pair gave way
to the fourth-order triple at ~1.79x growth (``_cn_control.R_MAX_REFINE``), rtol 1e-2 took 2-3x
the node-steps of 1e-3 on fixed walls, and 1e-3 took 6x those of 1e-4 on the moving wall.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.special import erf, erfinv

from xpersson.engine import Wall, _cn, exact, solve

RTOLS = (1e-2, 1e-3, 1e-4)  # loose to tight
ATOL = 1e-10


Scene = tuple[str, np.ndarray, float, Wall, np.ndarray]


def _fixed_scenes(n: int = 4, seed: int = 36) -> list[Scene]:
    """``n`` seeded fixed-wall scenes: (name, tau [Pa^2], p0 [Pa], wall, exact A/A0)."""
    rng = np.random.default_rng(seed)
    out = []
    for k in range(n):
        dec = int(rng.integers(3, 7))
        tau = 10.0 ** rng.uniform(-2.0, 2.0) * np.logspace(-dec, 0.0, 4 * dec + 1)
        target = (0.1, 1e-2, 1e-3, 1e-4)[k % 4]
        p0 = 2.0 * math.sqrt(tau[-1]) * float(erfinv(target))
        out.append((f"fixed {dec}dec A/A0={target:g}", tau, p0, Wall.absorbing(0.0),
                    erf(p0 / (2.0 * np.sqrt(tau)))))  # fmt: skip
    return out


def _moving_scene() -> Scene:
    """The wall ``p_w = -(0.2 Pa + tau / (1 Pa))`` (a callable: the march, not the closed form)."""
    p0, s0, c = 0.5, 0.2, 1.0
    tau = np.logspace(-3.0, 0.0, 13)
    wall = Wall.absorbing(lambda t: -(s0 + c * t))
    return "moving", tau, p0, wall, exact.linear_wall_area(tau, p0, s0, c)


SCENES = [*_fixed_scenes(), _moving_scene()]


@pytest.mark.parametrize("scene", SCENES, ids=[s[0] for s in SCENES])
def test_looser_tolerance_never_costs_more(scene, monkeypatch):
    name, tau, p0, wall, area = scene
    marched: list[int] = []
    orig = _cn._march

    def spy(pbs, plan, n, *args):  # node-steps of every level marched
        level = orig(pbs, plan, n, *args)
        marched.append(len(pbs) * (n + 1) * int(level.nsteps))
        return level

    monkeypatch.setattr(_cn, "_march", spy)
    work, nodes = [], []
    for rtol in RTOLS:
        marched.clear()
        res = solve(tau, p0, wall, None, method="cn", rtol=rtol, atol=ATOL)
        assert res.status == "success"
        err = np.abs(np.asarray(res.area) - area)
        # within its tolerance, and below its own estimate
        assert np.all(err <= rtol * area + ATOL), (name, rtol)
        assert np.all(err <= np.asarray(res.error_estimate)), (name, rtol)
        work.append(sum(marched))
        nodes.append(int(res.n_nodes))
    # loose to tight: never more work, nor a finer grid, at the looser tolerance
    assert work == sorted(work), (name, work)
    assert nodes == sorted(nodes), (name, nodes)
