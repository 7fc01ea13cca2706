"""The window's edges and the time steps of a ``cn`` level, each in one compiled loop (the
compiled path's :func:`._cn_plan._edges` and :func:`._cn_plan._level_times`).

:func:`._cn_plan._edges` computes, per load, the regime of each edge (real wall or artificial
edge ``p0 -/+ k sqrt(2 tau)``) at every step's midpoint, the edges and their speeds at the start
and end of every step, and from the first declared breakpoint on the chord speeds: about forty
numpy calls per load and level, most of a small level's set-up. :func:`window_edges` does the
same elementwise arithmetic in the same order (the results are bit for bit the numpy path's:
no sums, one rounding per operation, tested), for all loads at once, from the walls' tracks
(:func:`._cn_plan._tracks`, evaluated in Python: the walls are the caller's callables, or
in one compiled call where a wall carries a table, :func:`compiled_track`).
:func:`level_times` is the same for the level's time steps (:func:`._cn_plan._level_times`
without graded zones: their ``pow`` stays numpy's, which a compiled ``pow`` need not equal).
Units: tau in Pa^2, pressures in Pa, speeds in 1/Pa.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

__all__ = [
    "compiled_track",
    "compiled_window",
    "level_times",
    "wall_query",
    "wall_track",
    "window_edges",
]


def compiled_window(
    fn: Callable[..., None], pbs: list, plan: Any, taus: Any, tr: dict
) -> tuple[Any, Any]:
    """The window of the loads ``pbs`` along ``taus`` [Pa^2] from the walls' tracks ``tr``
    (:func:`._cn_plan._tracks`), by ``fn`` (:func:`window_edges`, compiled or as Python):
    ``(out, flags)`` of :func:`window_edges` (what :func:`._cn_plan._edges_batch` gives, bit
    for bit, as rows)."""
    n, nb = taus.size - 1, len(pbs)
    chord_from = plan.chord_from
    out, flags = np.empty((10, nb, n)), np.empty((4, nb, n), dtype=bool)
    p0 = np.array([pb.p0 for pb in pbs], dtype=float)
    sticky = bool(plan.yield_wall and not plan.release)
    fn(p0, float(plan.k), bool(plan.yield_wall), sticky, float(chord_from), taus, tr["mid"],
       tr["lo_m"], tr["up_m"], tr["lo"], tr["up"], tr["lo_va"], tr["lo_vb"], tr["up_va"],
       tr["up_vb"], tr["ys"], out, flags)  # fmt: skip
    return out, flags


def compiled_track(
    wall: Any, mid: Any, taus: Any, fast: tuple, table_track: Callable[..., None] | None
) -> tuple[Any, ...]:
    """:func:`._cn_plan._track_wall` of a wall whose speeds are differenced, by ``fast``
    (the compiled :func:`wall_query` and :func:`wall_track`) around one call of the wall, or
    by one compiled call of ``table_track`` (:func:`._wall_table.table_track`, given where the
    wall carries a table): positions [Pa] at ``mid`` and ``taus`` [Pa^2], speeds [1/Pa]
    before / after each time."""
    query, track = fast
    n = taus.size
    bp = np.asarray(getattr(wall, "breakpoints", ()), dtype=float)
    at_mid, at_t, vb, va = np.empty(n - 1), np.empty(n), np.empty(n), np.empty(n)
    if table_track is not None:  # the wall's table: query, positions and track in one call
        table_track(*wall.table.args(), taus, mid, bp, at_mid, at_t, vb, va)
        return at_mid, at_t, vb, va
    hi, lo, q = np.empty(n), np.empty(n), np.empty(4 * n - 1)
    query(taus, mid, bp, hi, lo, q)
    track(wall.at(q), taus, hi, lo, bp, at_mid, at_t, vb, va)
    return at_mid, at_t, vb, va


ROWS = ("la", "wa", "lb", "wb", "lva", "wva", "ysa", "lvb", "wvb", "ysb")
"""The rows of :func:`window_edges`'s float output: lower edge and width at the start (a) and
end (b) of every step, then the speeds and the yield wall's speed at each end."""


