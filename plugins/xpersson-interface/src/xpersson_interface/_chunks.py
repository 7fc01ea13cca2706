"""Loads in chunks for the interface analyses (private): per-load cost independent of the count.

The analyses' work per load is dense (splines, ``Phi`` tables, detachment bins, gap tensors on
~600 magnifications): with all loads at once its arrays (1e4 loads x 600 nodes: 48 MB each)
fall out of the cache and the cost per load grows with the number of loads (1.5-1.8x at 1e4
against 100). Above :data:`CHUNK` loads the solved curve (shared: one dense grid, one
``_past_full_contact`` cut for every load of the call) is split into chunks of :data:`CHUNK`
loads, each with its own :class:`~xpersson.physics.SolvedContact`; what an analysis shares
across loads (the bin edges, the ``u`` grid of ``gap_pdf``) is still taken from every load.

A load's values do not depend on the other loads of its chunk or call beyond round-off: its
crossing (Newton steps per row), its ``Phi`` table (zero below its own first non-zero node)
and its row sums (einsum, never a BLAS product over the loads) are its own. Two batch
dependences are left: the full-contact cut (taken over the call's loads; no cut cost 10-20 %
on the worst leakage scenes, a cut per group of loads 1.5-2.7x; measured on 60 random batches
of 2-7 loads, ``contact_stiffness`` moved by <= 4e-16 relative, every gap and leakage output
kept its bits) and the band sums of ``gap_pdf``/``gap_cdf``
(:func:`xpersson.physics._gap_band.windowed_sum`: blocks over the call's terms, the series of
``gap_cdf`` scaled by the call's largest ``1/h``; ``leak_rate_emt`` 7e-15 relative at 1000
loads). Up to :data:`CHUNK` loads: one chunk, the
analyses' shared ``SolvedContact``. :func:`subset`: the analysis context and Dataset of some of
the loads (a direct call of the load table, :mod:`._by_load`).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from typing import Any

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from xpersson import physics
from xpersson.cache import memoize
from xpersson.plugins.solved import Solved, curve_variables, per_solve

__all__ = [
    "CHUNK",
    "Part",
    "bin_edges",
    "chunk_rows",
    "contact_of",
    "contacts",
    "joined",
    "on_gap_grid",
    "sub_solved",
    "subset",
]

#: Loads per chunk: 512 loads x 600 nodes of float64 (2.5 MB per array) stay near the cache;
#: per load, 512 loads cost as 100 (measured on the roll-off H = 0.3 scene).
CHUNK = 512

#: (rows of the loads, their solved curve, their SolvedContact)
Part = tuple[slice, Solved, physics.SolvedContact]


def bin_edges(s: Solved, n_bins: int) -> NDArray[np.float64]:
    """About ``n_bins`` detachment bin edges: geometric in ``zeta - 1``, plus 1 and
    ``zeta_max`` (shared by every chunk)."""
    z_max = float(s.zeta[-1])
    if z_max <= 1.0:
        return s.zeta
    return _bin_edges(z_max, int(n_bins))


@memoize("interface.bin_edges", scope="process", maxsize=32)
def _bin_edges(z_max: float, n_bins: int) -> NDArray[np.float64]:
    """:func:`bin_edges` of ``zeta_max > 1`` (read-only; once per curve, not per direct call)."""
    inner = 1.0 + np.geomspace(1e-9, z_max - 1.0, n_bins)
    return np.unique(np.concatenate(([1.0], inner[inner < z_max], [z_max])))


def on_gap_grid(rho: NDArray[np.float64], u: NDArray[np.float64]) -> xr.DataArray:
    """``rho`` (n_load, n_u) [1/m] as a DataArray on ``("p0", "u")`` with the coordinate ``u``
    [m]: a shallow copy of the grid's template with ``rho`` as its data (the same DataArray as
    a new one; the coordinate and its index built once per grid, not per solve: ~0.3 ms of
    a 100-load ``gap_pdf`` solve)."""
    return _gap_template(u, rho.shape).copy(deep=False, data=rho)


@memoize("interface.gap_grid", scope="process", maxsize=16)
def _gap_template(u: NDArray[np.float64], shape: tuple[int, int]) -> xr.DataArray:
    """A DataArray of ``shape`` (no data of its own: a broadcast 0) on the gap grid ``u``."""
    attrs = {"units": "m", "long_name": "interfacial separation"}
    coord = xr.Variable(("u",), np.array(u, dtype=float), attrs)
    return xr.DataArray(np.broadcast_to(0.0, shape), dims=("p0", "u"), coords={"u": coord})


def chunk_rows(n_load: int, chunk: int = CHUNK) -> list[slice]:
    """Consecutive slices of at most ``chunk`` loads covering ``n_load`` loads."""
    return [slice(i, min(i + chunk, n_load)) for i in range(0, n_load, chunk)]


def sub_solved(s: Solved, rows: slice) -> Solved:
    """The solved curve of the loads ``rows`` (same magnifications)."""
    S = s.s_factor
    if S is not None and np.ndim(S) == 2 and np.shape(S)[0] == s.p0.size:
        S = S[rows]
    return dataclasses.replace(
        s,
        p0=s.p0[rows],
        area=s.area[rows],
        non_area=s.non_area[rows],
        contact=s.contact[rows],
        s_factor=S,
    )


def contact_of(ctx: Any, s: Solved) -> physics.SolvedContact:
    """The SolvedContact of the solved curve ``s`` (its loads, A(zeta), spectrum and E* all
    from the Dataset: :mod:`xpersson.plugins.stored`)."""
    return physics.SolvedContact(s.psd, s.E_star, s.p0, *s.curve)


def contacts(ctx: Any, s: Solved, key: tuple[Any, ...], chunk: int = CHUNK) -> list[Part]:
    """The chunks of ``s`` with their SolvedContacts (built once per solve and ``key``; their
    splines and tables are built when an analysis first asks, one chunk at a time)."""

    def build() -> list[Part]:
        parts = []
        for rows in chunk_rows(s.p0.size, chunk):
            sub = sub_solved(s, rows)
            parts.append((rows, sub, contact_of(ctx, sub)))
        return parts

    return per_solve(ctx, ("chunks", chunk, *key), build)


def joined(parts: list[Any], fn: Callable[[Any], Any]) -> Any:
    """``fn`` of every chunk (a :data:`Part` or what stands for it), joined along the loads
    (arrays or tuples of arrays); one chunk: its own result, untouched."""
    outs = [fn(p) for p in parts]
    if len(outs) == 1:
        return outs[0]
    first = outs[0]
    if isinstance(first, tuple):
        return tuple(_cat([o[i] for o in outs]) for i in range(len(first)))
    return _cat(outs)


def _cat(arrays: list[NDArray]) -> NDArray:
    return np.concatenate(arrays, axis=0)


def subset(ctx: Any, ds: Any, rows: NDArray[np.intp]) -> tuple[Any, Any]:
    """The analysis context and Dataset of the loads ``rows`` alone (their ``solve_at``
    re-solves those loads of the same solve; the Dataset holds only what the solved curve
    reads, :func:`xpersson.plugins.solved.curve_variables`: selecting every variable cost
    ~1.5 ms per call at 1000 loads); all loads: ``ctx`` and ``ds`` themselves."""
    p0 = np.atleast_1d(np.asarray(ctx.p0, dtype=float))
    if rows.size == p0.size and np.array_equal(rows, np.arange(p0.size)):
        return ctx, ds
    solve_at = getattr(ctx, "solve_at", None)
    if solve_at is not None:
        whole = solve_at

        def solve_at(zeta: Any, loads: Any = None, tau: Any = None) -> Any:
            sel = rows if loads is None else rows[np.asarray(loads, dtype=int)]
            return whole(zeta, sel, tau)

    sub = dataclasses.replace(ctx, p0=p0[rows], solve_at=solve_at)
    return sub, _Rows(ds, curve_variables(ctx), rows)


class _Rows:
    """The variables ``names`` of a Dataset at the loads ``rows``, as ``ds[names].isel(p0=rows)``
    holds them (``.variables``: the same values, dimensions and attributes; what
    :func:`xpersson.plugins.solved.solved_curve` reads), without building a Dataset: xarray's
    ``isel`` cost ~0.2 ms of every direct call."""

    def __init__(self, ds: Any, names: tuple[str, ...], rows: NDArray[np.intp]) -> None:
        out = {}
        for name in names:
            var = ds.variables.get(name)
            if var is not None and "p0" in var.dims:
                axis = var.dims.index("p0")
                var = xr.Variable(var.dims, np.take(var.values, rows, axis=axis), var.attrs)
            if var is not None:
                out[name] = var
        self.variables = out
