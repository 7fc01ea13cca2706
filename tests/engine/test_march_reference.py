"""Every wall type of the ``cn`` march against a plain dense Crank-Nicolson of the same
discretisation (``reference_cn.py``): the level's outputs agree to 1e-12 of their scale.

The wall types the march handles (``_moving``, ``_moving_block``, ``_cn_plan._edges``):
the window's artificial absorbing edges (every case, before a wall enters the window), a
fixed absorbing lower wall, moving absorbing walls (declared linear motion, speeds by central
differences, chord speeds after a declared breakpoint with its graded implicit-Euler steps),
an absorbing upper wall (fixed, moving, and a fixed yield wall, which acts absorbing), two
walls, the moving yield wall's closure rows, and batches of loads (systems concatenated).
"""

from __future__ import annotations

import numpy as np
import pytest
from reference_cn import reference_level

from xpersson.engine import Wall
from xpersson.engine._cn import grid_level
from xpersson.engine._moving_block import symmetric_steps
from xpersson.engine._problem import make_problem

TAU = np.logspace(-2.0, 1.0, 7)  # output times [Pa^2]


def _sqrt_lower(t):
    return 0.3 * np.sqrt(t) - 0.2  # moves up; speed by central differences


def _kinked_lower(t):
    return 0.25 * np.sqrt(np.maximum(t - 0.3, 0.0))  # square-root onset at tau_b = 0.3


CASES = {
    "fixed lower": (Wall.absorbing(0.0), None, (1.0,)),
    "linear lower": (Wall.linear(0.0, 0.05), None, (1.0,)),
    "moving lower": (Wall.absorbing(_sqrt_lower), None, (1.0,)),
    "breakpoint lower": (Wall.absorbing(_kinked_lower, breakpoints=[0.3]), None, (1.0,)),
    "fixed upper": (Wall.absorbing(-20.0), Wall.absorbing(2.0), (1.0,)),
    "moving upper": (Wall.absorbing(-20.0), Wall.absorbing(lambda t: 2.0 - 0.1 * t), (1.0,)),
    "two walls": (Wall.absorbing(0.0), Wall.absorbing(lambda t: 2.5 + 0.2 * t), (1.0,)),
    "fixed yield (absorbing)": (Wall.absorbing(0.0), Wall.yield_closure(2.0), (1.0,)),
    "yield closure": (
        Wall.absorbing(0.0),
        Wall.yield_closure(lambda t: 1.6 + 0.5 * t, lambda t: 0.5 + 0.0 * t),
        (1.0,),
    ),
    "yield closure, batch": (
        Wall.absorbing(0.0),
        Wall.yield_closure(lambda t: 1.6 + 0.5 * t, lambda t: 0.5 + 0.0 * t),
        (0.7, 1.0, 1.3),
    ),
    # a narrow window deep in its stiff regime (sigma = pi^2 tau / Y^2 >= 10 from tau ~ 2 on)
    # while the yield wall moves up (the case of _moving_block.symmetric_steps)
    "yield closure, stiff": (
        Wall.absorbing(0.0),
        Wall.yield_closure(lambda t: 1.2 + 0.05 * t, lambda t: 0.05 + 0.0 * t),
        (1.0,),
    ),
    "two walls, batch": (Wall.absorbing(lambda t: -0.1 * t), Wall.absorbing(3.0), (0.5, 1.5)),
}


def _level(lower, upper, p0, n_base=12, mult=1):
    pb = make_problem(TAU, np.array(p0), lower, upper, 1e-6, None, None, 10**6, {}, batch=True)
    return grid_level([pb.load(i) for i in range(len(p0))], n_base, mult)


@pytest.mark.parametrize("name", list(CASES))
def test_march_matches_the_dense_reference(name):
    lower, upper, p0 = CASES[name]
    inp, level = _level(lower, upper, p0)
    assert level.ok and inp.out_at.size > 0
    win = inp.window
    # the case exercises what it names: the real wall is inside the window in some steps
    if "lower" in name or "two walls" in name:
        assert win.real_lower.any()
    if "upper" in name or "two walls" in name or "fixed yield" in name:
        assert win.real_upper.any() and not inp.yield_wall
    if name.startswith("yield closure"):
        assert inp.yield_wall and win.real_upper.any()
    sym = symmetric_steps(win, inp.yield_wall)
    assert (sym is not None) == name.startswith("yield closure")
    if "breakpoint" in name:
        assert win.chord.any() and (inp.theta[2 * 2 :] == 1.0).any()  # graded, implicit start
    ref = reference_level(inp)
    edges = np.concatenate([win.start.lower.ravel(), (win.start.lower + win.start.width).ravel()])
    scale_p = max(float(np.max(np.abs(p0))), float(np.max(np.abs(edges))))
    out = level.outputs
    for key, scale in (
        ("area", 1.0),
        ("absorbed_lower", 1.0),
        ("absorbed_upper", 1.0),
        ("load", scale_p),
        ("moment_lower", scale_p),
        ("moment_upper", scale_p),
    ):
        got, want = getattr(out, key), ref[key]
        err = float(np.max(np.abs(got - want))) / scale
        assert err <= 1e-12, f"{name}: {key} differs from the reference by {err:.2e}"
    # the case is not trivial: something was absorbed
    assert np.max(out.absorbed_lower + out.absorbed_upper) > 1e-3


def test_refined_level_matches_the_reference():
    """A subdivided level (mult = 2: nested steps and nodes) of the yield closure."""
    lower, upper, p0 = CASES["yield closure"]
    inp, level = _level(lower, upper, p0, n_base=10, mult=2)
    ref = reference_level(inp)
    np.testing.assert_allclose(level.outputs.area, ref["area"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(level.outputs.absorbed_upper, ref["absorbed_upper"], atol=1e-12)
