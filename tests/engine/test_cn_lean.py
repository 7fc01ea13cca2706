"""The lean level (:mod:`xpersson.engine._cn_lean`): one compiled call for a ``cn`` level's set-up
(times, the tabled wall's track, the window, the output steps, the face coefficients, the start
state's exponent) gives the numpy path's inputs and start state bit for bit, and the level it
marches the numpy path's outputs bit for bit, on generated walls, loads, grids and plans."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scipy.interpolate import PchipInterpolator, PPoly

from xpersson import set_options
from xpersson.engine import Wall, WallTable, _compiled, _moving
from xpersson.engine._cn import CNOptions, _Grids
from xpersson.engine._cn_control import _Judge
from xpersson.engine._cn_lean import _inputs, _normalized, _setup, lean_ok
from xpersson.engine._cn_outputs import batch_balances_of
from xpersson.engine._cn_plan import _joint_plan, _start_time
from xpersson.engine._level import Outputs, _kernel
from xpersson.engine._problem import make_problem
from xpersson.engine._result import Raw, finish_batch

pytest.importorskip("numba")

TAU = np.logspace(-1.0, np.log10(15.0), 5)  # output times [Pa^2]


def _wall(wiggle: float, breakpoint: float | None) -> Wall:
    """A tabled absorbing lower wall ``-sigma(tau)`` [Pa] (a PCHIP of sigma^2 that wiggles:
    several crossings of the window's edge), with a declared breakpoint [Pa^2] if given (a
    graded zone: its first step implicit, chord speeds from it on)."""
    t = np.logspace(-3.0, np.log10(20.0), 60)
    sigma = 2.0 * np.sqrt(t) * (1.0 + wiggle * np.sin(4.0 * np.log(t)))
    pc = PchipInterpolator(t, sigma**2, extrapolate=False)
    poly = PPoly(pc.c, pc.x, extrapolate=False)
    lo, hi = float(t[0]), float(t[-1])

    def position(tau):
        v = np.asarray(poly(np.minimum(np.maximum(np.asarray(tau, dtype=float), lo), hi)))
        return -np.sqrt(np.maximum(v, 0.0))

    table = WallTable(poly.c, poly.x, lo, hi, False, True, True)
    bps = () if breakpoint is None else (breakpoint,)
    return Wall.absorbing(position, breakpoints=bps, table=table)


def _level(wiggle, breakpoint, p0, rtol, n_base, nsub):
    """The loads' problems and the plan of their level ``(n_base, nsub)``, as ``cn`` makes
    them."""
    wall = _wall(wiggle, breakpoint)
    batch = make_problem(TAU, np.array(p0), wall, None, rtol, None, None, 10**6, {}, batch=True)
    pbs = [batch.load(i) for i in range(len(p0))]
    opts = CNOptions.read(pbs[0].options, pbs[0].atol)
    tau_s = _start_time(pbs, opts.window_k)
    grids = _Grids(pbs, opts, tau_s, pbs[0].tau > tau_s)
    plan = grids.plan(n_base, 1)
    return pbs, plan, (n_base * nsub, nsub, grids.stretch, opts.rannacher)


def _build() -> None:
    """The compiled kernels built, whatever ``XPERSSON_COMPILED`` says (these tests compare
    them with the numpy path; a hypothesis test cannot take the ``compiled_on`` fixture)."""
    with set_options(compiled=True):
        assert _compiled.build()


def _bits(a) -> bytes:
    return np.ascontiguousarray(a).tobytes()


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    wiggle=st.floats(0.0, 0.7),
    breakpoint=st.one_of(st.none(), st.floats(0.2, 5.0)),
    p0=st.lists(st.floats(0.2, 1.5), min_size=1, max_size=3),
    rtol=st.sampled_from([1e-4, 1e-6, 1e-8]),
    n_base=st.sampled_from([6, 24, 40]),
    nsub=st.integers(1, 3),
)
def test_lean_level_is_the_numpy_paths_bit_for_bit(wiggle, breakpoint, p0, rtol, n_base, nsub):
    """The set-up's times, output steps, window (edges, speeds, regimes) and start state equal
    :func:`._moving.level_inputs` and :func:`._moving._initial_state` of the numpy path, and
    the level's outputs (marched by the compiled level from them) equal the numpy march's."""
    _build()
    pbs, plan, (n, nsub, stretch, n_ie) = _level(wiggle, breakpoint, p0, rtol, n_base, nsub)
    if not lean_ok(pbs, plan, nsub):  # (a graded zone subdivided: the general set-up)
        return
    with set_options(compiled=False):
        ref = _moving.level_inputs(pbs, plan, n, nsub, stretch, n_ie)
        win = ref.window
        r0 = _moving._initial_state(win, ref.nodes.x, ref.nodes.w, ref.p0, ref.taus[0], ref.k)
        want = _moving._march(pbs, plan, n, nsub, stretch, n_ie)
    with set_options(compiled=True):
        outs = plan.outs if plan.outs is not None else pbs[0].tau[pbs[0].tau > plan.tau_s]
        made = _setup(_compiled.built("lean"), pbs, plan, outs, n, nsub, stretch, n_ie)
        got = _moving._march(pbs, plan, n, nsub, stretch, n_ie)
    if want.failure:  # (the walls swept the window: both say so)
        assert got.failure == want.failure
        return
    inp, start = _inputs(made, plan), _normalized(made[8], made[9], plan.k).ravel()
    for name in ("taus", "theta", "out_at", "p0"):
        assert _bits(getattr(inp, name)) == _bits(getattr(ref, name)), name
    assert _bits(start) == _bits(r0)
    for end in ("start", "end"):
        for name, have in getattr(inp.window, end)._asdict().items():
            assert _bits(have) == _bits(getattr(getattr(win, end), name)), (end, name)
    for name in ("real_lower", "real_upper", "chord"):
        assert _bits(getattr(inp.window, name)) == _bits(getattr(win, name)), name
    assert got.nsteps == want.nsteps
    for name, have in got.outputs._asdict().items():
        if have is not None:
            assert _bits(have) == _bits(getattr(want.outputs, name)), name


def test_lean_level_is_taken_only_where_it_applies():
    """A tabled lower wall without an upper wall takes the lean set-up; an upper wall, a
    position callable without a table, or densities do not."""
    pbs, plan, (n, nsub, *_) = _level(0.3, None, [0.8], 1e-6, 24, 2)
    assert lean_ok(pbs, plan, nsub)
    plain = Wall.absorbing(pbs[0].lower.position)  # (the same wall, no table)
    for lower, upper, p_out in (
        (plain, None, None),
        (pbs[0].lower, Wall.absorbing(5.0), None),
        (pbs[0].lower, None, np.array([0.5])),
    ):
        pb = make_problem(TAU, np.array([0.8]), lower, upper, 1e-6, None, p_out, 10**6, {},
                          batch=True).load(0)  # fmt: skip
        assert not lean_ok([pb], plan, nsub)


def test_lean_level_needs_chord_speeds_from_the_march_start():
    """The lean set-up asks the wall for no point speeds: it is taken where every step moves
    with its chord speed (a tabled wall's speeds are differences: chords from the march's
    start), not where a plan would start them later (the point speeds would be read)."""
    pbs, plan, (n, nsub, *_) = _level(0.3, None, [0.8], 1e-6, 24, 2)
    assert plan.chord_from == plan.base[0] == plan.tau_s
    assert lean_ok(pbs, plan, nsub)
    later = dataclasses.replace(plan, chord_from=float(plan.base[1]))
    assert not lean_ok(pbs, later, nsub)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    wiggle=st.floats(0.0, 0.7),
    p0=st.lists(st.floats(0.05, 3.0), min_size=1, max_size=4),
    clock=st.one_of(st.floats(0.01, 100.0), st.floats(1e14, 1e20)),
    k=st.floats(2.0, 9.0),
)
def test_compiled_start_scan_is_the_numpy_start_time(wiggle, p0, clock, k):
    """The start time of a tabled lower wall by one compiled scan equals the numpy scan's,
    for loads whose windows the wall reaches early, late or never, and where it reaches one
    already at the first candidate (``clock`` 1e14-1e20: the scan runs further down)."""
    _build()
    wall = _wall(wiggle, None)
    batch = make_problem(TAU * clock, np.array(p0), wall, None, 1e-6, None, None, 10**6, {},
                         batch=True)  # fmt: skip
    pbs = [batch.load(i) for i in range(len(p0))]
    with set_options(compiled=False):
        want = _start_time(pbs, k)
    with set_options(compiled=True):
        assert _compiled.built("start") is not None
        got = _start_time(pbs, k, scan=_compiled.built("start"))
    assert got == want


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    breakpoint=st.one_of(st.none(), st.floats(0.05, 10.0)),
    kinks=st.lists(st.floats(0.01, 20.0), max_size=6),
    per_decade=st.floats(1.0, 40.0),
    tau_s=st.floats(1e-4, 0.09),
)
def test_compiled_plan_is_the_numpy_plan(breakpoint, kinks, per_decade, tau_s):
    """The time plan's base sequence and output indices by one compiled call equal the numpy
    path's, with kinks (some on the outputs or the geometric times) and graded zones."""
    _build()
    wall = _wall(0.3, breakpoint)
    batch = make_problem(TAU, np.array([0.9]), wall, None, 1e-6, None, None, 10**6, {},
                         batch=True)  # fmt: skip
    pbs = [batch.load(0)]
    kinks = kinks + [float(TAU[1])]  # (a kink on an output time)
    with set_options(compiled=False):
        want = _joint_plan(pbs, 6.0, per_decade, tau_s, kinks)
    with set_options(compiled=True):
        assert _compiled.built("plan") is not None
        got = _joint_plan(pbs, 6.0, per_decade, tau_s, kinks, _compiled.built("plan"))
    assert _bits(got.base) == _bits(want.base)
    assert _bits(got.out_index) == _bits(want.out_index)
    assert got.zones == want.zones


