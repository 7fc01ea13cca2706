"""The viscoelastic q-integrals of a block of (v, T) points at once, each point at its own
magnifications (the friction analysis's dense grids differ per point; issue 25)."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from xpersson.cache import Cache

from ._modulus import ModulusModel
from ._panels import grouped_sums, reduced_ok
from .kernel import NODES, PANELS_PER_DECADE, _checked_nu, _cumulative_at, _w, panel_edges

__all__ = ["cumulative_paired", "block_integrals", "block_nodes", "dense_block", "shared_block"]

_BLOCKS = Cache(
    "viscoelastic.block_integrals",
    scope="solve",
    maxsize=4,
    doc="tau, f and the angular integrals of a block of (v, T) points on the output grid",
)
_NODES = Cache(
    "viscoelastic.block_nodes",
    scope="solve",
    maxsize=4,
    doc="(v, aT, q-panel node values) of the first block on a spectrum's output grid",
)

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

    Every row gets the panels :func:`_cumulative_at` gives it alone (its own edges and node
    counts; the rows' panels evaluated as one flat list), so each row equals that call. A row may
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
    K = z.shape[0]
    P = max(max(e.size for e in edges) - 1, 1)
    rows = np.concatenate([np.full(max(e.size - 1, 0), k) for k, e in enumerate(edges)])
    cols = np.concatenate([np.arange(max(e.size - 1, 0)) for e in edges])
    lo = np.concatenate([e[:-1] for e in edges])
    hi = np.concatenate([e[1:] for e in edges])

    def sums(sel: NDArray[np.intp], qn: Array, wq: Array) -> Array:
        base = qn**3 * np.asarray(psd.C(qn), dtype=float) * wq
        excess, loss = model.parts(scale[rows[sel], None] * qn)  # excess_mean_sq, angular[1]
        return np.stack([np.sum(excess * base, axis=-1), np.sum(loss * base, axis=-1)])

    # every row's panels in one flat list (no padding), narrow ones at fewer nodes (_panels)
    flat = grouped_sums(lo, hi, n, sums, reduced_ok(model, aT)) if lo.size else None
    idx = np.zeros(z.shape, dtype=int)
    for k, e in enumerate(edges):
        if e.size >= 2:
            idx[k] = np.searchsorted(e, np.clip(q[k], e[0], e[-1]))
    out = []
    for which in range(2):
        panel = np.zeros((K, P))
        if flat is not None:
            panel[rows, cols] = flat[which]
        cum = np.concatenate([np.zeros((K, 1)), np.cumsum(panel, axis=-1)], axis=-1)
        out.append(np.take_along_axis(cum, idx, axis=-1))
    return out[0], out[1]


def block_integrals(
    psd: Any,
    model: ModulusModel,
    nu: float,
    zeta: Array,
    v: Array,
    aT: Array,
    ppd: int,
    keep: dict[Any, Any] | None = None,
) -> dict[str, Array]:
    """The output-grid arrays of a block of (v, T) points, each ``(K, n_zeta)``, from one
    evaluation of the modulus on the q panels and one at the output scales: ``tau`` [Pa^2],
    ``f`` [Pa^2], ``L`` [Pa], ``rms`` and ``loss`` [Pa]; each bitwise what
    :func:`~xpersson_viscoelastic.kernel.diffusion_time`, ``coefficient_f``,
    ``loss_integral`` and ``angular_averages`` give (``keep``: the q panels' node values, see
    :func:`~xpersson_viscoelastic.kernel._cumulative_at`)."""
    f = _checked_nu(nu)
    z = np.asarray(zeta, dtype=float)
    q_L = float(psd.q_L)
    exact = model.E_r**2 * np.asarray(psd.I3(z * q_L), dtype=float)
    rest, cum_loss = _cumulative_at(psd, model, z, v, aT, "both", NODES, ppd, keep)
    q = z * q_L
    mean_sq, loss = model.angular(_w(v, aT, q))
    return {
        "tau": (np.pi / 4.0) * (exact + rest) / (f * f),
        "f": (np.pi / 4.0) * q_L * q**3 * np.asarray(psd.C(q)) * mean_sq / (f * f),
        "L": cum_loss / f,
        "rms": np.sqrt(mean_sq) / f,
        "loss": loss / f,
    }


def shared_block(
    psd: Any, model: ModulusModel, nu: float, zeta: Array, v: Array, aT: Array, ppd: int
) -> dict[str, Array]:
    """:func:`block_integrals` once per solve (its ``tau_stacked``, ``interpret_stacked`` and
    the single-scene ``tau``, ``f``, ``interpret`` share it; ``"viscoelastic.block_integrals"``);
    the first block on a spectrum's output grid leaves its q panels' node values for
    :func:`block_nodes`."""
    grid = (psd, model, float(nu), int(ppd))

    def compute() -> tuple[dict[str, Array], dict[Any, Any]]:
        keep: dict[Any, Any] = {}  # the q panels' node values: graded_stacked reuses them
        return block_integrals(psd, model, nu, zeta, v, aT, ppd, keep), keep

    got, keep = _BLOCKS.get((*grid, zeta, v, aT), compute)
    _NODES.get(grid, lambda: (v, aT, keep))
    return got


def block_nodes(psd: Any, model: ModulusModel, nu: float, ppd: int) -> Any:
    """``(v [m/s], aT [1], keep)`` of the first block of this solve on the output grid of
    ``psd`` and ``nu`` with ``model`` (see :func:`._graded.known_nodes`), or ``None``."""
    return _NODES.peek((psd, model, float(nu), int(ppd)))


def dense_block(
    psd: Any, model: ModulusModel, nu: float, zeta: Array, v: Array, aT: Array, ppd: int
) -> tuple[Array, Array]:
    """``(tau [Pa^2], L [Pa])`` of K points, row k at its own magnifications ``zeta[k]``
    (K, m), as :func:`~xpersson_viscoelastic.kernel.diffusion_time` and ``loss_integral``
    give each row (the friction analysis's dense grids)."""
    f = _checked_nu(nu)
    z = np.asarray(zeta, dtype=float)
    exact = model.E_r**2 * np.asarray(psd.I3(z * float(psd.q_L)), dtype=float)
    rest, loss = cumulative_paired(psd, model, z, v, aT, ppd=ppd)
    return (np.pi / 4.0) * (exact + rest) / (f * f), loss / f
