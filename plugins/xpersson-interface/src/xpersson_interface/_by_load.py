"""Many loads through a table in the load (private): ``gap_pdf`` and ``leakage`` at a cost per
load that falls with the number of loads.

The direct path costs about 100 us per load (the dense re-solve of the curve, ``Phi``, the
detachment's sub-problem sums, 256 Gaussian sums per load for ``gap_pdf``, the effective
medium's cells for ``leakage``): 30 to 100 times the batched solve of the same loads at
1000-1e4 loads. Its outputs are smooth functions of the load (the area curve of a
``load_similar`` boundary depends on ``p0`` only through ``tau/p0^2``; each output is an
integral of it). So where the loads are :data:`DENSITY` times as many as the table's nodes
(and at least :data:`TABLE_MIN`; ``leakage``: :data:`LEAK_MIN` loads not sealed by both
theories, counted on those), only *node* loads are computed directly: a subset of the
requested loads about 1/:data:`PER_DECADE` decade apart in ``ln p0`` (the lowest and the
highest always among them; at least ``4 ORDER`` over the range). Every other load takes
each output from the Lagrange polynomial through the :data:`ORDER` nearest nodes in
``ln p0``, of the output's logarithm (near full contact the detached area falls
super-exponentially and its logarithm stays smooth in ``ln p0``; the gap density element by
element, floored at :data:`FLOOR`), or of a transform of it that removes a known
singularity (:data:`Weight`: ``leakage``'s ``u1`` near sealing, its effective medium where
it percolates; ``_leakage.table_weights``).

**Segments.** A stencil never crosses a change of regime: nodes are grouped into runs alike in
every *key* (an output never interpolated: the sealed flags, the piece of the spectrum that
``leakage``'s ``u1`` reaches) and in which outputs are regular (finite, positive); a load takes
its stencil from the segment of the two nodes around it (one-sided near the segment's ends),
a load between two segments has none. A load between two nodes alike in every output, none
of them regular (a sealed stretch), takes their values, whatever the segment's length (its
estimate: the noise).

**Groups**: :func:`._by_group.by_group` tables each group of outputs (:data:`LEAK_GROUPS`) with
segments of its own keys and nodes of its own (``leakage`` on roll-off spectra: the medium does
not see the junction's keys, and is not computed where only the junction needs it).

**The error, estimated per load.** The nodes at twice the spacing (the even ones) interpolate
the odd ones (each from the even nodes of its own segment, one-sided past the segment's last
even node); the largest relative error among the odd nodes of a load's stencil, times
``SAFETY 2^-ORDER`` (halving the spacing divides a smooth function's error by ``2^ORDER``;
:data:`SAFETY` = 16 keeps that margin), plus the direct path's own irregularity in the load
(:data:`NOISE`, ``leakage`` :data:`LEAK_NOISE`: no interpolation follows it) times one plus
the stencil's Lebesgue function (1.5 centred, up to 7 one-sided), is the load's estimate.
Errors are relative to the load's value (a row: its largest element), at least :data:`DEPTH`
of the largest over the loads (a gap density 1e-57 of the others, near full contact, is 0 to
that). The estimate is written per load (``gap_pdf_load_error``, ``leak_load_error``; 0: the
load was computed directly).

**Refinement.** Each run of loads whose estimate exceeds the tolerance (:data:`TOL`,
``leakage`` :data:`LEAK_TOL`), or that has no stencil, is tabled again between the nodes around
it at twice the density, up to :data:`MAX_DEPTH` times; a run whose nodes would be more than
half of its loads has those of its loads that miss the tolerance computed directly. Level by
level: the node loads of every run of one level are computed in one direct call (each call
has a fixed cost: ``leakage`` ~2.5 ms, ~28 loads' worth); a group's values that a call computed
without being asked for (:data:`COMPUTED`) are kept and answer a later level's ask without a
call. Loads whose direct values cost
nothing (``free``: ``leakage``'s loads sealed by both theories next to the open ones,
``_leakage.with_sealed``) or that the table would compute directly anyway, found only by
refinement (``leakage``'s loads near the junction's sealing: ``_first_level``) are nodes of
the first level: computed in the first call, and a change of keys there needs no refinement
to be found.

Measured against the direct path (``benchmarks/load_table_check.py``): ``gap_pdf`` on the 12
scenes of ``benchmarks/summary.py`` at 3000 and 1e4 loads within 2.0e-5 of each load's largest
density; ``leakage`` on those, 20 held-out scenes (``--seeds 37 38``) and the 12 of
``summary.py --held-out 2026`` (``--held-out 2026``) at 1000 loads within 4.7e-4 (0.40 of its
estimate) and at 1e4 loads within 1.4e-3, every interpolated load within 0.81 of its estimate
(``results/load_table_check_leakage_1000.json``, ``..._1e4.json``). Beyond the design
(``benchmarks/load_table_extreme.py``: 90 scenes, H 0.05-1, 3-9 decades, contact areas 1e-8 to
1 - 1e-12, 1000 loads): ``leakage`` within 0.49 of its estimate, ``gap_pdf`` on 88 within
it and 2.6 / 2.3 times it (4.1e-5 / 3.3e-5) on two 9-decade spectra near a contact area of
1e-7, where its density at ``u = 0`` wavers by ~1e-5 from load to load (beyond :data:`NOISE`:
those loads' drop from full contact is unresolved, ``plugins.solved.UNRESOLVED``, warned).
Outputs not smooth in the load are not tabled (``_params.UNTABLED``); a row rising above its
nodes or its interpolated maximum is refined (``_stencils.SPIKE``). Below the minimum every
load is computed directly, bit for bit.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable

import numpy as np
from numpy.typing import NDArray

from ._stencil_sums import chain
from ._stencils import (
    DEPTH,
    FLOOR,
    Weight,
    _errors,
    _interpolate,
    _logs,
    _Roles,
    _segments,
    _window_max,
)

__all__ = [
    "COMPUTED",
    "DENSITY",
    "DEPTH",
    "FLOOR",
    "LEAK_GROUPS",
    "LEAK_MIN",
    "LEAK_ORDERS",
    "LEAK_PER_DECADE",
    "LEAK_SAFETY",
    "LEAK_NOISE",
    "LEAK_TOL",
    "MAX_DEPTH",
    "NOISE",
    "ORDER",
    "PER_DECADE",
    "SAFETY",
    "TABLE_MIN",
    "TOL",
    "Weight",
    "by_load",
]

#: Loads from which the table may be used (fewer: every load computed directly).
TABLE_MIN = 64
#: The table is used where the loads are at least this many times its first level's nodes
#: (:data:`PER_DECADE` per decade of the loads' range, at least ``4 ORDER``): at 2 times every
#: load is computed directly anyway (the nodes would be more than half of a run's loads), at
#: 3 (150 loads over 3 decades) ``gap_pdf`` took 0.55-0.80 of the direct path's time on the
#: 24 scenes of ``benchmarks/summary.py`` and ``--held-out 2026``, every interpolated load
#: within 0.47 of its estimate (``benchmarks/load_table_check.py --loads 150 --held-out
#: 2026``). Up to 2026-11-30 the table started at 400 loads: 150-399 loads took 2.7-3x the
#: time of 500 (``gap_pdf`` 18-24x the bare solve at 200-350 loads, against ~9x at 400).
DENSITY = 3.0
#: Node loads per decade of ``p0`` (the spacing of the table).
PER_DECADE = 16
#: Points of each interpolating polynomial (degree ``ORDER - 1``).
ORDER = 8
#: Largest estimated relative error of an interpolated load; above it the region is refined.
TOL = 1e-4
#: Refinements of a region (each doubles its nodes per decade) before it is computed directly.
MAX_DEPTH = 4
#: The direct path's own irregularity in the load (relative; ``gap_pdf``: ``Phi``'s linear
#: look-up table), which no interpolation follows; a node's reaches a load through the
#: stencil's weights.
NOISE = 5e-6
#: The same for the leak analysis, from :data:`TABLE_MIN` loads on as ``gap_pdf``: directly,
#: its outputs are regular in the load to ~1e-7 (sixth differences at 500 loads per decade,
#: the 12 design scenes) except at features narrower than the table's spacing, which the
#: check at the nodes cannot see: a kink of ``u1`` (slope jumps of up to ~0.05 in
#: ``d ln(u1^3)/d ln p0``, e.g. at ``zeta_c = 1.64`` on a held-out roll-off H = 0.83 scene) and
#: the ringing of the area curve's spline just past a breakpoint of the spectrum (``zeta_c``
#: 1.04-1.08 times the roll-off). At 16 nodes per decade they cost up to 3e-4 beyond the
#: smooth estimate (held-out seeds 37 and 38: 1.28 of the estimate with 1e-5 here); 1e-4,
#: through the stencil (2.5e-4 centred), covers them (largest ratio 0.78 on 34 scenes).
#: ``LEAK_MIN``: loads not sealed by both theories (the sealed ones cost nothing directly)
#: from which the leak analysis is tabled: each direct call of the table costs ~2.5 ms, and
#: with fewer open loads the table took up to 1.6x the direct path's time (design scenes at
#: 150-1000 loads: 44-132 open loads 1.04-1.6x, 172 and more 0.27-0.87x).
LEAK_TOL, LEAK_NOISE, LEAK_MIN = 2e-3, 1e-4, 160
#: The leak analysis's stencils (points) and margin: its estimate is 4 times the error of the
#: table at twice the spacing (``LEAK_SAFETY 2^-8``), not that error scaled down by ``2^-8``
#: (the asymptotic rate, which the ripple and the kinks do not reach: with it the estimate fell
#: short 2-9x; with the error at twice the spacing alone, up to 3.9x on held-out scenes).
#: 8 points only (4 and 6 fell short 1.5x more often).
LEAK_ORDERS, LEAK_SAFETY = (8,), 4.0 * 2**8
LEAK_PER_DECADE = 16
#: The leak analysis's groups of outputs, each tabled with segments of its own keys: the
#: effective medium does not see the junction's keys (the piece of the spectrum ``u1``
#: reaches, the junction's sealing). Cut there too, its one-sided stencils amplified its
#: ripple (~2e-4) into check residuals of 1e-3 - 2e-2 at the junction's segment ends (the
#: roll-off, ``zeta_c > 0.3 zeta_max``): ~40 % of the loads refined at 32 per decade on
#: roll-off spectra, where its own error was 1e-5 - 1.5e-4 (``benchmarks/leakage_rolloff.py``).
LEAK_GROUPS = (
    frozenset({"leak_zeta_c", "leak_u1", "leak_flow_factor", "leak_rate", "leak_sealed", "piece"}),
    frozenset({"leak_flow_factor_emt", "leak_rate_emt", "leak_sealed_emt"}),
)
#: The smooth part of the estimate: this times ``2^-m`` the error of the ``m``-point table at
#: twice the spacing (asymptotically that error divided by ``2^m``: a margin of 16).
SAFETY = 16.0

Exact = Callable[[NDArray[np.intp]], dict[str, NDArray[np.float64]]]


def by_load(
    p0: NDArray[np.float64],
    exact: Exact,
    tol: float = TOL,
    keys: frozenset[str] = frozenset(),
    noise: float = NOISE,
    least: int = 0,
    orders: tuple[int, ...] = (ORDER,),
    safety: float = SAFETY,
    per_decade: float = PER_DECADE,
    weights: tuple[Weight, ...] = (),
    free: NDArray[np.bool_] | None = None,
) -> tuple[dict[str, NDArray[np.float64]], NDArray[np.float64]]:
    """The outputs of every load (``{name: (n_load, ...)}``) and the estimated error per load.

    ``exact(rows)`` gives the outputs of the loads ``p0[rows]`` computed directly (arrays with
    the loads along the first axis: per-load values or rows of them, all positive where
    regular); ``tol`` the largest estimated error of an interpolated load. ``keys`` names
    per-load outputs that are never interpolated (flags, the piece of a piecewise-smooth
    input a load lies on): a load takes their value where its whole stencil agrees on it,
    and is refined where not. ``noise``: the direct path's own irregularity in the load
    (relative), added to every estimate through the stencil's weights. ``least``: the
    distinct loads from which the table is used. ``orders``: the stencils (points) tried per
    load, the one of the smallest estimate taken (fewer points: a smaller Lebesgue function
    near a segment's ends, where the noise dominates); ``safety``: :data:`SAFETY`.
    ``weights``: outputs tabled transformed (:data:`Weight`; their error still measured on
    ``v``). ``free`` (per load): loads made nodes of the first level (their direct values
    cost (almost) nothing, or they would be computed directly anyway) (groups of outputs
    with nodes of their own: :func:`._by_group.by_group`).
    """
    p0 = np.asarray(p0, dtype=float)
    n = p0.size
    if not tabled(p0, least):
        return exact(np.arange(n)), np.zeros(n)
    xs, first, inverse = np.unique(np.log(p0), return_index=True, return_inverse=True)
    pre = np.zeros((1, xs.size), dtype=bool)
    if free is not None:
        pre[0, inverse[np.asarray(free, dtype=bool)]] = True
    out, err = _table(
        xs,
        lambda sel, _which: exact(first[sel]),
        (tol, noise, orders, safety),
        (keys, weights),
        per_decade,
        pre,
        (None,),  # one table of every output
    )
    return {k: v[inverse] for k, v in out.items()}, err[inverse]


def tabled(p0: NDArray[np.float64], least: int) -> bool:
    """Whether the loads ``p0`` [Pa] go through the table: at least ``least`` and
    :data:`TABLE_MIN` of them, all finite and positive, and :data:`DENSITY` times the table's
    first-level nodes over their range."""
    n = p0.size
    if n < max(least, TABLE_MIN) or not bool(np.all(np.isfinite(p0) & (p0 > 0.0))):
        return False
    decades = math.log10(float(p0.max()) / float(p0.min()))
    return n >= DENSITY * (max(PER_DECADE * decades, 4 * ORDER) + 1)


#: ``exact(rows, which)`` of :func:`_table`: the outputs of the loads ``rows``, ``which``
#: (n_group, n_rows) the groups each load is computed for (the other groups' outputs of a
#: load: any value, unread unless :data:`COMPUTED` names them).
Partial = Callable[[NDArray[np.intp], NDArray[np.bool_]], dict[str, NDArray[np.float64]]]
#: Optional entry of ``exact(rows, which)``'s result: per row, the groups (n_rows, n_group)
#: whose outputs it computed, asked for or not (``leakage``: a chunk's effective medium is
#: computed for every load of the chunk once most of them ask for it). Kept, a group's values
#: of a row not asked for serve a later level that asks for it, instead of a direct call
#: (the same operations on a batch of other loads: the same values up to round-off).
COMPUTED = "computed groups"
#: A group of outputs of :func:`_table`: their names, or None (every output).
Group = frozenset[str] | None


def own_roles(roles: _Roles, group: Group) -> _Roles:
    """The keys and weights of ``roles`` that belong to ``group`` (its segments: its own keys
    only; None: every output's)."""
    if group is None:
        return roles
    keys, weights = roles
    return keys & group, tuple(w for w in weights if w[0] <= group)


def _names(group: Group, outputs: Iterable[str]) -> list[str]:
    """The names of ``outputs`` (in their order) that belong to ``group`` (None: all)."""
    return [k for k in outputs if group is None or k in group]


class _Direct:
    """The loads computed directly, per group of outputs, each once: the rows asked for at one
    refinement level are computed in one call of ``exact`` (its fixed cost, the dense
    re-solve and the splines, is paid once per level, not once per refined run). A group's
    values that a call computed without being asked (:data:`COMPUTED`) are kept and serve a
    later level's ask (no call where they serve every row)."""

    def __init__(self, exact: Partial, n: int, groups: tuple[Group, ...]) -> None:
        self.exact, self.n, self.groups = exact, n, groups
        self.done = np.zeros((len(groups), n), dtype=bool)
        self.pending = np.zeros((len(groups), n), dtype=bool)
        self.vals: dict[str, NDArray[np.float64]] = {}
        self.kept = np.zeros((len(groups), n), dtype=bool)  # (values in kept_vals)
        self.kept_vals: dict[str, NDArray[np.float64]] = {}

    def need(self, g: int, rows: NDArray[np.intp]) -> None:
        self.pending[g, rows] = True

    def run(self) -> None:
        ask = self.pending & ~self.done
        self.pending[:] = False
        ask = self._serve(ask)
        rows = np.flatnonzero(ask.any(axis=0))
        if not rows.size:
            return
        which = ask[:, rows]
        got = dict(self.exact(rows, which))
        computed = got.pop(COMPUTED, None)
        self._store(self.vals, got, rows, which)
        self.done[:, rows] |= which
        if computed is not None:  # computed, not asked: kept for a later level
            more = np.asarray(computed, dtype=bool).T & ~which
            self._store(self.kept_vals, got, rows, more)
            self.kept[:, rows] |= more

    def _store(
        self,
        into: dict[str, NDArray[np.float64]],
        got: dict[str, NDArray[np.float64]],
        rows: NDArray[np.intp],
        which: NDArray[np.bool_],
    ) -> None:
        """Each group's outputs of ``got`` at the rows ``rows[which[g]]`` into ``into``."""
        for k, v in got.items():
            if k not in into:
                into[k] = np.full((self.n,) + v.shape[1:], np.nan)
        for g, names in enumerate(self.groups):
            sel = which[g]
            if not sel.any():
                continue
            every = bool(sel.all())  # (no selection to copy)
            at = rows if every else rows[sel]
            for k in _names(names, got):
                into[k][at] = got[k] if every else got[k][sel]

    def _serve(self, ask: NDArray[np.bool_]) -> NDArray[np.bool_]:
        """The asks ``ask`` (n_group, n) that kept values answer, answered (their values
        taken, the rows done); the others returned."""
        have = ask & self.kept
        if not have.any():
            return ask
        self._store(self.vals, self.kept_vals, np.arange(self.n), have)
        self.done |= have
        return ask & ~have


def _table(
    xs: NDArray[np.float64],
    exact: Partial,
    tol: tuple[float, float, tuple[int, ...], float],
    roles: _Roles,
    per_decade: float,
    pre: NDArray[np.bool_],
    groups: tuple[Group, ...],
) -> tuple[dict[str, NDArray[np.float64]], NDArray[np.float64]]:
    """:func:`by_load` on the sorted distinct ``xs = ln p0`` (``tol``: the tolerance, the noise,
    the orders and the safety), a table per group of outputs (``groups``; ``(None,)``: one
    table of every output), each with nodes, estimates and refinement of its own: the table
    at ``per_decade`` nodes, each run of loads whose estimate exceeds the tolerance again at
    twice the density (between the nodes around it), at most :data:`MAX_DEPTH` times;
    directly where the nodes would be more than half of the loads (those whose estimate
    already meets the tolerance keep it). Level by level: the node loads of every group and
    run of a level in one direct call; ``pre`` (n_group, n): each group's nodes of the first
    level besides. A load's estimate is the largest over the groups (0 where computed for
    every group)."""
    n_g = len(groups)
    direct = _Direct(exact, xs.size, groups)
    tabled: dict[str, NDArray[np.float64]] = {}
    err = np.full((n_g, xs.size), np.inf)
    m = max(tol[2])
    regions = [[(0, xs.size - 1)] for _ in groups]
    own = [own_roles(roles, g) for g in groups]
    for depth in range(MAX_DEPTH + 2):
        plans = []
        for g in range(n_g):
            for lo, hi in regions[g]:
                sub = np.arange(lo, hi + 1)
                # at least 4 m nodes over the run's range (a narrow one: denser than per_decade)
                h = min(math.log(10.0) / per_decade, (xs[hi] - xs[lo]) / (4 * m))
                nodes = _nodes(xs[sub], h)
                if depth > MAX_DEPTH or nodes.size < 2 * m or 2 * nodes.size > sub.size:
                    direct.need(g, sub[err[g, sub] > tol[0]])
                else:
                    if not depth:  # (the first level: one run, every load)
                        nodes = np.flatnonzero(_mark(nodes, xs.size) | pre[g])
                    direct.need(g, sub[nodes])
                    plans.append((g, sub, nodes))
        direct.run()
        regions = [[] for _ in groups]
        for g, sub, nodes in plans:
            at = {k: direct.vals[k][sub[nodes]] for k in _names(groups[g], direct.vals)}
            xn = xs[sub[nodes]]
            keep = np.ones(sub.size, dtype=bool)
            keep[nodes] = False
            rest = np.flatnonzero(keep)  # the loads of the run that are not nodes
            vals, est = _one_group(xn, at, _logs(at, own[g], xn), xs[sub[rest]], own[g], tol)
            for k, v in vals.items():
                if k not in tabled:
                    tabled[k] = np.full_like(direct.vals[k], np.nan)
                tabled[k][sub[rest]] = v
            err[g, sub[rest]] = est
            regions[g] += [(sub[a], sub[b]) for a, b in _runs(rest[est > tol[0]], nodes)]
        per_decade *= 2
        if not any(regions):
            break
    err[direct.done] = 0.0
    out = {}
    last = {k: g for g, names in enumerate(groups) for k in _names(names, direct.vals)}
    for g, names in enumerate(groups):  # a load computed for a group: its own values
        done = direct.done[g]
        for k in _names(names, direct.vals):
            if k not in tabled:
                o = np.full_like(direct.vals[k], np.nan)
            else:  # the table's array itself where no later group reads it (no copy)
                o = tabled.pop(k) if last[k] == g else tabled[k].copy()
            o[done] = direct.vals[k][done]
            out[k] = o
    return out, err.max(axis=0)


def _one_group(
    xn: NDArray[np.float64],
    at: dict[str, NDArray[np.float64]],
    logs: dict[str, NDArray[np.float64]],
    x: NDArray[np.float64],
    roles: _Roles,
    tol: tuple[float, float, tuple[int, ...], float],
) -> tuple[dict[str, NDArray[np.float64]], NDArray[np.float64]]:
    """The outputs at ``x`` and their estimated error, per load from the order (of
    ``tol[2]``) of the smallest estimate: ``2^-m tol[3]`` (:data:`SAFETY`) times the error of the
    ``m``-point table at twice the spacing (the smooth part: ``~h^m``), plus the nodes' and
    the load's own irregularity ``tol[1]`` through the stencil (its Lebesgue function, 1.5
    centred, up to 7 one-sided for 8 points; inf where the load has no stencil)."""
    out: dict[str, NDArray[np.float64]] = {}
    best = np.full(x.size, np.inf)
    seg = _segments(at, roles[0])  # the nodes' segments, once for every order and stencil
    for m in tol[2]:
        check = _check(xn, at, logs, roles, m, seg)  # (n_node,): the 2h error at the odd nodes
        vals, bad, lebesgue, idx, flat = _interpolate(xn, at, logs, x, roles, m, (seg, None))
        est = _window_max(check, idx) * (tol[3] / 2**m) + tol[1] * (1.0 + lebesgue)
        est[bad] = np.inf
        est[flat] = tol[1]  # exact (stated: the noise, > 0: not computed directly)
        take = est < best if out else np.ones(x.size, dtype=bool)
        for k, v in vals.items():
            out[k] = (
                v
                if k not in out
                else np.where(take.reshape((-1,) + (1,) * (v.ndim - 1)), v, out[k])
            )
        best = np.where(take, est, best)
    return out, best


def _runs(flagged: NDArray[np.intp], nodes: NDArray[np.intp]) -> list[tuple[int, int]]:
    """The runs of consecutive ``flagged`` loads (only nodes between them), each as the
    nodes around it ``(first, last)``."""
    if not flagged.size:
        return []
    pos = np.searchsorted(nodes, flagged)  # the node above each flagged load
    split = np.flatnonzero(np.diff(flagged) - np.diff(pos) != 1) + 1
    first = nodes[pos[np.concatenate(([0], split))] - 1]
    last = nodes[pos[np.concatenate((split - 1, [flagged.size - 1]))]]
    return list(zip(first.tolist(), last.tolist(), strict=True))


def _mark(i: NDArray[np.intp], n: int) -> NDArray[np.bool_]:
    """Per position ``0 .. n-1``: whether it is one of ``i``."""
    out = np.zeros(n, dtype=bool)
    out[i] = True
    return out


def _nodes(xs: NDArray[np.float64], h: float) -> NDArray[np.intp]:
    """Indices of sorted ``xs`` about ``h`` apart: each node the last value within ``h`` of
    the one before (at least the next), the last value always included."""
    compiled = chain(xs, h)  # (the same nodes)
    if compiled is not None:
        return compiled
    last = xs.size - 1
    # each value's successor node, for every value at once (one search, not one per node)
    nxt = np.searchsorted(xs, xs + h, side="right") - 1
    nxt = np.minimum(np.maximum(nxt, np.arange(1, xs.size + 1)), last).tolist()
    out = [0]
    while out[-1] < last:
        out.append(nxt[out[-1]])
    return np.asarray(out, dtype=np.intp)


def _check(
    xn: NDArray[np.float64],
    at: dict[str, NDArray[np.float64]],
    logs: dict[str, NDArray[np.float64]],
    roles: _Roles,
    m: int = ORDER,
    seg: NDArray[np.intp] | None = None,
) -> NDArray[np.float64]:
    """Per node: the relative error of the even nodes' ``m``-point table at the node (odd
    nodes; 0 at the even ones), the largest over the outputs (inf where unusable). ``seg``:
    the nodes' segments (:func:`._stencils._segments` of ``at``), where known."""
    odd = np.arange(1, xn.size, 2)
    even = np.arange(0, xn.size, 2)
    sub = {k: v[::2] for k, v in at.items()}  # (views: the values of the even nodes)
    logs_even = {k: v[::2] for k, v in logs.items()}
    if seg is None:  # every node's: an odd node's own segment is known
        seg = _segments(at, roles[0])
    segs = (seg[even], seg[odd])
    vals, bad, _, _, _ = _interpolate(xn[even], sub, logs_even, xn[odd], roles, m, segs, False)
    err = _errors(vals, at, odd, sorted(sub.keys() - roles[0]))
    err[bad] = np.inf
    out = np.zeros(xn.size)
    out[odd] = err
    return out
