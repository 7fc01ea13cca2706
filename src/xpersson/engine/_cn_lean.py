"""A ``cn`` level's set-up in one compiled call (the compiled path's lean level).

On the small levels an accurate error control leaves (tens of nodes, tens of steps: a few
thousand node-steps) the march itself is a few microseconds; the Python around it was most of
a level's time: the level's times (:func:`._cn_plan._level_times`), the wall's track
(:func:`._cn_plan._tracks`), the window (:func:`._cn_plan._edges_batch`), the output steps,
the face coefficients (:func:`._moving_fused.face_coefficients`) and the start state
(:func:`._moving._initial_state`), each a compiled call or a dozen numpy calls with its own
allocations and argument checks. :func:`level_setup` does all of them in one call, by the same
compiled kernels in the same order (the numbers are the numpy path's bit for bit: every
operation is one rounding, no sums, ``tests/engine/test_cn_lean.py``); what numba need not
reproduce stays numpy's: the start state's ``exp`` (numpy's own, which ``libm``'s differs from
in the last bit), its mass (a ``gemv``) and the face coefficients' product with the face
functions (a ``gemm``).

Taken where the compiled march is in force (``_compiled.built("lean")``), for the common case: an
absorbing lower wall carrying a table (:class:`._wall_table.WallTable`, speeds differenced), no
upper wall, no densities or progress reports, no one-wall (image) start, chord speeds from
the march's start (:func:`._cn_grading._chord_from`: the wall's point speeds, never read,
are not computed), and no graded stretch subdivided in the level; every other level takes
:func:`._moving._march`.

The lean level is marched on the set-up's arrays (:func:`lean_level`, no named tuples of
inputs): the start state's normalisation and the steps in one compiled call
(:func:`lean_march`), the load at the outputs in another (:func:`lean_load`); the arrays the
kernels fill are made by the caller (a compiled function's returned arrays cost ~0.6 us each).

The same for the rest of a solve's small numpy work, each one compiled call with the numpy
path's operations (bit for bit; the numpy path stays where numba is off or missing):
:func:`start_scan` (the start time of a tabled lower wall) and :func:`plan_base` (the time
plan's base sequence after its geometric times); the outputs' kernels after the march are in
:mod:`._cn_outputs`. Units: tau in Pa^2, pressures in Pa, speeds in 1/Pa.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ._cn_grading import _differenced
from ._cn_plan import Edge, Window, _grades, _Plan
from ._level import Level, LevelInputs, Outputs, level_grid
from ._moving_fused import _OPS, _SNAP, fused_level
from ._problem import Problem

__all__ = [
    "lean_level",
    "lean_load",
    "lean_march",
    "lean_ok",
    "level_setup",
    "plan_base",
    "start_scale",
    "start_scan",
]

Array = NDArray[np.float64]


def lean_ok(pbs: list[Problem], plan: _Plan, nsub: int) -> bool:
    """Whether the level of ``plan`` subdivided ``nsub`` times takes :func:`lean_level`
    (see the module)."""
    pb = pbs[0]
    lo = pb.lower
    if pb.upper is not None or pb.p_out is not None or plan.image is not None:
        return False
    if lo is None or lo.table is None or not _differenced(lo) or plan.base.size < 2:
        return False
    # (chord speeds from the first step: level_setup asks the wall for no point speeds)
    return plan.chord_from <= plan.base[0] and not _grades(plan.base, nsub, plan.zones)


def lean_level(
    fns: tuple[Callable[..., Any], ...],
    kernels: tuple[Callable[..., int], Callable[..., None]],
    pbs: list[Problem],
    plan: _Plan,
    n: int,
    nsub: int,
    stretch: float,
    n_ie: int,
) -> Level | None:
    """The level ``(n, nsub)`` of ``plan`` (``stretch``, ``n_ie`` as in
    :func:`._moving.level_inputs`) set up by ``fns`` (:func:`_setup`) and marched by
    ``fns[2]`` (:func:`lean_march`: the start state's normalisation and
    :func:`._moving_fused.level_march`, compiled): the steps of
    :func:`._moving_fused.fused_level` on the set-up's arrays, without the inputs' named tuples
    (their making was a fifth of a small level's time); levels of no steps or of more steps
    than one block take :func:`._moving_fused.fused_level` with ``kernels``; None where that
    declines (the outputs' states would be too many to keep: the caller marches)."""
    nb, nn = len(pbs), n + 1
    outs = plan.outs if plan.outs is not None else pbs[0].tau[pbs[0].tau > plan.tau_s]
    if outs.shape[0] * nb * nn > _SNAP:
        return None
    made = _setup(fns, pbs, plan, outs, n, nsub, stretch, n_ie)
    if isinstance(made, Level):
        return made
    grid, p0, taus, theta, out, flags, out_at, coef, r0, mass = made
    steps = taus.shape[0] - 1
    if steps == 0 or steps > _OPS // (4 * nb * nn):  # (fused_level's blocks, its own copy)
        inp = _inputs(made, plan)
        return fused_level(kernels, inp, _normalized(r0, mass, plan.k).ravel(), stretch, coef)
    nodes, rows, basis = grid.nodes, grid.rows, grid.basis
    n_out = out_at.shape[0]
    snaps, sums = np.empty((n_out, nb * nn)), np.zeros((7, nb, n_out))
    zs = np.zeros((9, nb))
    ops = np.empty((steps, 4, nb * nn))
    # the face coefficients: the numpy path's BLAS product (face_ops), the same numbers
    np.matmul(coef.reshape(-1, 3), basis, out=ops.reshape(-1, nn))
    info = fns[2](
        math.erf(plan.k / math.sqrt(2.0)), mass, r0, steps, ops, nodes.w, rows.volumes,
        rows.walls, rows.last, flags, out, out_at, zs, snaps, sums,
    )  # fmt: skip
    if info != 0:
        return Level(None, 0, nn, f"tridiagonal solve failed (info={info})")
    # (_moving_fused._reduce_snapshots with the window's edges as marched: BLAS's sums)
    R = snaps.reshape(n_out, nb, nn)
    area, moment = (R @ nodes.w).T, (R @ grid.xw).T
    load = np.empty(area.shape)
    if not fns[3](area, moment, sums, load):  # (a NaN: numpy's operations decide its bits)
        load = sums[5] * area + sums[6] * moment
    return Level(Outputs(area, sums[1], sums[2], load, sums[3], -sums[4], None), steps, nn)


_NO_ZONES = np.zeros(0)  # the zone starts of a plan without graded zones
_NO_ZONES.setflags(write=False)


def _setup(
    fns: tuple[Callable[..., Any], ...],
    pbs: list[Problem],
    plan: _Plan,
    outs: Array,
    n: int,
    nsub: int,
    stretch: float,
    n_ie: int,
) -> tuple | Level:
    """``(grid, p0, taus, theta, out, flags, out_at, coef, r0, mass)`` of the level by
    ``fns``: :func:`level_setup` and :func:`start_scale` (compiled; :func:`_inputs` and
    :func:`_normalized` make them :func:`._moving.level_inputs`' and its start state),
    ``r0`` (loads, nodes) the start state before its normalisation and ``mass`` (loads,) its
    mass (:func:`_normalized` scales it); or the failed level where the walls swept the
    window."""
    setup, scale = fns[:2]
    pb = pbs[0]
    nb = len(pbs)
    grid = level_grid(nb, n, stretch)
    p0 = np.array([p.p0 for p in pbs], dtype=float)
    zones = plan.zones
    zone_starts = np.array([tb for tb, _ in zones]) if zones else _NO_ZONES
    chord_from = plan.chord_from
    lo = pb.lower
    # the arrays it fills, made here (a compiled function's returned arrays cost ~0.6 us each)
    size = (plan.base.shape[0] - 1) * nsub
    steps = size + min(n_ie, size)
    taus, theta = np.empty(steps + 1), np.empty(steps)
    out, flags = np.empty((10, nb, steps)), np.empty((4, nb, steps), dtype=np.bool_)
    out_at, coef = np.empty(outs.shape[0], np.int64), np.empty((steps, 4, nb, 3))
    r0 = np.empty((nb, n + 1))
    ok = setup(
        plan.base, nsub, n_ie, zone_starts, chord_from, outs, p0, float(plan.k),
        *lo.table.args(), grid.nodes.x, taus, theta, out, flags, out_at, coef, r0,
    )  # fmt: skip
    if not ok:
        return Level(None, 0, n + 1, "the walls swept the whole window (area 0)")
    np.exp(r0, out=r0)  # (numpy's exp: the numpy path's start state)
    scale(r0, out[1], taus[0])
    # the start state's mass (BLAS gemv: the numpy path's), its normalisation by the caller
    return grid, p0, taus, theta, out, flags, out_at, coef, r0, r0 @ grid.nodes.w


def _normalized(r0: Array, mass: Array, k: float) -> Array:
    """The start state ``r0`` (loads, nodes) of mass ``mass`` scaled to the window's mass
    ``erf(k / sqrt 2)`` (in place; :func:`._moving._initial_state`'s operations)."""
    r0 *= (math.erf(k / math.sqrt(2.0)) / mass)[:, None]
    return r0


def _inputs(made: tuple, plan: _Plan) -> LevelInputs:
    """The :class:`._level.LevelInputs` of :func:`_setup`'s arrays ``made``."""
    grid, p0, taus, theta, out, flags, out_at = made[:7]
    start = Edge(out[0], out[1], out[4], out[5], out[6])
    end = Edge(out[2], out[3], out[7], out[8], out[9])
    window = Window(flags[0], flags[1], start, end, flags[3])
    return LevelInputs(
        taus, theta, out_at, grid.nodes, window, p0[:, None], plan.k, plan.yield_wall,
        plan.image, grid,
    )  # fmt: skip


def level_setup(  # noqa: PLR0913 - the plan's and the table's arrays, as they hold them
    base: Any,
    nsub: int,
    n_ie: int,
    zone_starts: Any,
    chord_from: float,
    outs: Any,
    p0: Any,
    k: float,
    c: Any,
    x: Any,
    t_lo: float,
    t_hi: float,
    extrapolate: bool,
    root: bool,
    negate: bool,
    xn: Any,
    taus: Any,
    theta: Any,
    out: Any,
    flags: Any,
    out_at: Any,
    coef: Any,
    arg: Any,
) -> bool:  # pragma: no cover - compiled (the numpy path is the reference)
    """A lean level's set-up (see the module) into the arrays given (sized by the caller):
    ``taus``, ``theta`` of :func:`._cn_plan._level_times` (``base`` [Pa^2]
    subdivided ``nsub`` times, ``n_ie`` implicit-Euler half steps, theta 1 at the
    ``zone_starts``), ``out`` (10, loads, steps) and ``flags`` (4, loads, steps) of
    :func:`._cn_edges.window_edges` for the loads
    ``p0`` [Pa] (window half-width ``k``; the lower wall the table ``c .. negate``; no upper
    wall; chord speeds from ``chord_from``, at most ``taus[0]``: the wall's point speeds are
    not computed), ``out_at`` the steps of the output times ``outs`` (``np.searchsorted``),
    ``coef`` (steps, 4, loads, 3) of :func:`._moving_fused.face_coefficients`, ``arg``
    (loads, nodes) the start state's exponent ``-(l + W x - p0)^2 / (4 tau_0)`` at the nodes
    ``xn`` (:func:`._moving._initial_state`'s operations); returns whether the window's
    width stays positive (else the walls swept it)."""
    nb = p0.shape[0]
    size = (base.shape[0] - 1) * nsub + 1
    n_ie = min(n_ie, size - 1)
    level_times(base, nsub, n_ie, taus, theta)  # noqa: F821 - bound by _compiled._build
    n = taus.shape[0] - 1
    for i in range(n):
        for tb in zone_starts:
            if taus[i] == tb:
                theta[i] = 1.0
    mid = np.empty(n)
    for i in range(n):
        mid[i] = 0.5 * (taus[i] + taus[i + 1])
    # the lower wall's positions at the times and midpoints (in time order: the table's
    # look-ups start next to the last one); its point speeds are never read: every step
    # moves with its chord speed (lean_ok), which window_edges writes over them
    lo_m, lo = np.empty(n), np.empty(n + 1)
    vb = va = np.zeros(n + 1)
    q = np.empty(2 * n + 1)
    for i in range(n):
        q[2 * i], q[2 * i + 1] = taus[i], mid[i]
    q[2 * n] = taus[n]
    p = np.empty(q.shape[0])
    table_values(c, x, t_lo, t_hi, extrapolate, q, p, root, negate)  # noqa: F821
    for i in range(n):
        lo[i], lo_m[i] = p[2 * i], p[2 * i + 1]
    lo[n] = p[n * 2]
    up, zero = np.full(n + 1, math.inf), np.zeros(n + 1)
    window_edges(p0, k, False, False, chord_from, taus, mid, lo_m, up[:n], lo, up, va, vb,  # noqa: F821
                 zero, zero, zero, out, flags)  # fmt: skip
    ok = True
    for qq in range(nb):
        for i in range(n):
            if out[1, qq, i] <= 0.0 or out[3, qq, i] <= 0.0:
                ok = False
    j = 0
    for o in range(outs.shape[0]):  # (np.searchsorted, side "left": outs sorted)
        while j <= n and taus[j] < outs[o]:
            j += 1
        out_at[o] = j
    face_coefficients(0, n, taus, theta, out[1], out[4], out[5], out[3], out[7], out[8], coef)  # noqa: F821
    t0 = taus[0]
    for qq in range(nb):
        la, wa = out[0, qq, 0], out[1, qq, 0]
        for jj in range(xn.shape[0]):
            v = wa * xn[jj]
            v = v + la
            v = v - p0[qq]
            v = v * v
            arg[qq, jj] = v / (-4.0 * t0)
    return ok


def start_scale(r: Any, width: Any, t0: float) -> None:  # pragma: no cover - compiled
    """The start state after numpy's ``exp`` of :func:`level_setup`'s exponent: times the
    window's width at the start ``width[:, 0]`` [Pa] and ``1 / sqrt(4 pi t0)`` [1/Pa], the
    walls' rows 0 (:func:`._moving._initial_state`'s operations, in place)."""
    c = 1.0 / math.sqrt(4.0 * math.pi * t0)
    nn = r.shape[1]
    for q in range(r.shape[0]):
        w = width[q, 0]
        for j in range(nn):
            r[q, j] = r[q, j] * w * c
        r[q, 0] = 0.0
        r[q, nn - 1] = 0.0


def lean_march(  # noqa: PLR0913 - the level's arrays, as the set-up made them
    c: float,
    mass: Any,
    r0: Any,
    steps: int,
    ops: Any,
    w: Any,
    volumes: Any,
    walls: Any,
    last: Any,
    flags: Any,
    out: Any,
    out_at: Any,
    zs: Any,
    snaps: Any,
    sums: Any,
) -> int:  # pragma: no cover - compiled (the numpy path is the reference)
    """The start state ``r0`` (loads, nodes) of mass ``mass`` (loads,) scaled to the window's
    mass ``c`` (``r0 *= (c / mass)[:, None]``, :func:`_normalized`'s operations), then the
    level's ``steps`` steps by :func:`._moving_fused.level_march` on :func:`level_setup`'s
    window ``out``, ``flags`` (no upper wall), the face products ``ops`` and the rows ``w``,
    ``volumes``, ``walls``, ``last``; ``zs`` (9, loads) zeros, the outputs into ``snaps`` and
    ``sums``; returns LAPACK's ``info`` (0: every solve succeeded)."""
    nn = r0.shape[1]
    for q in range(r0.shape[0]):
        f = c / mass[q]
        for j in range(nn):
            r0[q, j] = r0[q, j] * f
    pos = np.zeros(1, np.int64)
    return level_march(0, steps, ops, w, volumes, walls, last, False, flags[0], flags[1],  # noqa: F821
                       out[9], out[0], out[1], out[2], out[3], out_at, r0.reshape(-1), zs[:5],
                       zs[5:], pos, snaps, sums)  # fmt: skip


def lean_load(area: Any, moment: Any, sums: Any, load: Any) -> bool:  # pragma: no cover
    """The load ``int p R dx = l area + W moment`` (loads, outputs) [Pa] of a lean level into
    ``load``, from the window's edges ``l = sums[5]``, ``W = sums[6]`` at the outputs (numpy's
    ``sums[5] * area + sums[6] * moment``, element by element; compiled); False where a value
    is NaN (its sign and payload then follow numpy's operand order: numpy recomputes)."""
    for q in range(area.shape[0]):
        for j in range(area.shape[1]):
            v = sums[5, q, j] * area[q, j] + sums[6, q, j] * moment[q, j]
            if v != v:
                return False
            load[q, j] = v
    return True


def start_scan(  # noqa: PLR0913 - the table's arrays, as it holds them
    c: Any,
    x: Any,
    t_lo: float,
    t_hi: float,
    extrapolate: bool,
    root: bool,
    negate: bool,
    grid: Any,
    tau_max: float,
    k: float,
    p0: Any,
) -> float:  # pragma: no cover - compiled (the numpy path is the reference)
    """:func:`._cn_plan._scan_start` of the loads ``p0`` [Pa] with the table's lower wall and
    no upper one: the first of the candidate times ``tau_max grid`` [Pa^2] where the wall
    reaches a load's window ``p0 - k sqrt(2 tau)``, the same comparisons; -1 where it does
    at the first candidate (the caller scans further down)."""
    n, nb = grid.shape[0], p0.shape[0]
    cand = np.empty(n)
    for j in range(n):
        cand[j] = tau_max * grid[j]
    pos = np.empty(n)
    table_values(c, x, t_lo, t_hi, extrapolate, cand, pos, root, negate)  # noqa: F821
    first = np.full(nb, -1, np.int64)
    left = nb
    for j in range(n):
        ks = k * math.sqrt(2.0 * cand[j])
        for q in range(nb):
            if first[q] < 0 and not pos[j] <= p0[q] - ks:
                first[q] = j
                left -= 1
        if left == 0:
            break
    best = tau_max
    for q in range(nb):
        if first[q] == 0:
            return -1.0
        if first[q] > 0:
            t = cand[first[q] - 1] * 0.5
        else:
            t = tau_max
        best = min(best, t)
    return best


def _sorted_unique(v: Any) -> Any:  # pragma: no cover - compiled
    """:func:`._grid.sorted_unique` of a 1-D float array. Sorted by a merge sort: numba's
    ``sort`` is a quicksort that takes quadratic time on a sorted run with values appended
    (the plan's geometric times and its fixed ones): 87 s for a plan of 1.2e6 times (a forced
    ``cn`` pull-off solve over 33 decades, ``fuzz.py --methods 1 --seed 191``), 0.04 s so."""
    v = v[np.argsort(v, kind="mergesort")]
    keep = np.empty(v.shape[0], np.bool_)
    for i in range(v.shape[0]):
        keep[i] = i == 0 or v[i] != v[i - 1]
    return v[keep]


def plan_base(
    geo: Any, outs: Any, kinks: Any, graded: Any, ratio: float, zones: Any, tau_s: float
) -> tuple:  # pragma: no cover - compiled (the numpy path is the reference)
    """The time plan's base sequence [Pa^2] and the outputs' indices in it, as
    :func:`._cn_plan._joint_plan` makes them from the geometric times ``geo``, the outputs
    ``outs``, the window's ``kinks``, the ``graded`` zones' times (their ``zones`` (m, 2):
    start, end), the step ``ratio`` and the start ``tau_s`` (the same comparisons)."""
    fixed = _sorted_unique(np.concatenate((outs, kinks, graded)))
    thr = 0.3 * ratio
    end = outs[outs.shape[0] - 1]
    keep = np.empty(geo.shape[0], np.bool_)
    for i in range(geo.shape[0]):
        ok = True
        for j in range(fixed.shape[0]):
            if not abs(geo[i] - fixed[j]) > thr * fixed[j]:
                ok = False
                break
        for z in range(zones.shape[0]):
            ok = ok and (geo[i] <= zones[z, 0] or geo[i] >= zones[z, 1])
        keep[i] = (ok or i == 0) and geo[i] < end
    base = _sorted_unique(np.concatenate((geo[keep], fixed)))
    base = base[base >= tau_s]
    index = np.empty(outs.shape[0], np.int64)
    j = 0
    for o in range(outs.shape[0]):  # (np.searchsorted, side "left": outs sorted)
        while j < base.shape[0] and base[j] < outs[o]:
            j += 1
        index[o] = j
    return base, index
