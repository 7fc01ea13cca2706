"""Stiff windows of ``cn`` (``_stiff``): a yield wall that stops the window from growing.

The substeps keep the base times (levels stay nested), resolve the decay of the window's
slowest mode where ``sigma = pi^2 tau / W^2`` passes from 0.5 to 10, and the solve keeps its
identities and its error estimate against a tight reference."""

from __future__ import annotations

import math

import numpy as np
import pytest

from xpersson.engine import Wall, _stiff, solve
from xpersson.engine._cn import CNOptions, _Grids
from xpersson.engine._cn_plan import _joint_plan, _start_time
from xpersson.engine._problem import make_problem

P0, EPS = 0.3, 1e-3
TAU = np.logspace(-3, 1.0, 9)


def _yield(y0: float = 1.0, eps: float = EPS) -> Wall:
    """A slowly rising yield wall: the window [0, Y] stops growing, sigma reaches ~100."""
    return Wall.yield_closure(lambda t: y0 + eps * np.asarray(t), lambda t: eps + 0.0 * t)


def _grids(upper: Wall | None, loads=(P0,)) -> _Grids:
    pbs = [make_problem(TAU, p, Wall.absorbing(0.0), upper, 1e-6, None, None, 10**6, None)
           for p in loads]  # fmt: skip
    opts = CNOptions.read(pbs[0].options, pbs[0].atol)
    tau_s = _start_time(pbs, opts.window_k)
    return _Grids(pbs, opts, tau_s, pbs[0].tau > tau_s)


def test_stiffness_is_pi2_tau_over_the_window_width_squared():
    """Late, both walls are real and the window is [0, Y]: sigma = pi^2 tau_mid / Y^2."""
    lv = _grids(_yield(eps=1e-9))
    plan = _joint_plan(lv.pbs, lv.opts.window_k, 8.0, lv.tau_s, lv.kinks)
    sigma = _stiff.stiffness(lv.pbs, plan)
    b = plan.base
    mid = np.sqrt(b[:-1] * b[1:])
    late = mid > 1.0  # k sqrt(2 tau) far beyond Y = 1 there
    width = 1.0 + 1e-9 * b[:-1]  # the narrower end of each step
    np.testing.assert_allclose(sigma[late], math.pi**2 * mid[late] / width[late] ** 2, rtol=1e-12)
    assert sigma[late].max() > 50.0


def test_refined_plan_nests_the_base_and_resolves_the_decay():
    lv = _grids(_yield(), loads=(0.2, P0, 0.5))
    per_decade = lv.opts.per_node * 24 * 4
    base = _joint_plan(lv.pbs, lv.opts.window_k, per_decade, lv.tau_s, lv.kinks)
    plan = lv.plan(24, 4)  # made through the refinement
    assert plan.base.size > base.base.size
    # every base time (outputs, kinks) is kept exactly: the levels stay nested
    assert np.isin(base.base, plan.base).all()
    np.testing.assert_array_equal(plan.base[plan.out_index], TAU[TAU > lv.tau_s])
    assert np.all(np.diff(plan.base) > 0)
    # each base step is split uniformly: substeps per base step from the stiffness
    sigma = _stiff.stiffness(lv.pbs, base)
    sub = np.diff(np.searchsorted(plan.base, base.base))
    step = math.log(10.0) / per_decade
    dln = np.log(base.base[1:] / base.base[:-1])
    mid = (sigma > _stiff.STIFF_STEP) & (sigma < _stiff.STIFF_END)
    assert mid.any()
    # the slowest mode decays by at most STIFF_STEP base steps' worth per substep
    assert np.all(sigma[mid] * dln[mid] / sub[mid] <= _stiff.STIFF_STEP * step * (1 + 1e-9))
    assert np.all(sub[sigma >= _stiff.STIFF_END] == _stiff.STIFF_LATE)
    assert np.all(sub[sigma <= _stiff.STIFF_STEP] == 1)
    assert _stiff.stiff_at_end(lv.pbs, lv.opts.window_k)