_VALUES = st.one_of(
    st.floats(-2.0, 2.0), st.sampled_from([0.0, -0.0, np.nan, np.inf, -np.inf, 1e-300])
)


@settings(max_examples=60, deadline=None)
@given(
    shape=st.tuples(st.integers(1, 3), st.integers(1, 5)),
    data=st.data(),
    factor=st.floats(1e-3, 20.0),
    rtol=st.sampled_from([1e-8, 1e-6, 1e-4]),
)
def test_compiled_judge_ratio_is_the_numpy_ratio(shape, data, factor, rtol):
    """The error control's estimate and worst estimate / tolerance by one compiled pass equal
    the numpy path's, NaN and infinities included (numpy's ``max``, Python's ``max``)."""
    _build()
    n = shape[0] * shape[1]

    def field():
        return np.array(data.draw(st.lists(_VALUES, min_size=n, max_size=n))).reshape(shape)

    a, b = (Outputs(*(field() for _ in range(6)), None) for _ in range(2))
    scale = np.abs(field()) + 0.5
    pb = make_problem(TAU, 0.9, _wall(0.3, None), None, rtol, None, None, 10**6, {})
    judge = _Judge(pb, scale)
    with set_options(compiled=False), np.errstate(all="ignore"):
        want = judge.ratio(a, b, factor)
    with set_options(compiled=True):
        got = judge.ratio(a, b, factor)
    assert _bits(got[0]) == _bits(want[0])
    # (the worst ratio is a decision, compared with 1: its value, NaN for NaN)
    assert got[1] == want[1] or (np.isnan(got[1]) and np.isnan(want[1]))