def window_edges(  # noqa: PLR0913 - the tracks as _cn_plan._tracks holds them
    p0: Any,
    k: float,
    yield_wall: bool,
    sticky: bool,
    chord_from: float,
    taus: Any,
    mid: Any,
    lo_m: Any,
    up_m: Any,
    lo: Any,
    up: Any,
    lo_va: Any,
    lo_vb: Any,
    up_va: Any,
    up_vb: Any,
    ys_t: Any,
    out: Any,
    flags: Any,
) -> None:  # pragma: no cover - compiled (the numpy path is the reference)
    """The window of the loads ``p0`` (loads,) [Pa] along ``taus`` (steps + 1,) [Pa^2].

    The walls' tracks: positions at the step midpoints ``mid`` (``lo_m``, ``up_m``) and at
    ``taus`` (``lo``, ``up``; ``+inf`` without a wall), their speeds just after (``_va``) and
    before (``_vb``) each time and the yield wall's speed ``ys_t`` (0 without one);
    ``sticky``: a yield wall stays real once it entered (not where the plan releases it,
    ``_Plan.release``); ``chord_from`` the first breakpoint's time (``inf``: none), from
    which the speeds are the steps' chord speeds.  ``out`` (10, loads, steps) receives the
    rows :data:`ROWS`, ``flags`` (4, loads, steps) whether the lower wall, the upper wall
    is real in the step, whether the yield wall is, and whether the speeds are chords (the
    yield wall's flag is the upper one where it is a yield wall: the march's ``yreal``).
    """
    n = taus.shape[0] - 1
    for q in range(p0.shape[0]):
        p = p0[q]
        ru_prev = False
        for i in range(n):
            s_m = math.sqrt(2.0 * mid[i])
            rl = lo_m[i] >= p - k * s_m
            ru = up_m[i] <= p + k * s_m
            if sticky:
                ru = ru or ru_prev
                ru_prev = ru
            for end in range(2):
                t = i + end
                s = math.sqrt(2.0 * taus[t])
                ds = 1.0 / s
                le = lo[t] if rl else p - k * s
                ue = up[t] if ru else p + k * s
                if rl:
                    lv = lo_va[t] if end == 0 else lo_vb[t]
                else:
                    lv = -k * ds
                if ru:
                    wv = (up_va[t] if end == 0 else up_vb[t]) - lv
                else:
                    wv = k * ds - lv
                ys = ys_t[t] if (yield_wall and ru) else 0.0
                row = 2 * end
                out[row, q, i] = le
                out[row + 1, q, i] = ue - le
                out[4 + 3 * end, q, i] = lv
                out[5 + 3 * end, q, i] = wv
                out[6 + 3 * end, q, i] = ys
            chord = taus[i] >= chord_from
            if chord:
                dt = taus[i + 1] - taus[i]
                lvc = (out[2, q, i] - out[0, q, i]) / dt
                wvc = (out[3, q, i] - out[1, q, i]) / dt
                out[4, q, i], out[5, q, i] = lvc, wvc
                out[7, q, i], out[8, q, i] = lvc, wvc
            flags[0, q, i] = rl
            flags[1, q, i] = ru
            flags[2, q, i] = ru and yield_wall
            flags[3, q, i] = chord


def level_times(base: Any, nsub: int, n_ie: int, t: Any, theta: Any) -> None:
    """:func:`._cn_plan._level_times` without graded zones, into ``t`` and ``theta`` (sized
    by the caller: ``(base.size - 1) nsub + 1 + n_ie`` times, one step less), the same
    elementwise arithmetic (bit for bit): every step of ``base`` [Pa^2] subdivided ``nsub``
    times, then the first ``n_ie`` steps halved (implicit Euler, ``theta = 1``; the others
    Crank-Nicolson, 1/2)."""  # pragma: no cover - compiled (the numpy path is the reference)
    n_base = base.shape[0] - 1
    q = n_ie  # (the first n_ie times are interleaved with the halves below)
    for i in range(n_base):
        a = base[i]
        d = base[i + 1] - a
        for j in range(nsub):
            t[q] = a + d * (j / nsub)
            q += 1
    t[q] = base[n_base]
    for i in range(n_ie):  # t[n_ie + i] holds the i-th time of the subdivided sequence
        lo, hi = t[n_ie + i], t[n_ie + i + 1]
        t[2 * i] = lo
        t[2 * i + 1] = 0.5 * (lo + hi)
    for i in range(theta.shape[0]):
        theta[i] = 1.0 if i < 2 * n_ie else 0.5


def wall_query(taus: Any, mid: Any, bp: Any, hi: Any, lo: Any, q: Any) -> None:
    """:func:`._cn_plan._probe_times` into ``hi``, ``lo`` and the times a wall is asked at
    into ``q`` (4 times - 1: probe below, time, probe above, midpoint ``mid``, ...; the order
    of :func:`._cn_plan._track_wall`), the same elementwise arithmetic (bit for bit);
    ``bp`` the wall's breakpoints [Pa^2] (may be empty)."""  # pragma: no cover - compiled
    n = taus.shape[0]
    tiny = 64.0 * 2.220446049250313e-16  # (64 ulp of 1: numpy's finfo(float).eps)
    for i in range(n):
        t = taus[i]
        h = 1e-5 * t
        if bp.shape[0] > 0:
            dist = abs(t - bp[0])
            for j in range(1, bp.shape[0]):
                dist = min(dist, abs(t - bp[j]))
            if dist > 0:
                h = min(h, 1e-3 * dist)
            h = max(h, tiny * abs(t))
        hi[i] = t + h if i < n - 1 else t - 2.0 * h
        lo[i] = t - h
        q[4 * i], q[4 * i + 1], q[4 * i + 2] = lo[i], t, hi[i]
        if i < n - 1:
            q[4 * i + 3] = mid[i]


def wall_track(
    p: Any, taus: Any, hi: Any, lo: Any, bp: Any, at_mid: Any, at_t: Any, vb: Any, va: Any
) -> None:  # pragma: no cover - compiled (the numpy path is the reference)
    """:func:`._cn_plan._wall_speeds` from the wall's positions ``p`` at the times of
    :func:`wall_query`: the positions at the midpoints and at ``taus`` into ``at_mid``,
    ``at_t``, the speeds just before / after each time into ``vb``, ``va`` (central
    differences, the backward one at the last time, one-sided at the breakpoints ``bp``),
    the same elementwise arithmetic (bit for bit)."""
    n = taus.shape[0]
    for i in range(n):
        p_lo, p_t, p_hi = p[4 * i], p[4 * i + 1], p[4 * i + 2]
        at_t[i] = p_t
        if i < n - 1:
            at_mid[i] = p[4 * i + 3]
            v = (p_hi - p_lo) / (hi[i] - lo[i])
        else:
            v = (3.0 * p_t - 4.0 * p_lo + p_hi) / (2.0 * (taus[i] - lo[i]))
        vb[i], va[i] = v, v
        for j in range(bp.shape[0]):
            if taus[i] == bp[j]:
                vb[i] = (p_t - p_lo) / (taus[i] - lo[i])
                va[i] = (p_hi - p_t) / (hi[i] - taus[i])
                break
