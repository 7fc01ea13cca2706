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

Taken where the compiled march is in force (:func:`._compiled.lean`), for the common case: an
absorbing lower wall carrying a table (:class:`._wall_table.WallTable`, speeds differenced), no
upper wall, no densities or progress reports, no one-wall (image) start, and no
graded stretch subdivided in the level; every other level takes :func:`._moving._march`.

The same for the rest of a solve's small numpy work, each one compiled call with the numpy
path's operations (bit for bit; the numpy path stays where numba is off or missing):
:func:`start_scan` (the start time of a tabled lower wall), :func:`plan_base` (the time plan's
base sequence after its geometric times), :func:`judge_ratio` (the error control's estimate and
worst ratio) and :func:`batch_balances` (a batch's balances and the screen's reductions).
Units: tau in Pa^2, pressures in Pa, speeds in 1/Pa.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ._cn_plan import Edge, Window, _differenced, _grades, _Plan
from ._level import Level, LevelInputs, Outputs, level_grid
from ._moving_fused import _OPS, _SNAP, fused_level
from ._problem import Problem

__all__ = [
    "batch_balances_of",
    "batch_balances",
    "judge_ratio",
    "lean_inputs",
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
    return not _grades(plan.base, nsub, plan.zones)


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
    nodes, rows, basis = grid
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
    area, moment = (R @ nodes.w).T, (R @ (nodes.x * nodes.w)).T
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
    """``(grid, p0, taus, theta, out, flags, out_at, coef, start state)`` of the level by
    ``fns``: :func:`level_setup` and :func:`start_scale` (compiled; see :func:`lean_inputs`),
    or the failed level where the walls swept the window."""
    setup, scale = fns[:2]
    pb = pbs[0]
    nb = len(pbs)
    grid = level_grid(nb, n, stretch)
    p0 = np.array([p.p0 for p in pbs], dtype=float)
    zones = plan.zones
    zone_starts = np.array([tb for tb, _ in zones]) if zones else _NO_ZONES
    chord_from = zones[0][0] if zones else math.inf
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
        *lo.table.args(), lo.breakpoint_array, grid.nodes.x, taus, theta, out, flags, out_at,
        coef, r0,
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


def lean_inputs(
    fns: tuple[Callable[..., Any], ...],
    pbs: list[Problem],
    plan: _Plan,
    n: int,
    nsub: int,
    stretch: float,
    n_ie: int,
) -> tuple[LevelInputs, Array, Array] | Level:
    """``(inputs, start state, face coefficients)`` of the level (what
    :func:`._moving.level_inputs`, :func:`._moving._initial_state` and
    :func:`._moving_fused.face_coefficients` give) by ``fns``: :func:`level_setup` and
    :func:`start_scale` (compiled); or the failed level where the walls swept the window."""
    outs = plan.outs if plan.outs is not None else pbs[0].tau[pbs[0].tau > plan.tau_s]
    made = _setup(fns, pbs, plan, outs, n, nsub, stretch, n_ie)
    if isinstance(made, Level):
        return made
    return _inputs(made, plan), _normalized(made[8], made[9], plan.k).ravel(), made[7]


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
    bp: Any,
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
    ``p0`` [Pa] (window half-width ``k``; the lower wall the table ``c .. negate`` with
    breakpoints ``bp``; no upper wall; chord speeds from
    ``chord_from``), ``out_at`` the steps of the output times ``outs`` (``np.searchsorted``),
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
    # the lower wall's track (:func:`._wall_table.table_track`'s calls)
    lo_m, lo, vb, va = np.empty(n), np.empty(n + 1), np.empty(n + 1), np.empty(n + 1)
    hi_t, lo_t, q = np.empty(n + 1), np.empty(n + 1), np.empty(4 * n + 3)
    wall_query(taus, mid, bp, hi_t, lo_t, q)  # noqa: F821
    p = np.empty(q.shape[0])
    table_values(c, x, t_lo, t_hi, extrapolate, q, p, root, negate)  # noqa: F821
    wall_track(p, taus, hi_t, lo_t, bp, lo_m, lo, vb, va)  # noqa: F821
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
    """:func:`._cn_plan._start_time` of the loads ``p0`` [Pa] with the table's lower wall and
    no upper one: the first of the candidate times ``tau_max grid`` [Pa^2] where the wall
    reaches a load's window ``p0 - k sqrt(2 tau)``, the same comparisons."""
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
            t = cand[0]
        elif first[q] > 0:
            t = cand[first[q] - 1] * 0.5
        else:
            t = tau_max
        best = min(best, t)
    return best


def _sorted_unique(v: Any) -> Any:  # pragma: no cover - compiled
    """:func:`._grid.sorted_unique` of a fresh 1-D float array (sorted in place)."""
    v.sort()
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


def judge_ratio(  # noqa: PLR0913 - the two answers' fields
    a_area: Any,
    b_area: Any,
    a_load: Any,
    a_ml: Any,
    a_mu: Any,
    b_load: Any,
    b_ml: Any,
    b_mu: Any,
    scale: Any,
    factor: float,
    rtol: float,
    atol: float,
) -> tuple:  # pragma: no cover - compiled (the numpy path is the reference)
    """:meth:`._cn_control._Judge.ratio`'s numbers in one pass (loads, outputs): the estimate
    ``factor |a - b|`` of the area, the largest estimate / tolerance of the area and the
    largest ``factor |load identity a - b| / scale`` [1] (NaN where any is NaN, as numpy's
    ``max``), the same operations element by element."""
    nb, n_out = a_area.shape
    err = np.empty((nb, n_out))
    m_area, m_load = -math.inf, -math.inf
    for q in range(nb):
        for j in range(n_out):
            e = factor * abs(a_area[q, j] - b_area[q, j])
            err[q, j] = e
            r = e / (rtol * abs(a_area[q, j]) + atol)
            la = a_load[q, j] + a_ml[q, j] + a_mu[q, j]
            lb = b_load[q, j] + b_ml[q, j] + b_mu[q, j]
            g = factor * abs(la - lb) / scale[q, j]
            if not r <= m_area:  # (a larger value, or NaN: NaN stays)
                m_area = r if m_area == m_area else m_area
            if not g <= m_load:
                m_load = g if m_load == m_load else m_load
    return err, m_area, m_load


_UNSURE = np.full((1, 1), np.nan)  # a non-area the compiled screen leaves to numpy's sum


def batch_balances_of(fast: Callable[..., tuple], problem: Problem, raw: Any, lo: Array) -> tuple:
    """:func:`._result._balances` and the screen's reductions of :func:`._result.finish_batch`
    for a batch ``raw`` of ``problem`` without an upper wall (``lo``: the lower wall's
    positions [Pa], as ``_fixed_positions`` gives them) by ``fast``
    (:func:`batch_balances`, compiled): ``(prob, loadb, reductions)``."""
    shape = raw.area.shape
    lo2 = lo.reshape(-1, shape[-1]) if lo.ndim else np.full((1, shape[-1]), lo)
    # (the arrays it fills made here: a compiled function's returned arrays cost ~0.6 us each)
    prob, loadb, red = np.empty(shape), np.empty(shape), np.empty(6)
    na = raw.non_area if np.ndim(raw.non_area) == 2 else _UNSURE
    fast(raw.area, raw.absorbed_lower, raw.absorbed_upper, raw.load, raw.wall_term,
         raw.error_estimate, problem.p0, lo2, problem.rtol, na, prob, loadb, red)  # fmt: skip
    return prob, loadb, red


def _nan_max(m: float, v: float) -> float:  # pragma: no cover - compiled
    """The running ``max`` of numpy (NaN once any value is NaN)."""
    if m != m or v != v:
        return math.nan if v != v or m != m else m
    return v if v > m else m


def batch_balances(  # noqa: PLR0913 - the batch's fields
    area: Any,
    abs_l: Any,
    abs_u: Any,
    load: Any,
    wall_term: Any,
    error: Any,
    p0: Any,
    lo: Any,
    rtol: float,
    non_area: Any,
    prob: Any,
    loadb: Any,
    red: Any,
) -> None:  # pragma: no cover - compiled (the numpy path is the reference)
    """:func:`._result._balances` of a batch without an upper wall (``lo`` the lower wall's
    positions (1 or loads, outputs) [Pa], ``p0`` (loads, 1) [Pa]) and the screen's reductions
    of :func:`._result.finish_batch` in one pass, into ``prob``, ``loadb`` (loads, outputs)
    and ``red`` = ``[max prob, -min prob, max loadb, -min loadb, max (error - rtol |area|),
    sure]`` (numpy's NaN-propagating ``max``/``min``), the same operations element by element;
    ``sure`` is 1 where the sum of ``non_area`` is finite in any order (every value finite and
    below ``1e300 / size``), else 0 (then numpy's sum decides)."""
    nb, n = area.shape
    red[:] = -math.inf
    bound = 1e300 / max(non_area.size, 1)
    red[5] = 1.0
    for q in range(non_area.shape[0]):
        for j in range(non_area.shape[1]):
            if not abs(non_area[q, j]) <= bound:
                red[5] = 0.0
    for q in range(nb):
        p = p0[q, 0]
        a = abs(p)
        for j in range(n):
            v = area[q, j] + abs_l[q, j]
            v = v + abs_u[q, j]
            v = v - 1.0
            prob[q, j] = v
            b = abs(lo[q if lo.shape[0] > 1 else 0, j])
            sc = a if a != a else (b if b != b else (b if b > a else a))
            sc = sc if sc > 0 else 1.0
            g = load[q, j] + wall_term[q, j]
            g = g - p
            g = g / sc
            loadb[q, j] = g
            red[0] = _nan_max(red[0], v)
            red[1] = _nan_max(red[1], -v)
            red[2] = _nan_max(red[2], g)
            red[3] = _nan_max(red[3], -g)
            slack = abs(area[q, j]) * -rtol
            red[4] = _nan_max(red[4], slack + error[q, j])


def _same_shape(a: Any, b: Any, c: Any, d: Any, shape: Any) -> bool:  # pragma: no cover
    """Whether ``a .. d`` are all shaped ``shape`` (compiled)."""
    return a.shape == shape and b.shape == shape and c.shape == shape and d.shape == shape


def _combined(a: Any, b: Any, o: Any) -> bool:  # pragma: no cover - compiled
    """``a + (a - b) / 3`` element by element into ``o`` (:func:`._level.combine`'s numpy
    operations: ``d = a - b``, ``d /= 3``, ``a + d``); whether no value is NaN (a NaN's sign
    and payload depend on the operands' order, which the compiler may swap: numpy decides)."""
    for q in range(a.shape[0]):
        for j in range(a.shape[1]):
            d = a[q, j] - b[q, j]
            d = d / 3.0
            v = a[q, j] + d
            if v != v:
                return False
            o[q, j] = v
    return True


def combine_fields(  # noqa: PLR0913 - the two levels' six fields
    a0: Any, a1: Any, a2: Any, a3: Any, a4: Any, a5: Any,
    b0: Any, b1: Any, b2: Any, b3: Any, b4: Any, b5: Any,
    out: Any,
) -> bool:  # fmt: skip  # pragma: no cover - compiled (the numpy path is the reference)
    """:func:`._level.combine`'s Richardson step of the six (loads, outputs) fields ``a``
    (finer) and ``b`` (coarser) into ``out`` (6, loads, outputs); False (the numpy path
    answers) where a field is not shaped as ``out[0]`` or a value is NaN."""
    s = out[0].shape
    if not (_same_shape(a0, a1, a2, a3, s) and _same_shape(a4, a5, b0, b1, s)
            and _same_shape(b2, b3, b4, b5, s)):  # fmt: skip
        return False
    return (_combined(a0, b0, out[0]) and _combined(a1, b1, out[1])
            and _combined(a2, b2, out[2]) and _combined(a3, b3, out[3])
            and _combined(a4, b4, out[4]) and _combined(a5, b5, out[5]))  # fmt: skip


def _summed(ws: Any, a: Any, b: Any, c: Any, o: Any) -> bool:  # pragma: no cover - compiled
    """``0 + ws[0] a + ws[1] b + ws[2] c`` element by element into ``o`` (:func:`._level.
    _weighted`'s numpy operations: ``a * w_0``, ``+= 0``, then ``+= (v * w_i)``); whether no
    value is NaN (see :func:`_combined`)."""
    for q in range(a.shape[0]):
        for j in range(a.shape[1]):
            acc = a[q, j] * ws[0]
            acc = acc + 0.0
            acc = acc + b[q, j] * ws[1]
            v = acc + c[q, j] * ws[2]
            if v != v:
                return False
            o[q, j] = v
    return True


def weighted_fields(  # noqa: PLR0913 - the three levels' six fields
    ws: Any,
    a0: Any, a1: Any, a2: Any, a3: Any, a4: Any, a5: Any,
    b0: Any, b1: Any, b2: Any, b3: Any, b4: Any, b5: Any,
    c0: Any, c1: Any, c2: Any, c3: Any, c4: Any, c5: Any,
    out: Any,
) -> bool:  # fmt: skip  # pragma: no cover - compiled (the numpy path is the reference)
    """:func:`._level.weighted` of three levels' six (loads, outputs) fields ``a``, ``b``,
    ``c`` with the weights ``ws`` (3,) into ``out`` (6, loads, outputs); False (the numpy
    path answers) where a field is not shaped as ``out[0]`` or a value is NaN."""
    s = out[0].shape
    if not (_same_shape(a0, a1, a2, a3, s) and _same_shape(a4, a5, b0, b1, s)
            and _same_shape(b2, b3, b4, b5, s) and _same_shape(c0, c1, c2, c3, s)
            and _same_shape(c4, c5, c0, c0, s)):  # fmt: skip
        return False
    return (_summed(ws, a0, b0, c0, out[0]) and _summed(ws, a1, b1, c1, out[1])
            and _summed(ws, a2, b2, c2, out[2]) and _summed(ws, a3, b3, c3, out[3])
            and _summed(ws, a4, b4, c4, out[4]) and _summed(ws, a5, b5, c5, out[5]))  # fmt: skip


def _plain(v: float) -> bool:  # pragma: no cover - compiled
    """Whether ``v`` is neither NaN nor -0 (where numpy's ``clip``/``maximum`` loops may
    differ in the sign or payload they return)."""
    return v == v and not (v == 0.0 and math.copysign(1.0, v) < 0.0)


def projected(area: Any, abs_l: Any, abs_u: Any, out: Any) -> bool:  # pragma: no cover
    """:func:`._level.project` where no sum of the absorbed fractions exceeds 1 (compiled):
    into ``out`` (7, loads, outputs) the clipped ``area``, ``max(abs_l, 0)``,
    ``max(abs_u, 0)`` and the distances moved (area, lower, upper, their sum), the same
    operations; False (``out`` partly written) where a value is NaN or -0 or a sum exceeds 1
    (the numpy path decides those)."""
    s = out[0].shape
    if area.shape != s or abs_l.shape != s or abs_u.shape != s:
        return False
    for q in range(s[0]):
        for j in range(s[1]):
            a0, l0, u0 = area[q, j], abs_l[q, j], abs_u[q, j]
            if not (_plain(a0) and _plain(l0) and _plain(u0)):
                return False
            a = a0 if a0 > 0.0 else 0.0  # (numpy's clip: max then min, NaN excluded above)
            a = a if a < 1.0 else 1.0
            lo = l0 if l0 >= 0.0 else 0.0  # (numpy's maximum; -0 excluded above)
            up = u0 if u0 >= 0.0 else 0.0
            total = lo + up
            if not total <= 1.0:
                return False
            out[0, q, j], out[1, q, j], out[2, q, j] = a, lo, up
            out[3, q, j] = abs(a - a0)
            out[4, q, j] = abs(lo - l0)
            out[5, q, j] = abs(up - u0)
            out[6, q, j] = abs(total - (l0 + u0))
    return True