_NUDGE = st.sampled_from([0.0, -0.0, 1e-14, -1e-14, 1e-9, -1e-9, 1e-3, -1e-3, np.nan, np.inf])


@settings(max_examples=80, deadline=None)
@given(data=st.data(), loads=st.integers(1, 3), rtol=st.sampled_from([1e-8, 1e-6, 1e-3]))
def test_compiled_batch_balances_are_the_numpy_ones(data, loads, rtol):
    """A batch's balances, status and messages with the balances and the screen's reductions
    by one compiled call equal the numpy path's: balances near their tolerance either way,
    NaN, infinities and failing loads included."""
    _build()
    n = loads * TAU.size
    p0 = np.linspace(0.5, 1.2, loads)
    pb = make_problem(TAU, p0, _wall(0.3, None), None, rtol, None, None, 10**6, {}, batch=True)

    def draw(values):
        return np.array(data.draw(st.lists(values, min_size=n, max_size=n))).reshape(loads, -1)

    def nudge():  # (one balance off by a drawn amount, the others exact)
        out = np.zeros(n)
        out[data.draw(st.integers(0, n - 1))] = data.draw(_NUDGE)
        return out.reshape(loads, -1)

    area = draw(st.sampled_from([0.0, 0.25, 0.5, 1.0]))
    lo = (1.0 - area) * draw(st.sampled_from([0.0, 0.5, 1.0]))
    with np.errstate(all="ignore"):
        up = 1.0 - area - lo + nudge()  # (probability balance near 0, either sign)
        wall = draw(st.sampled_from([0.0, -0.5, 0.25]))
        load = p0[:, None] - wall + nudge()  # (load balance near 0)
        err = draw(st.floats(0.0, 2.0)) * rtol * np.abs(area)
        raw = Raw(area, lo + up, lo, up, load, wall, err, None, "success", "", 9, 5, 9)
    with set_options(compiled=False), np.errstate(all="ignore"):
        want = finish_batch(pb, raw, "cn")
    with set_options(compiled=True), np.errstate(all="ignore"):
        got = finish_batch(pb, raw, "cn")
    assert got["status"] == want["status"] and got["message"] == want["message"]
    assert _bits(got["success"]) == _bits(want["success"])
    prob, loadb = want["fields"]["probability_balance"], want["fields"]["load_balance"]
    slack = np.abs(area) * -rtol + err
    with np.errstate(all="ignore"):
        ref = [prob.max(), -prob.min(), loadb.max(), -loadb.min(), slack.max()]
    with set_options(compiled=True):
        red = batch_balances_of(
            _compiled.built("balances"), pb, raw, got["fields"]["wall_lower"][:1]
        )
    red = red[2]
    assert np.array_equal(red[:5], ref, equal_nan=True)  # (NaN-propagating max / min)
    assert red[5] == float(bool(np.all(np.isfinite(lo + up))))  # (sure: a finite sum)
    for name, value in want["fields"].items():
        if value is not None:
            assert _bits(got["fields"][name]) == _bits(value), name


