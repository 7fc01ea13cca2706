"""The load table with nodes of its own per group of outputs (private, :mod:`._by_load`).

Each group of outputs is tabled with segments of its own keys (the others' keys do not cut its
stencils) and nodes of its own: on one set of nodes a load computed directly for one group's
sake (``leakage``: the junction near its sealing and at a roll-off, each load a key of its
own) would be computed for every group. Each group has its own estimates and refinement, and
the direct call computes, per load, only the groups that ask for it (``exact(rows, which)``):
``leakage``'s effective medium (its detachment bins and gap cells: ~2/3 of a direct load's
cost) is then interpolated, within its own estimate, at the loads only the junction needs.
Levels stay shared: the nodes of every group and run of one level are computed in one direct
call. The table is :func:`._by_load._table` (``by_load``'s: one group of every output).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ._by_load import COMPUTED, Partial, Weight, _table, tabled


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
    """:func:`._by_load.by_load` of the loads ``p0`` [Pa] with a table per group of outputs
    (``groups``: every output in one), each with its own nodes: ``exact(rows, which)``
    computes, per load, the groups ``which`` (n_group, n_rows) asks for; ``free`` (n_group,
    n_load): each group's loads of the first level. The other arguments are ``by_load``'s."""
    p0 = np.asarray(p0, dtype=float)
    n = p0.size
    if not tabled(p0, least):
        out = dict(exact(np.arange(n), np.ones((len(groups), n), dtype=bool)))
        out.pop(COMPUTED, None)
        return out, np.zeros(n)
    xs, first, inverse = np.unique(np.log(p0), return_index=True, return_inverse=True)
    each = np.zeros((len(groups), xs.size), dtype=bool)
    for g, fg in enumerate(np.broadcast_to(np.asarray(free, dtype=bool), (len(groups), n))):
        each[g, inverse[fg]] = True
    out, err = _table(
        xs,
        lambda sel, which: exact(first[sel], which),
        (tol, noise, orders, safety),
        (keys, weights),
        per_decade,
        each,
        groups,
    )
    return {k: v[inverse] for k, v in out.items()}, err[inverse]
