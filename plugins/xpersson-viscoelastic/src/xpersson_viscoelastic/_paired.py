"""The viscoelastic q-integrals of a block of (v, T) points at once, each point at its own
magnifications (the friction analysis's dense grids differ per point; issue 25)."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from ._modulus import ModulusModel
from .kernel import NODES, PANELS_PER_DECADE, _nodes, panel_edges

__all__ = ["cumulative_paired"]

Array = NDArray[np.float64]


def cumulative_paired(
    psd: Any,
    model: ModulusModel,
    zeta: Array,
    v: Array,
    aT: Array,
    n: int = NODES,
    ppd: int = PANELS_PER_DECADE,
) -> tuple[Array, Array]:
    """:func:`~xpersson_viscoelastic.kernel._cumulative_at` of K points at once, each at its
    own magnifications: row k of ``zeta`` (K, m) with ``v[k]``, ``aT[k]`` (K,). Returns the
    ``"tau"`` and the ``"loss"`` integrals, each (K, m), from one evaluation of the modulus.

    Every row gets the panels :func:`_cumulative_at` gives it alone (its own edges; the rows'
    panels padded with zero weights to one count), so each row equals that call. A row may
    end in repeats of its last magnification (padding of shorter grids).
    """
    z = np.asarray(zeta, dtype=float)
    q = z * float(psd.q_L)
    scale = np.asarray(v, dtype=float) * np.asarray(aT, dtype=float)
    kinks = model.breakpoints()
    edges = []
    for k in range(z.shape[0]):
        e = panel_edges(psd, q[k], ppd)
        if kinks.size and float(scale[k]) > 0:
            qk = kinks / float(scale[k])
            e = np.unique(np.concatenate([e, qk[(qk > e[0]) & (qk < e[-1])]]))
        edges.append(e)
    P = max(e.size for e in edges) - 1
    qn = np.full((z.shape[0], max(P, 1), n), float(psd.q_L))  # padding: zero weights
    wq = np.zeros_like(qn)
    idx = np.zeros(z.shape, dtype=int)
    for k, e in enumerate(edges):
        if e.size >= 2:
            qk, wk = _nodes(e, n)[:2]
            qn[k, : qk.shape[0]], wq[k, : qk.shape[0]] = qk, wk
            idx[k] = np.searchsorted(e, np.clip(q[k], e[0], e[-1]))
    base = qn**3 * np.asarray(psd.C(qn), dtype=float) * wq
    w = scale[:, None, None] * qn
    excess, loss = model.parts(w)  # what excess_mean_sq and angular(w)[1] give
    out = []
    for X in (excess, loss):
        panel = np.sum(X * base, axis=-1)
        cum = np.concatenate([np.zeros((z.shape[0], 1)), np.cumsum(panel, axis=-1)], axis=-1)
        out.append(np.take_along_axis(cum, idx, axis=-1))
    return out[0], out[1]