@settings(max_examples=60, deadline=None)
@given(
    shape=st.tuples(st.integers(1, 3), st.integers(1, 5)),
    data=st.data(),
    weights=st.lists(st.floats(-3.0, 3.0), min_size=3, max_size=3),
)
def test_compiled_level_combinations_are_the_numpy_ones(shape, data, weights):
    """The Richardson step of two levels (``combine``) and the weighted sum of three
    (``weighted``) by one compiled pass each equal the numpy path's bit for bit, signed
    zeros, NaN and infinities included, on C- and Fortran-ordered fields."""
    from xpersson.engine._level import combine, weighted

    _build()
    n = shape[0] * shape[1]

    def field():
        return np.array(data.draw(st.lists(_VALUES, min_size=n, max_size=n))).reshape(shape)

    lv = [Outputs(*(field() for _ in range(6)), None) for _ in range(3)]
    odd = lv[2]._replace(load=np.asfortranarray(lv[2].load))  # (another memory layout)
    ws = np.array(weights)
    for compiled in (False, True):
        with set_options(compiled=compiled), np.errstate(all="ignore"):
            got = (combine(lv[0], lv[1], True), weighted(lv, ws), weighted([*lv[:2], odd], ws))
        if not compiled:
            want = got
    for have, ref in zip(got, want, strict=True):
        for name in Outputs._fields[:6]:
            assert _bits(getattr(have, name)) == _bits(getattr(ref, name)), name
    plain = np.full(shape, 0.25)  # (ordinary values: the compiled pass answers, and is reached)
    with set_options(compiled=True):
        fast = _kernel("fields")
        assert fast is not None and fast[0](*[plain] * 12, np.empty((6, *shape)))
        assert fast[1](np.full(3, 1 / 3), *[plain] * 18, np.empty((6, *shape)))


