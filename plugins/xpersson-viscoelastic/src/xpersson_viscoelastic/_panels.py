"""Gauss-Legendre panels in ``ln q`` with as many nodes as each panel's width needs.

A Prony modulus is analytic in ``ln w`` except for poles ``pi/2`` off the real axis (each mode
``i w tau / (1 + i w tau)``); with the PSD's breakpoints as panel edges the integrands
``q^3 C(q) X(q v a_T)`` are analytic on every panel, and an ``m``-node rule on a panel of
half-width ``h`` (in ``ln q``) errs by ``~ (h / R)^(2 m)`` with ``R`` of order 2. The panels of a
dense grid (the friction analysis's, geometric in ``zeta - 1`` down to ``1e-7``) are far
narrower than :data:`~xpersson_viscoelastic.kernel.PANELS_PER_DECADE` gives: there fewer nodes
reach the same round-off (:data:`NODE_LADDER`: every rung at ``(h / 2.2)^(2 m) <= 1e-16``;
measured against all panels at 8 nodes: at most 5e-15 relative, ``v a_T`` from 1e-8 to 1e5 m/s).
Wider panels keep the full rule (bitwise as before).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["NODE_LADDER", "node_counts", "grouped_sums", "reduced_ok"]

Array = NDArray[np.float64]

#: (largest half-width in ``ln q``, nodes) of the reduced rules, narrowest first.
NODE_LADDER: tuple[tuple[float, int], ...] = (
    (2.2e-4, 2),
    (4.7e-3, 3),
    (0.022, 4),
    (0.055, 5),
    (0.10, 6),
    (0.158, 7),
)


def reduced_ok(model: Any, aT: Any) -> bool:
    """Whether the reduced rules apply: a Prony model (analytic integrands) and a constant
    shift factor (not the flash temperature's ``a_T(q)``)."""
    from ._modulus import Prony

    return isinstance(model, Prony) and not callable(aT)


def node_counts(half: Array, n: int, reduced: bool = True) -> NDArray[np.intp]:
    """Nodes of each panel of half-width ``half`` [1] (in ``ln q``): ``n`` at most."""
    counts = np.full(half.shape, n, dtype=np.intp)
    if reduced:
        for h, m in reversed(NODE_LADDER):
            counts[half <= h] = min(m, n)
    return counts


def grouped_sums(
    lo: Array,
    hi: Array,
    n: int,
    evaluate: Callable[[NDArray[np.intp], Array, Array], Array],
    reduced: bool = True,
) -> Array:
    """Per-panel sums over panels ``[lo, hi]`` [1/m] (1-D), each panel at its own node count.

    ``evaluate(sel, qn, wq)`` returns the sums over the nodes of the panels ``sel`` (indices)
    with nodes ``qn`` [1/m] and weights ``wq`` (``dq``), each ``(len(sel), m)``, as an array
    whose last axis is ``len(sel)``. Returns the panels' sums, last axis ``lo.size``. With a
    single node count the call is exactly that of one rule on every panel.
    """
    from ._gauss import spectral_rule as _rule

    slo, shi = np.log(lo), np.log(hi)
    mid, half = 0.5 * (shi + slo), 0.5 * (shi - slo)
    counts = node_counts(half, n, reduced)
    out: Array | None = None
    for m in np.unique(counts):
        sel = np.flatnonzero(counts == m)
        x, w, _ = _rule(int(m))
        qn = np.exp(mid[sel, None] + half[sel, None] * x)
        got = np.asarray(evaluate(sel, qn, half[sel, None] * w * qn), dtype=float)
        if out is None:
            out = np.zeros(got.shape[:-1] + lo.shape)
        out[..., sel] = got
    return out if out is not None else np.zeros(lo.shape)
