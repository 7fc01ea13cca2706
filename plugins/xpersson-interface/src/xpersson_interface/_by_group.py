"""The load table with nodes of its own per group of outputs (private, :mod:`._by_load`).

Each group of outputs is tabled with segments of its own keys (the others' keys do not cut its
stencils) and nodes of its own: on one set of nodes a load computed directly for one group's
sake (``leakage``: the junction near its sealing and at a roll-off, each load a key of its
own) would be computed for every group. Each group has its own estimates and refinement, and
the direct call
computes, per load, only the groups that ask for it (``exact(rows, which)``): ``leakage``'s
effective medium (its detachment bins and gap cells: ~2/3 of a direct load's cost) is then
interpolated, within its own estimate, at the loads only the junction needs. Levels stay
shared: the nodes of every group and run of one level are computed in one direct call.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from ._by_load import MAX_DEPTH, Weight, _nodes, _one_group, _runs, tabled
from ._stencils import _logs, _Roles

#: ``exact(rows, which)``: the outputs of the loads ``rows``, ``which`` (n_group, n_rows) the
#: groups each load is computed for (the other groups' outputs of a load: any value, unread).
Partial = Callable[[NDArray[np.intp], NDArray[np.bool_]], dict[str, NDArray[np.float64]]]


def by_group(
    p0: NDArray[np.float64],
    exact: Partial,
    tol: float,
    keys: frozenset[str],
    noise: float,
    least: int,
    orders: tuple[int, ...],
    safety: float,
    per_decade: float,
    weights: tuple[Weight, ...],
    free: NDArray[np.bool_],
    groups: tuple[frozenset[str], ...],
) -> tuple[dict[str, NDArray[np.float64]], NDArray[np.float64]]:
    """:func:`._by_load.by_load` with a table per group of outputs (``groups``: every output
    in one), each with its own nodes: ``exact(rows, which)`` computes, per load, the groups
    ``which`` (n_group, n_rows) asks for; ``free`` (n_group, n_load): each group's loads of
    the first level."""
    p0 = np.asarray(p0, dtype=float)
    n = p0.size
    if not tabled(p0, least):
        return exact(np.arange(n), np.ones((len(groups), n), dtype=bool)), np.zeros(n)
    xs, first, inverse = np.unique(np.log(p0), return_index=True, return_inverse=True)
    each = np.zeros((len(groups), xs.size), dtype=bool)
    for g, fg in enumerate(np.broadcast_to(np.asarray(free, dtype=bool), (len(groups), n))):
        each[g, inverse[fg]] = True
    out, err = table(
        xs,
        lambda sel, which: exact(first[sel], which),
        (tol, noise, orders, safety),
        (keys, weights),
        per_decade,
        each,
        groups,
    )
    return {k: v[inverse] for k, v in out.items()}, err[inverse]


def own_roles(roles: _Roles, group: frozenset[str]) -> _Roles:
    """The keys and weights of ``roles`` that belong to ``group`` (its segments: its own keys
    only)."""
    keys, weights = roles
    return keys & group, tuple(w for w in weights if w[0] <= group)


class _Direct:
    """The loads computed directly, per group, each once; every level in one call."""

    def __init__(self, exact: Partial, n: int, groups: tuple[frozenset[str], ...]) -> None:
        self.exact, self.n, self.groups = exact, n, groups
        self.done = np.zeros((len(groups), n), dtype=bool)
        self.pending = np.zeros((len(groups), n), dtype=bool)
        self.vals: dict[str, NDArray[np.float64]] = {}

    def need(self, g: int, rows: NDArray[np.intp]) -> None:
        self.pending[g, rows] = True

    def run(self) -> None:
        ask = self.pending & ~self.done
        self.pending[:] = False
        rows = np.flatnonzero(ask.any(axis=0))
        if not rows.size:
            return
        which = ask[:, rows]
        got = self.exact(rows, which)
        for k, v in got.items():
            if k not in self.vals:
                self.vals[k] = np.full((self.n,) + v.shape[1:], np.nan)
        for g, names in enumerate(self.groups):
            for k in names & got.keys():
                self.vals[k][rows[which[g]]] = got[k][which[g]]
        self.done[:, rows] |= which


def table(
    xs: NDArray[np.float64],
    exact: Partial,
    tol: tuple[float, float, tuple[int, ...], float],
    roles: _Roles,
    per_decade: float,
    pre: NDArray[np.bool_],
    groups: tuple[frozenset[str], ...],
) -> tuple[dict[str, NDArray[np.float64]], NDArray[np.float64]]:
    """``_by_load._table`` with a table per group (``pre`` (n_group, n): each group's loads of
    the first level; every output in a group); a load's estimate the largest over the groups
    (0 where computed for every group)."""
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
                h = min(math.log(10.0) / per_decade, (xs[hi] - xs[lo]) / (4 * m))
                nodes = _nodes(xs[sub], h)
                if depth > MAX_DEPTH or nodes.size < 2 * m or 2 * nodes.size > sub.size:
                    direct.need(g, sub[err[g, sub] > tol[0]])
                else:
                    if not depth:
                        nodes = np.union1d(nodes, np.flatnonzero(pre[g]))
                    direct.need(g, sub[nodes])
                    plans.append((g, sub, nodes))
        direct.run()
        regions = [[] for _ in groups]
        for g, sub, nodes in plans:
            at = {k: v[sub[nodes]] for k, v in direct.vals.items() if k in groups[g]}
            xn = xs[sub[nodes]]
            keep = np.ones(sub.size, dtype=bool)
            keep[nodes] = False
            rest = np.flatnonzero(keep)
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
    for g, names in enumerate(groups):  # a load computed for a group: its own values
        done = direct.done[g]
        for k in names & direct.vals.keys():
            o = tabled[k].copy() if k in tabled else np.full_like(direct.vals[k], np.nan)
            o[done] = direct.vals[k][done]
            out[k] = o
    return out, err.max(axis=0)