@settings(max_examples=40, deadline=None)
@given(
    n=st.integers(1, 6),
    loads=st.integers(1, 3),
    value=st.one_of(st.integers(0, 10**6), st.lists(st.integers(0, 99), min_size=3, max_size=3)),
)
def test_one_load_views_and_counts_are_numpys(n, loads, value):
    """The shortcuts of a batch's fields: a view of one row over the loads is numpy's
    broadcast (values, shape, read-only, no copy), a count per load numpy's broadcast of it."""
    from xpersson.engine._views import broadcast_view, per_load

    row = np.arange(float(n))
    got, want = broadcast_view(row, (loads, n)), np.broadcast_to(row, (loads, n))
    assert got.shape == want.shape and _bits(got) == _bits(want)
    assert not got.flags.writeable and np.shares_memory(got, row)
    if isinstance(value, list):
        value = np.array(value[:loads] + [0] * (loads - len(value[:loads])), dtype=np.int64)
    counts = per_load(value, loads)
    assert counts.dtype == np.int64 and not counts.flags.writeable
    assert _bits(counts) == _bits(np.broadcast_to(np.asarray(value, dtype=np.int64), (loads,)))


@settings(max_examples=30, deadline=None)
@given(
    wiggle=st.floats(0.0, 0.7),
    p0=st.lists(st.floats(-0.5, 1.5), min_size=1, max_size=3),
    spoil=st.sampled_from([None, np.nan, np.inf]),
)
def test_compiled_position_check_is_the_numpy_one(wiggle, p0, spoil):
    """The input check of a tabled lower wall in one compiled call accepts and refuses what
    the numpy check does (a load on or below the wall at ``tau = 0``, a non-finite position
    somewhere in the table), with the numpy check's message."""
    _build()
    wall = _wall(wiggle, None)
    if spoil is not None:  # (a non-finite coefficient in one interval of table and callable)
        c = wall.table.c.copy()
        c[0, c.shape[1] // 2] = spoil
        table = WallTable(c, *wall.table.args()[1:])
        wall = Wall.absorbing(table.values, table=table)
    p0 = np.array(p0)
    outcome = []
    for compiled in (False, True):
        with set_options(compiled=compiled):
            try:
                make_problem(TAU, p0, wall, None, 1e-6, None, None, 10**6, {}, batch=True)
                outcome.append("ok")
            except ValueError as exc:
                outcome.append(str(exc))
    assert outcome[0] == outcome[1]


def test_compiled_plan_of_a_long_sorted_run_is_the_numpy_plan():
    """A plan of 3e5 geometric times (a long run, sorted, with the fixed times appended: the
    input on which numba's quicksort is quadratic; the plan's sort is a merge sort now):
    the same base and output indices as the numpy path."""
    _build()
    wall = Wall.absorbing(0.0)
    tau = np.array([0.0, 1e20])
    pbs = [make_problem(tau, 1.0, wall, None, 1e-6, None, None, 10**6, {})]
    with set_options(compiled=False):
        want = _joint_plan(pbs, 6.0, 1e4, 1e-5, [3e-3])
    with set_options(compiled=True):
        got = _joint_plan(pbs, 6.0, 1e4, 1e-5, [3e-3], fast=_compiled.built("plan"))
    assert want.base.size > 2e5
    np.testing.assert_array_equal(got.base, want.base)
    np.testing.assert_array_equal(got.out_index, want.out_index)
