"""Time plan and window of the ``cn`` method: analytic start, kinks of the window edges,
graded stretches after wall breakpoints, the refined step sequences and the window edges (with
their speeds) along them.  See :mod:`._cn` for the scheme."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from ._cn_edges import compiled_track, compiled_window
from ._cn_grading import _GRADE, _chord_from, _differenced, _graded_zones
from ._cn_kinks import _bracketed_roots, _switch_times_batch, kinks_apart
from ._grid import decades as _decades
from ._grid import is_in as _is_in
from ._grid import sorted_unique
from ._problem import Problem
from ._wall_table import kernels as table_kernels

__all__ = [
    "Edge",
    "Window",
    "_Plan",
    "_joint_plan",
    "_level_times",
    "_edges_batch",
    "_faces",
    "_exact_start",
    "_start_time",
    "_switch_times_batch",
    "_bracketed_roots",
]

Array = NDArray[np.float64]


@dataclass
class _Plan:
    base: Array  # level-0 time sequence tau_s ... tau_end
    out_index: Array  # index in base of each numerical output
    tau_s: float
    k: float
    yield_wall: bool
    zones: tuple[tuple[float, float], ...] = ()  # graded stretches (tau_b, tau_end) after
    # declared wall breakpoints: steps uniform in (tau - tau_b)^(1/4), implicit first step;
    # chord mesh speeds from the first breakpoint on
    image: float | None = None  # resting lower wall [Pa] of an image start; None: Gaussian
    release: bool = False  # yield wall real only inside the window (_cn_control._release)
    outs: Array | None = None  # the batch's numerical output times (tau > tau_s) [Pa^2]
    chord_from: float = math.inf  # the mesh moves with the steps' chord speeds from here on
    # [Pa^2] (:func:`_chord_from`; inf: the walls' point speeds throughout)


_NO_ZONES = np.zeros((0, 2))  # the graded zones (start, end) of a plan without any (read-only)
_NO_ZONES.setflags(write=False)

_START_GRID = np.logspace(-18, 0, 721)  # candidate start times / tau_max (read-only)
_START_GRID.setflags(write=False)
#: Rounds of the start scan: where a load's window already holds a wall at the first candidate
#: (``1e-18 tau_max``), the scan runs again 18 decades further down, up to this many times.
_START_ROUNDS = 4


def _start_time(
    pbs: list[Problem], k: float, lower: bool = True, scan: Callable | None = None
) -> float:
    """Largest tau_s with every real wall (the upper one only unless ``lower``) outside the
    window of every load of ``pbs`` on [0, tau_s] (the smallest of the loads' own).  The loads
    of a batch share their walls and clock: the walls are evaluated once for all of them
    (``scan``: :func:`._cn_lean.start_scan` compiled, for a tabled lower wall: the same)."""
    pb = pbs[0]
    tau_max = pb.tau_max
    shared = all(
        p.lower is pb.lower and p.upper is pb.upper and p.tau_max == tau_max for p in pbs[1:]
    )
    if not shared:
        return min(_start_time([p], k, lower) for p in pbs)
    # candidates down to 1e-18 tau_max; where a load's window holds a wall already at the
    # first, 18 decades further down (a start there would put the free Gaussian's tail beyond
    # the wall: a load 3 widths from it lost 1.3e-3 of its mass and force, the same on every
    # grid level, which no error estimate sees: tests/engine/test_start_time.py)
    top = float(tau_max)
    for _ in range(_START_ROUNDS):
        t = _scan_start(pbs, k, lower, scan, top)
        if t is not None:
            return t
        top *= float(_START_GRID[0])
    return top  # (a load on its wall: no start outside it; the last round's first candidate)


def _scan_start(
    pbs: list[Problem], k: float, lower: bool, scan: Callable | None, top: float
) -> float | None:
    """:func:`_start_time` on the candidates ``top _START_GRID`` [Pa^2] (``top`` <= the
    loads' ``tau_max``), or None where some load's window holds a wall at the first."""
    pb = pbs[0]
    lo = pb.lower  # (a table's wall scanned in one compiled call)
    if scan and lower and pb.upper is None and lo.table is not None and callable(lo.position):
        p0 = np.array([p.p0 for p in pbs], dtype=float)
        t = float(scan(*lo.table.args(), _START_GRID, top, float(k), p0))
        return None if t < 0.0 else t
    cand = top * _START_GRID
    ks = k * np.sqrt(2.0 * cand)
    lo, up = pb.lower.at(cand), None if pb.upper is None else pb.upper.at(cand)
    starts = [_first_start(p.p0, cand, ks, lo, up, top, lower) for p in pbs]
    return None if any(t is None for t in starts) else min(starts)  # type: ignore[type-var]


def _first_start(
    p0: float, cand: Array, ks: Array, lo: Array, up: Array | None, top: float, lower: bool
) -> float | None:
    """:func:`_start_time` of the load ``p0`` [Pa] from the walls ``lo``, ``up`` [Pa] (None:
    no upper wall) at the candidate times ``cand`` [Pa^2] (``ks = k sqrt(2 cand)``): ``top``
    [Pa^2], the round's largest candidate, where no wall reaches the window; None where the
    window holds a wall already at the first candidate."""
    ok = None if up is None else up >= p0 + ks
    if lower:
        ok = lo <= p0 - ks if ok is None else ok & (lo <= p0 - ks)
    if ok is None or np.count_nonzero(ok) == ok.size:
        return top
    first = int(ok.argmin())
    if first == 0:
        return None
    return float(cand[first - 1]) * 0.5


def _exact_start(pbs: list[Problem], k: float, tau_s: float) -> tuple[float, float | None]:
    """The one-wall start: ``(tau_w, wall)`` when the only wall is absorbing, moving, and
    declared at rest [Pa] (``Wall.still_until``) up to ``tau_w > tau_s`` [Pa^2]: up to
    ``tau_w`` every load is the one-wall closed form (the image solution), exact, and the
    march starts there; else ``(tau_s, None)`` (also when densities are wanted: the analytic
    start's are the free Gaussian's).  A fixed wall is marched as before: ``auto`` gives it
    the closed form, and ``method="cn"`` asks for the march.

    Not with an upper wall: started where a yield wall enters the window, the march's first
    steps (a coarse image state, then the window's kink) cost more than marching the
    fixed-wall stretch (measured on the plastic roll-off scenes of benchmarks/summary.py)."""
    pb = pbs[0]
    lo = pb.lower
    if pb.p_out is not None or pb.upper is not None or lo is None or lo.kind != "absorbing":
        return tau_s, None
    t_w = 0.0 if lo.is_fixed else min(lo.still_until, pb.tau_max)
    if not t_w > tau_s:
        return tau_s, None
    return t_w, float(lo.at(np.zeros(1))[0])


def _level_times(
    base: Array,
    nsub: int,
    n_ie: int,
    zones: tuple[tuple[float, float], ...] = (),
    fast: Callable[..., None] | None = None,
) -> tuple[Array, Array]:
    """Nested refinement of ``base`` plus Rannacher halves; returns (times, theta per step).

    Inside a graded zone ``(tau_b, tau_e)`` the steps are subdivided uniformly in
    ``(tau - tau_b)^(1/4)`` and the step starting at ``tau_b`` is implicit Euler (the wall's
    speed may be unbounded there).  ``fast``: the compiled loop
    :func:`._cn_edges.level_times` (the same numbers), also where no zone grades (:func:`_grades`).
    """
    size = (base.size - 1) * nsub + 1
    n_ie = min(n_ie, size - 1)
    t, theta = np.empty(size + n_ie), np.empty(size + n_ie - 1)
    if fast is not None and not _grades(base, nsub, zones):
        fast(base, nsub, n_ie, t, theta)
    else:
        _subdivided(base, nsub, n_ie, zones, t)
        theta[: 2 * n_ie] = 1.0
        theta[2 * n_ie :] = 0.5
    if zones:
        theta[_is_in(t[:-1], [tb for tb, _ in zones])] = 1.0
    return t, theta


def _subdivided(
    base: Array, nsub: int, n_ie: int, zones: tuple[tuple[float, float], ...], t: Array
) -> None:
    """The times of :func:`_level_times` into ``t``: the subdivided sequence from ``t[n_ie]``
    on, its first ``n_ie`` steps halved into ``t[:2 n_ie]`` (what sorting the union gives)."""
    a, b = base[:-1], base[1:]
    frac = np.arange(nsub) / nsub
    sub = t[n_ie:-1].reshape(a.size, nsub)
    np.add(a[:, None], (b - a)[:, None] * frac[None, :], out=sub)
    for tb, te in zones:
        m = (a >= tb) & (b <= te)
        if nsub > 1 and np.count_nonzero(m):
            ua, ub = (a[m] - tb) ** (1 / _GRADE), (b[m] - tb) ** (1 / _GRADE)
            sub[m] = tb + (ua[:, None] + (ub - ua)[:, None] * frac[None, :]) ** _GRADE
            sub[m, 0] = a[m]
    t[-1] = base[-1]
    if n_ie > 0:
        head = t[n_ie : 2 * n_ie + 1].copy()  # (the halves overwrite it)
        t[: 2 * n_ie : 2], t[1 : 2 * n_ie : 2] = head[:-1], 0.5 * (head[:-1] + head[1:])


def _grades(base: Array, nsub: int, zones: tuple[tuple[float, float], ...]) -> bool:
    """Whether :func:`_level_times` subdivides a step of ``base`` [Pa^2] in a graded zone."""
    if nsub == 1 or not zones:
        return False
    a, b = base[:-1], base[1:]
    return any(((a >= tb) & (b <= te)).any() for tb, te in zones)


def _probe_times(wall, tau: Array) -> tuple[Array, Array] | None:
    """Times ``(tau + h, tau - h)`` [Pa^2] of the central differences of :func:`_wall_speeds`
    (at the last time ``(tau - 2 h, tau - h)``: a backward difference, see there), or None
    where the speed needs none (fixed wall, declared speed or linear motion)."""
    if not _differenced(wall):
        return None
    h = 1e-5 * tau
    bp = getattr(wall, "breakpoints", ())
    if bp:
        # never difference across a breakpoint: the step shrinks with the distance to it
        b = np.asarray(bp)
        dist = np.min(np.abs(tau[..., None] - b), axis=-1)
        h = np.where(dist > 0, np.minimum(h, 1e-3 * dist), h)
        # (at least 64 ulp: closer than that the two probes would be one time)
        h = np.maximum(h, 64.0 * np.finfo(float).eps * np.abs(tau))
    hi = tau + h
    if tau.size:
        hi[-1] = tau[-1] - 2.0 * h[-1]
    return hi, tau - h


def _wall_speeds(
    wall,
    tau: Array,
    probed: tuple[Array, Array] | None = None,
    p_end: float | None = None,
    probe: tuple[Array, Array] | None = None,
    p_tau: Array | None = None,
) -> tuple[Array, Array]:
    """dp_w/dtau [1/Pa] of a wall at ``tau`` just before and just after (declared, or by central
    differences).

    The two differ only at the wall's declared breakpoints, where the difference is one-sided
    (the speed just before ends a step, the speed just after starts one).  At the last time
    the speed is the backward three-point difference: a wall need not be defined past the end
    of the sequence (a clock clipped at ``zeta_max`` stops it there, and a central difference
    then gives half the speed: a first-order error at the last output, which no Richardson
    combination cancels).  ``probed``: the wall's positions at the times of
    :func:`_probe_times` (``probe``, computed here unless given), ``p_end`` its position at
    ``tau[-1]`` (evaluated here unless given), ``p_tau`` its positions at ``tau`` (used at
    the breakpoints; evaluated there unless given).
    """
    if wall is None or wall.is_fixed:
        z = np.zeros_like(tau)
        return z, z
    if wall.dposition is not None:
        v = wall.speed(tau)
        return v, v
    if wall.motion is not None:
        v = np.full_like(tau, wall.motion[1])
        return v, v
    hi, lo = _probe_times(wall, tau) if probe is None else probe
    if probed is None:
        p = wall.at(np.concatenate([hi, lo, tau[-1:]]))  # one call of the wall
        probed, p_end = (p[: tau.size], p[tau.size : -1]), float(p[-1])
    p_hi, p_lo = probed
    v = (p_hi - p_lo) / (hi - lo)
    if tau.size:  # backward: (3 p(t) - 4 p(t - h) + p(t - 2 h)) / 2 h
        v[-1] = (3.0 * p_end - 4.0 * p_lo[-1] + p_hi[-1]) / (2.0 * (tau[-1] - lo[-1]))
    before, after = v, v
    bp = getattr(wall, "breakpoints", ())
    at_bp = _is_in(tau, bp)
    if np.count_nonzero(at_bp):
        t = tau[at_bp]
        p_t = wall.at(t) if p_tau is None else p_tau[at_bp]
        before, after = v.copy(), v.copy()
        before[at_bp] = (p_t - p_lo[at_bp]) / (t - lo[at_bp])
        after[at_bp] = (p_hi[at_bp] - p_t) / (hi[at_bp] - t)
    return before, after


def _track_wall(
    wall, mid: Array, taus: Array, fast: tuple | None = None
) -> tuple[Array, Array, Array, Array]:
    """A wall's positions [Pa] at ``mid`` and ``taus`` and its speeds [1/Pa] just before / after
    each of ``taus``, from one call of the wall (+inf and 0 without a wall); ``fast``: the
    compiled :func:`._cn_edges.wall_query` and :func:`._cn_edges.wall_track` (the same
    numbers)."""
    if wall is None:  # (read-only inputs of the window: the positions at mid a view)
        z = np.zeros(taus.size)
        inf = np.empty(taus.size)
        inf.fill(np.inf)  # (np.full's Python costs ~0.7 us)
        return inf[:-1], inf, z, z
    if fast is not None and _differenced(wall):
        fns = None if wall.table is None else table_kernels()
        return compiled_track(wall, mid, taus, fast, None if fns is None else fns[2])
    probe = _probe_times(wall, taus)
    if probe is None:
        p = wall.at(np.concatenate([mid, taus]))
        return p[: mid.size], p[mid.size :], *_wall_speeds(wall, taus)
    # in time order (probe below, time, probe above, midpoint, ...): the wall's table lookups
    # then start next to the last one (the positions are the same, point by point)
    q = np.empty(4 * taus.size - 1)
    q[0::4], q[1::4], q[2::4], q[3::4] = probe[1], taus, probe[0], mid
    p = wall.at(q)
    at_t = np.ascontiguousarray(p[1::4])
    probed = (p[2::4], p[0::4])
    vb, va = _wall_speeds(wall, taus, probed, float(at_t[-1]), probe, at_t)
    return np.ascontiguousarray(p[3::4]), at_t, vb, va


def _tracks(pb: Problem, taus: Array, fast: tuple | None = None) -> dict:
    """The walls along a time sequence (shared by the loads of a batch): positions [Pa] at the
    step midpoints and at ``taus``, speeds [1/Pa] just before / after each time (one call of
    each wall)."""
    mid = 0.5 * (taus[:-1] + taus[1:])
    lo_m, lo, lo_vb, lo_va = _track_wall(pb.lower, mid, taus, fast)
    up_m, up, up_vb, up_va = _track_wall(pb.upper, mid, taus, fast)
    ys = pb.upper.speed(taus) if pb.upper is not None else up_vb  # (zeros without one)
    return {
        "mid": mid,
        "lo_m": lo_m,
        "up_m": up_m,
        "lo": lo,
        "up": up,
        "lo_vb": lo_vb,
        "lo_va": lo_va,
        "up_vb": up_vb,
        "up_va": up_va,
        "ys": ys,
    }


def _edges(pb: Problem, plan: _Plan, taus: Array, tr: dict | None = None) -> dict:
    """Window edges and their speeds at the start (a) and end (b) of every step.

    The regime of each edge (real wall or artificial edge ``p0 -/+ k sqrt(2 tau)``) is fixed per
    step (at its midpoint; a yield wall stays real once in, unless ``plan.release``); its kinks
    are step boundaries.  ``tr``: the walls along ``taus`` (:func:`_tracks`), or computed."""
    if tr is None:
        tr = _tracks(pb, taus)
    k, p0 = plan.k, pb.p0
    mid = tr["mid"]
    s_m = np.sqrt(2.0 * mid)
    rl = tr["lo_m"] >= p0 - k * s_m
    if plan.yield_wall and not plan.release:
        ru = np.logical_or.accumulate(tr["up_m"] <= p0 + k * s_m)
    else:
        ru = tr["up_m"] <= p0 + k * s_m
    out = {"rl": rl, "ru": ru}
    # the artificial edges and their speeds at every time, once (pointwise: sliced per end)
    s = np.sqrt(2.0 * taus)
    ds = 1.0 / s
    art = (p0 - k * s, p0 + k * s, -k * ds, k * ds)
    for tag, sl in (("a", slice(None, -1)), ("b", slice(1, None))):
        lo, up = tr["lo"][sl], tr["up"][sl]
        lo_v, up_v = tr["lo_v" + tag][sl], tr["up_v" + tag][sl]
        le = np.where(rl, lo, art[0][sl])
        ue = np.where(ru, up, art[1][sl])
        out["l" + tag] = le
        out["w" + tag] = ue - le
        out["lv" + tag] = np.where(rl, lo_v, art[2][sl])
        out["wv" + tag] = np.where(ru, up_v, art[3][sl]) - out["lv" + tag]
        out["ys" + tag] = (
            np.where(ru, tr["ys"][sl], 0.0) if plan.yield_wall else np.zeros(taus.size - 1)
        )
    # from the first breakpoint on, the mesh moves with the chord speeds of each step (the
    # exact displacement of the edges: the wall may move like sqrt(tau - tau_b), whose point
    # speeds are unbounded and made the scheme first order; after the graded stretch the chord
    # speeds also keep the Richardson control's error expansion clean)
    chord = np.zeros(mid.shape, bool)
    if plan.chord_from < math.inf:
        chord |= taus[:-1] >= plan.chord_from
    if np.count_nonzero(chord):
        dt = np.diff(taus)
        lvc = (out["lb"] - out["la"]) / dt
        wvc = (out["wb"] - out["wa"]) / dt
        for tag in ("a", "b"):
            out["lv" + tag] = np.where(chord, lvc, out["lv" + tag])
            out["wv" + tag] = np.where(chord, wvc, out["wv" + tag])
    out["chord"] = chord
    return out


def _faces(x: Array) -> tuple[Array, Array, Array]:
    """Face midpoints, node spacings and trapezoid weights (control volumes) of ``x``."""
    w = np.zeros_like(x)
    d = np.diff(x)
    w[:-1] += d / 2
    w[1:] += d / 2
    return 0.5 * (x[1:] + x[:-1]), d, w


class Edge(NamedTuple):
    """The window's edges at one end of every step, per load: arrays ``(loads, steps)``.

    The nodes are ``p_j = lower + width x_j`` [Pa] (``x_j`` in [0, 1], see
    :func:`._grid.clustered`).
    """

    lower: Array
    """Lower edge ``l`` [Pa]: the real lower wall, or the artificial edge ``p0 - k sqrt(2 tau)``."""
    width: Array
    """Window width ``W`` = upper edge - lower edge [Pa]."""
    lower_speed: Array
    """``dl/dtau`` [1/Pa] (the chord speed of the step from the first breakpoint on)."""
    width_speed: Array
    """``dW/dtau`` [1/Pa] (idem)."""
    yield_speed: Array
    """``dY/dtau`` [1/Pa] of a real yield wall (0 elsewhere and without one)."""


class Window(NamedTuple):
    """The window of one grid level along its steps, per load (see :func:`_edges`)."""

    real_lower: Array
    """``(loads, steps)`` bool: the lower edge is the real wall during the step."""
    real_upper: Array
    """``(loads, steps)`` bool: the upper edge is the real wall during the step."""
    start: Edge
    """The edges at the start of every step."""
    end: Edge
    """The edges at the end of every step."""
    chord: Array
    """``(loads, steps)`` bool: the speeds are the chord speeds of the step."""


def _edges_batch(
    pbs: list[Problem],
    plan: _Plan,
    taus: Array,
    fast: Callable[..., None] | None = None,
    tracks: tuple | None = None,
) -> Window:
    """The window of the loads ``pbs`` (which share their walls) along ``taus`` [Pa^2] (by
    the compiled loop ``fast``, :func:`._cn_edges.window_edges`, if given, and the walls'
    tracks by ``tracks``, :func:`._cn_edges.wall_query` and ``wall_track``: the same
    numbers)."""
    tr = _tracks(pbs[0], taus, tracks)  # the loads of a batch share their walls
    if fast is not None:
        out, flags = compiled_window(fast, pbs, plan, taus, tr)
        start = Edge(out[0], out[1], out[4], out[5], out[6])
        end = Edge(out[2], out[3], out[7], out[8], out[9])
        return Window(flags[0], flags[1], start, end, flags[3])
    eds = [_edges(pb, plan, taus, tr) for pb in pbs]
    if len(eds) == 1:
        ed = {key: val[None] for key, val in eds[0].items()}
    else:
        ed = {key: np.stack([e[key] for e in eds]) for key in eds[0]}
    start, end = (
        Edge(ed["l" + t], ed["w" + t], ed["lv" + t], ed["wv" + t], ed["ys" + t]) for t in "ab"
    )
    return Window(ed["rl"], ed["ru"], start, end, ed["chord"])


def _joint_plan(pbs: list[Problem], k: float, per_decade: float, tau_s: float,
                kinks: list[float] | None = None, fast: Callable[..., tuple] | None = None,
                ) -> _Plan:  # fmt: skip
    """One time schedule for a batch of loads: common analytic start, all kinks (the times
    where a real wall enters or leaves the window; found here unless given); ``fast``:
    :func:`._cn_lean.plan_base` compiled (the same plan)."""
    pb = pbs[0]
    outs = pb.tau[pb.tau > tau_s]
    yield_wall = pb.upper is not None and not pb.upper.acts_absorbing
    if outs.size == 0:
        return _Plan(np.array([tau_s]), np.zeros(0, int), tau_s, k, yield_wall)
    per_decade = max(per_decade, 4.0)
    decades = math.log10(outs[-1] / tau_s)
    n_geo = max(1, int(math.ceil(decades * per_decade)))
    geo = tau_s * _decades(decades, n_geo + 1)
    if kinks is None:
        kinks = kinks_apart(_switch_times_batch(pbs, k, tau_s, float(outs[-1])), outs)
    ratio = 10 ** (1.0 / per_decade) - 1.0
    zones, graded = _graded_zones(pbs, tau_s, float(outs[-1]), ratio)
    chord = _chord_from(pb, tau_s, zones)
    if fast is not None:  # (the rest in one compiled call)
        zs = np.array(zones, dtype=float).reshape(-1, 2) if zones else _NO_ZONES
        kk = np.array(kinks, dtype=float)
        base, index = fast(geo, outs, kk, graded, ratio, zs, tau_s)
        return _Plan(base, index, tau_s, k, yield_wall, zones, outs=outs, chord_from=chord)
    fixed = sorted_unique(np.concatenate([outs, np.asarray(kinks, dtype=float), graded]))
    # the geometric times far from every fixed one (relative gap 0.3 ratio)
    keep = (np.abs(geo[:, None] - fixed[None, :]) > (0.3 * ratio) * fixed).all(axis=1)
    for tb, te in zones:
        keep &= (geo <= tb) | (geo >= te)
    keep[0] = True
    base = sorted_unique(np.concatenate([geo[keep & (geo < outs[-1])], fixed]))
    base = base[base >= tau_s]
    index = np.searchsorted(base, outs)
    return _Plan(base, index, tau_s, k, yield_wall, zones, outs=outs, chord_from=chord)