def test_no_yield_wall_no_change():
    """A moving absorbing wall (the window grows with sqrt(tau)): the plan is left as made."""
    lv = _grids(Wall.absorbing(lambda t: 2.0 + 3.0 * np.asarray(t)))
    base = _joint_plan(lv.pbs, lv.opts.window_k, 24.0, lv.tau_s, lv.kinks)
    assert _stiff.stiff_refined(lv.pbs, base, 24.0) is base
    assert not _stiff.stiff_at_end(lv.pbs, lv.opts.window_k)


def test_stiff_window_identities_and_estimate_against_a_tight_reference():
    """P_elastic + P_plastic + P_noncontact = 1 to round-off, the force identity, and the
    error within the reported estimate of a reference solved at rtol 1e-7."""
    up = _yield()
    res = solve(TAU, P0, Wall.absorbing(0.0), up, rtol=1e-5, method="cn")
    ref = solve(TAU, P0, Wall.absorbing(0.0), up, rtol=1e-7, method="cn")
    assert res.status == "success" and ref.status == "success", (res.message, ref.message)
    total = res.area + res.absorbed_upper + res.absorbed_lower
    # (round-off of the step sums: the engine's own bound is 16 eps per step)
    np.testing.assert_allclose(total, 1.0, rtol=0, atol=16 * np.finfo(float).eps * res.nsteps)
    force = res.load + (1.0 + EPS * TAU) * res.absorbed_upper
    np.testing.assert_allclose(force, P0, rtol=1e-5)
    # the window became stiff: the elastic area is far below its fixed-wall start
    assert res.area[-1] < 1e-3
    err = np.abs(res.area - ref.area)
    assert np.all(err <= res.error_estimate)
    assert np.all(err <= 1e-5 * res.area)


TK = 0.37  # a kink of the yield wall's speed (its acceleration jumps), between two outputs


def _kinked(kinks=()) -> Wall:
    """A yield wall whose speed has a kink at TK (C^1 motion, as at a spectrum's knee)."""
    return Wall.yield_closure(
        lambda t: 1.0 + EPS * np.asarray(t) + 0.015 * np.maximum(np.asarray(t) - TK, 0.0) ** 2,
        lambda t: EPS + 0.03 * np.maximum(np.asarray(t) - TK, 0.0),
        kinks=kinks,
    )


def test_declared_kinks_are_step_boundaries_of_every_level():
    lv = _grids(_kinked((TK, 50.0)))  # (50 is beyond the last output: dropped)
    assert _stiff.wall_kinks(lv.pbs[0], lv.tau_s, float(TAU[-1])) == [TK]
    for n, dense in ((12, 1), (24, 4)):
        assert TK in lv.plan(n, dense).base
    assert TK not in _grids(_kinked()).plan(12, 1).base


def test_kink_inside_a_step_leaves_an_error_irregular_in_the_subdivision():
    """The levels ``m = 3..7`` of one plan, fitted by ``A + b m^-2 + c m^-4`` (the expansion
    Richardson extrapolation assumes): after the kink the residual of the fit falls more
    than 10x when the kink is declared (a step boundary of every level; measured 26-260x)."""
    ms = np.arange(3.0, 8.0)
    fit = np.stack([np.ones(ms.size), ms**-2, ms**-4], axis=1)
    resid = []
    for kinks in ((), (TK,)):
        lv = _grids(_kinked(kinks))
        late = TAU[TAU > lv.tau_s] > TK
        a = np.array([lv.level(12, int(m), 2).area[0][late] for m in ms])
        coef = np.linalg.lstsq(fit, a, rcond=None)[0]
        resid.append(np.abs(a - fit @ coef).max(axis=0))
    assert np.all(resid[1] < 0.1 * resid[0]), resid


def test_kinks_must_be_positive_finite_times():
    with pytest.raises(ValueError, match=r"kinks \[Pa\^2\]"):
        _kinked((-1.0,))
