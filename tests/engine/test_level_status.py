"""Failures inside ``cn`` are returned values, not exceptions: a singular tridiagonal solve
returns LAPACK's ``info``, a failed level says why in ``Level.failure``, and the accuracy
control ends its search on it with a status (the finest solved pair, flagged)."""

from __future__ import annotations

import numpy as np

from xpersson.engine import Wall, _cn, solve
from xpersson.engine._cnstep import tridiagonal_solve
from xpersson.engine._level import Level


def test_a_singular_tridiagonal_system_returns_its_info():
    dl, d, du = np.array([1.0]), np.array([0.0, 0.0]), np.array([1.0])
    rhs = np.array([1.0, 1.0])
    assert tridiagonal_solve(dl, d, du, rhs) == 0  # [[0, 1], [1, 0]]: pivoting solves it
    np.testing.assert_array_equal(rhs, [1.0, 1.0])
    info = tridiagonal_solve(np.array([0.0]), np.array([1.0, 0.0]), np.array([0.0]), np.ones(2))
    assert info == 2  # the second pivot is exactly zero


def test_a_failed_level_ends_the_search_with_a_status(monkeypatch):
    march, calls = _cn._march, []

    def third_fails(*args):
        calls.append(args[2])
        if len(calls) == 3:
            return Level(None, 0, args[2] + 1, "tridiagonal solve failed (info=7)")
        return march(*args)

    monkeypatch.setattr(_cn, "_march", third_fails)
    moving = Wall.absorbing(lambda t: -(0.2 + np.sqrt(t)))
    r = solve(np.logspace(-3, 1, 5), 1.0, moving, method="cn", rtol=1e-9)
    assert len(calls) == 3  # nothing is marched after the failure
    assert r.status == "tolerance_not_met" and not r.success
    assert "numerical failure: tridiagonal solve failed (info=7)" in r.message
    # the answer is the finest solved pair (the first two levels), flagged
    assert np.all(np.isfinite(r.area)) and np.all(r.error_estimate > 0)
