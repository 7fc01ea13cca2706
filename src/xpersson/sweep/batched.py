"""Batched sweep points: material sweeps solved as one batch of loads (contact similarity).

Where every plugin of a scene declares contact similarity (``fast_paths.contact_similarity``,
:class:`xpersson.plugins.FastPaths`: its outputs depend on the material only through E* and
scale as E*^n with their unit Pa^n when E* and the load scale together), a point (E*_k, p0)
is the point (E*_ref, p0 E*_ref / E*_k) with every Pa^n output multiplied by
(E*_k / E*_ref)^n. The points
of a block that differ only in ``material.E`` / ``material.nu`` are then solved by one pipeline
run whose loads are those equivalent loads (one engine call), and the block's Dataset is filled
from it directly (no Dataset per point). A point with several loads p0_j contributes the loads
p0_j E*_ref / E*_k; loads two points share (log-spaced E and p0) are solved once. Blocks where a
plugin does not declare it, or where a point has a tensile load or a pressure grid, are solved
point by point as before.

:class:`SweepPoints` holds the resolved points of a sweep (or of a block) without building
every one: only one point per combination of the non-material sweep values is resolved (the
material values were range-checked when the plan was expanded); the others are derived from it
on demand.
"""

from __future__ import annotations

import dataclasses
import itertools
from collections.abc import Iterator, Sequence
from typing import Any

import numpy as np
import xarray as xr

from ..pipeline import run, stacked
from ..plugins import fast_paths_on
from ._fastfail import failed
from ._rows import pressure_power, repeats, scaled_rows

__all__ = [
    "SweepPoints",
    "MATERIAL",
    "material_dims",
    "batched_block",
    "batch_capable",
    "scaled_ok",
    "pressure_power",
    "SIMILAR_METHODS",
]

#: Swept paths a batch of loads replaces (they enter the physics only through E*).
MATERIAL = ("material.E", "material.nu")


def material_dims(groups: Sequence[Sequence[Any]]) -> tuple[bool, ...]:
    """Per sweep dimension: whether all its parameters are material parameters."""
    return tuple(all(p.path in MATERIAL for p in g) for g in groups)


class SweepPoints(Sequence[Any]):
    """Resolved points of the region ``start:stop`` of a sweep grid, in C order.

    Parameters
    ----------
    groups : list of list of SweepParam
        The plan's groups (one per dimension).
    subs : dict
        Non-material global indices -> the resolved point at those indices (any material
        indices: the material values are set from ``groups`` when a point is derived).
    start, stop : tuple of int
        The region (the whole plan or one block).
    """

    def __init__(
        self,
        groups: Sequence[Sequence[Any]],
        subs: dict[tuple[int, ...], Any],
        start: tuple[int, ...],
        stop: tuple[int, ...],
    ) -> None:
        self.material = material_dims(groups)
        # per dimension: (path, SI values) of each parameter, material dimensions only
        self.values = [
            [(p.path, np.asarray(p.values, float)) for p in g] if m else []
            for g, m in zip(groups, self.material, strict=True)
        ]
        self.subs = subs
        self.start, self.stop = tuple(start), tuple(stop)
        self.shape = tuple(b - a for a, b in zip(self.start, self.stop, strict=True))

    def __len__(self) -> int:
        return int(np.prod(self.shape))

    def __getitem__(self, k: Any) -> Any:
        if isinstance(k, slice):
            return [self[i] for i in range(*k.indices(len(self)))]
        local = np.unravel_index(int(k), self.shape)
        glob = tuple(int(a + i) for a, i in zip(self.start, local, strict=True))
        return self.point(glob)

    def __iter__(self) -> Iterator[Any]:
        for k in range(len(self)):
            yield self[k]

    def key(self, glob: tuple[int, ...]) -> tuple[int, ...]:
        """The non-material indices of a global index."""
        return tuple(i for i, m in zip(glob, self.material, strict=True) if not m)

    def material_of(self, glob: tuple[int, ...], rs: Any) -> tuple[float, float]:
        """(E [Pa], nu [1]) of the point at global index ``glob`` (``rs``: its sub-point)."""
        E, nu = float(rs.E), float(rs.nu)
        for d, i in enumerate(glob):
            for path, values in self.values[d]:
                if path == "material.E":
                    E = float(values[i])
                else:
                    nu = float(values[i])
        return E, nu

    def point(self, glob: tuple[int, ...]) -> Any:
        """The resolved point at global index ``glob``."""
        rs = self.subs[self.key(glob)]
        E, nu = self.material_of(glob, rs)
        if E == rs.E and nu == rs.nu:
            return rs
        resolved = dict(rs.resolved)
        resolved["material"] = {**resolved.get("material", {}), "E": f"{E!r} Pa", "nu": nu}
        return dataclasses.replace(rs, E=E, nu=nu, resolved=resolved)

    def distinct(self) -> list[Any]:
        """One resolved point per combination of the non-material values."""
        return list(self.subs.values())

    def region(self, start: tuple[int, ...], stop: tuple[int, ...]) -> SweepPoints:
        """The points of a sub-region (a block), sharing the resolved sub-points."""
        out = SweepPoints.__new__(SweepPoints)
        out.material, out.values = self.material, self.values
        keep = [
            range(a, b)
            for (a, b), m in zip(zip(start, stop, strict=True), self.material, strict=True)
            if not m
        ]
        out.subs = {k: self.subs[k] for k in itertools.product(*keep)}
        out.start, out.stop = tuple(start), tuple(stop)
        out.shape = tuple(b - a for a, b in zip(start, stop, strict=True))
        return out


def resolved_region(
    groups: Sequence[Sequence[Any]],
    start: tuple[int, ...],
    stop: tuple[int, ...],
    resolve: Any,
) -> SweepPoints | None:
    """The points of a region with one resolve per non-material combination, or ``None`` when
    the sweep has no material dimension (``resolve(index)`` resolves the point at ``index``)."""
    material = material_dims(groups)
    if not fast_paths_on() or not any(material):
        return None
    subs = {}
    # material dimensions at their first value, whatever the region: every block then scales
    # from the same reference E* (the result does not depend on how the grid is cut)
    ranges = [
        range(a, b) if not m else range(1) for a, b, m in zip(start, stop, material, strict=True)
    ]
    for index in itertools.product(*ranges):
        key = tuple(i for i, m in zip(index, material, strict=True) if not m)
        subs[key] = resolve(index)
    return SweepPoints(groups, subs, start, stop)


#: Engine methods whose results follow contact similarity to round-off: ``auto`` (the closed
#: forms wherever the walls allow them) and ``exact``. A numerical method asked for by name
#: (``cn``, ``sine``, ``markov``) steers its error control by discrete decisions (grid levels,
#: series terms) that a scaled load does not reproduce: the equivalent-load solve then differs
#: from the point's own within the tolerance but beyond round-off (``benchmarks/fuzz.py
#: --methods 1 --sweeps 1 --seed 197``: up to 9e-7 of the area), so such points are solved
#: point by point.
SIMILAR_METHODS = ("auto", "exact")


def scaled_ok(rs: Any) -> bool:
    """Whether every plugin of a point declares contact similarity, the point has only
    compressive loads (any number) and no pressure grid, and its method is one of
    :data:`SIMILAR_METHODS`.

    The declaration counts only on the plugin's own class (:class:`~xpersson.plugins.FastPaths`
    is not inherited): a subclass (which may change the physics) is solved point by point
    unless it declares it again.
    """
    plugins = [rs.coefficient, rs.boundary, *(a for _, a in rs.analyses)]
    return (
        rs.p0.size >= 1
        and bool(np.all(rs.p0 > 0))
        and not rs.pressure_pdf
        and rs.method in SIMILAR_METHODS
        and all(type(p).fast_paths.contact_similarity for p in plugins)
    )


def batch_capable(groups: Sequence[Sequence[Any]], rs: Any) -> bool:
    """Whether points like ``rs`` of a sweep with these groups are solved as batches."""
    return fast_paths_on() and any(material_dims(groups)) and scaled_ok(rs)


def batched_block(
    block: Any,
    points: SweepPoints,
    names: list[str],
    template: xr.Dataset,
    sink: Any = None,
) -> Any:
    """The rows of every variable of a block (point-shaped as ``template``), or ``None``.

    Returns ``(rows, solver)``: name -> array ``(block.size, *template[name].shape)`` and the
    solver records of the batched runs; ``None`` where the block must be solved point by point
    (a run that did not meet its tolerance). The caller has checked that every sub-point
    declares contact similarity (:func:`scaled_ok`, :func:`~.fast.similar_block`).
    The sub-points (one per combination of the non-material values) are solved by one stacked
    run where their plugins allow it (:mod:`xpersson.pipeline.stacked`), else one run each.

    Raises
    ------
    FastPathFailed
        A run at the equivalent loads raised: the caller solves the block point by point and
        judges the failure there (:mod:`._fastfail`). The warning filters are not touched.
    """
    subs = _sub_points(block, points)  # every sub-point scaled_ok: checked by the caller
    where = np.concatenate([w for w, _, _ in subs])
    identity = bool(np.all(where == np.arange(where.size)))  # material dims innermost

    def into(wanted: list[str]) -> dict[str, np.ndarray]:  # the sweep's own rows, if given
        if sink is None or not identity:
            return {}
        got = _sink_rows(sink, block, {n: (template[n].shape, template[n].dtype) for n in wanted})
        return {n: r for n, r in got.items() if r is not None}

    got = _stacked_subs(subs, names, template, into)
    if got is not None:
        return _block_rows(got[0], names, where, identity, sink, block, template), [got[1]]
    if len(subs) == 1:  # one run: its rows as the stacked run's
        one = _similar_run(subs[0][1], subs[0][2], names, template, into)
        if one is None:
            return None
        return _block_rows(one[0], names, where, identity, sink, block, template), [one[1]]
    rows = _rows(sink, names, block, template)
    solver = []
    for where, rs, estar in subs:
        one = _similar_run(rs, estar, names, template)
        if one is None:
            return None
        for n in names:
            rows[n][where] = one[0][n]
        solver.append(one[1])
    return rows, solver


def _block_rows(
    got: dict[str, np.ndarray],
    names: list[str],
    where: np.ndarray,
    identity: bool,
    sink: Any,
    block: Any,
    template: xr.Dataset,
) -> dict[str, np.ndarray]:
    """The block's rows from the stacked run's (concatenated in the order of the sub-points,
    ``where``: their block positions): one row every point holds kept a view; else as computed
    where the order is the block's (``identity``: C-ordered arrays of the dtype, the sink's
    when written in place), else placed (into the sink's rows, if given)."""
    tv = template.variables
    rows = {n: got[n] for n in names if repeats(got[n], tv[n].dtype)}
    if identity:
        rest = [n for n in names if n not in rows]
        rows.update({n: np.require(got[n], tv[n].dtype, ["C", "W"]) for n in rest})
        return rows
    placed = _rows(sink, [n for n in names if n not in rows], block, template)
    for n, r in placed.items():
        r[where] = got[n]
    return {**rows, **placed}


def _rows(sink: Any, names: list[str], block: Any, template: xr.Dataset) -> dict[str, np.ndarray]:
    """The arrays of the rows of ``names`` for ``block``: the sweep's own where the caller
    gives a sink (an in-memory serial sweep's :class:`~.filling.Filling`) and the block's
    region of them is one contiguous run, else new ones."""
    tv = template.variables
    specs = {n: (tuple(tv[n].shape), tv[n].dtype) for n in names}
    given = {} if sink is None else _sink_rows(sink, block, specs)
    return {
        n: np.empty((block.size, *shape), dtype) if given.get(n) is None else given[n]
        for n, (shape, dtype) in specs.items()
    }


def _sink_rows(sink: Any, block: Any, specs: dict[str, Any]) -> dict[str, np.ndarray | None]:
    """``sink.rows`` of every variable of ``specs`` (name -> (point shape, dtype)), their
    arrays made together first where the sink makes them (:meth:`.filling.Filling.reserve`;
    a worker's shared-memory sink has them already)."""
    reserve = getattr(sink, "reserve", None)
    if reserve is not None:
        reserve(specs)
    return {n: sink.rows(n, block, tuple(shape), dtype) for n, (shape, dtype) in specs.items()}


def _sub_points(block: Any, points: SweepPoints) -> list[tuple[np.ndarray, Any, np.ndarray]]:
    """(block positions of its material points in C order, sub-point, E* [Pa] of each of them)
    per sub-point of a block (a combination of the non-material values).

    E* = E / (1 - nu^2) of every point as :meth:`SweepPoints.material_of` gives E and nu, one
    array operation per sub-point (``1 - nu^2`` in Python floats per distinct nu: the same
    floats as point by point).
    """
    mat, shape = points.material, block.shape
    flat = np.arange(block.size).reshape(shape)
    mat_dims = [d for d, m in enumerate(mat) if m]
    mat_shape = tuple(shape[d] for d in mat_dims)
    subs = []
    known: dict[tuple[float, float], np.ndarray] = {}  # E* of the block's material points
    for sub_local in itertools.product(
        *(range(n) if not m else [0] for n, m in zip(shape, mat, strict=True))
    ):
        sel = tuple(slice(None) if m else i for i, m in zip(sub_local, mat, strict=True))
        glob0 = tuple(a + i for a, i in zip(block.start, sub_local, strict=True))
        rs = points.subs[points.key(glob0)]
        key = (float(rs.E), float(rs.nu))  # the same for every sub-point of an E x H sweep
        if key not in known:
            known[key] = _estar(points, block, rs, mat_dims, mat_shape)
        subs.append((flat[sel].ravel(), rs, known[key]))
    return subs


def _estar(
    points: SweepPoints, block: Any, rs: Any, mat_dims: list[int], mat_shape: tuple[int, ...]
) -> np.ndarray:
    """E* [Pa] of a block's material points (C order) around the sub-point ``rs``."""
    grids = {"material.E": np.full(mat_shape, float(rs.E))}
    grids["material.nu"] = np.full(mat_shape, float(rs.nu))
    for j, d in enumerate(mat_dims):
        along = [1] * len(mat_dims)
        along[j] = -1
        for path, values in points.values[d]:
            grids[path][...] = values[block.start[d] : block.stop[d]].reshape(along)
    nus, at = np.unique(grids["material.nu"], return_inverse=True)
    denom = np.array([1.0 - nu**2 for nu in nus.tolist()])[at.reshape(mat_shape)]
    return (grids["material.E"] / denom).ravel()


def _similar_loads(rs: Any, estar: np.ndarray) -> tuple[Any, np.ndarray]:
    """``rs`` at the loads equivalent to (E*_k, p0_j), distinct and increasing, and where each
    (k, j) is among them (``inverse``, C order: point k, then load j).

    Equal equivalent loads (equal E*, or log-spaced E and p0 that share a ratio) are solved
    once: a load's result does not depend on the other loads of the run (the contact
    similarity a plugin declares is per load).
    """
    loads = (np.asarray(rs.p0, float)[None, :] * float(rs.E_star)) / estar[:, None]
    unique, inverse = np.unique(loads.ravel(), return_inverse=True)
    return dataclasses.replace(rs, p0=unique, p0_scalar=False), inverse.ravel()


def _equivalent_loads(subs: list[Any]) -> list[tuple[Any, np.ndarray]]:
    """:func:`_similar_loads` of every sub-point; the loads and their inverse computed once
    for the sub-points that share ``p0``, E*_ref and the points' E* (every H of an E x H
    sweep: the material dimensions start at the same value)."""
    out, known = [], {}
    for _, rs, estar in subs:
        key = (np.asarray(rs.p0, float).tobytes(), float(rs.E_star), estar.tobytes())
        if key not in known:
            known[key] = _similar_loads(rs, estar)
            out.append(known[key])
            continue
        ref, inverse = known[key]
        out.append((dataclasses.replace(rs, p0=ref.p0, p0_scalar=False), inverse))
    return out


def _stacked_subs(subs: list[Any], names: list[str], template: xr.Dataset, into: Any) -> Any:
    """The rows of every sub-point (concatenated in the order of ``subs``) from one stacked
    run and its solver record, or ``None`` (solve them one by one); ``into``: arrays some
    rows are written in (see :func:`._rows.scaled_rows`)."""
    if len(subs) < 2:
        return None
    refs = _equivalent_loads(subs)
    if stacked.stack_reason([r[0] for r in refs]):
        return None
    try:
        got = stacked.run_stacked([r[0] for r in refs])
    except Exception as exc:  # noqa: BLE001 - judged against the plain path by run_block
        raise failed("stacked_params", subs[0][1], exc) from exc
    if got is None or any(n not in got for n in names):
        return None
    estar = np.stack([e for _, _, e in subs])
    ref = np.array([float(rs.E_star) for _, rs, _ in subs])
    inverse = np.stack([inv for _, inv in refs])

    def var(n: str) -> tuple[tuple[str, ...], np.ndarray, Any]:
        dims, arr = got[n]
        arr = np.asarray(arr)
        if stacked.POINT in dims:
            return dims[1:], arr, template.variables[n].attrs.get("units")
        return dims, arr[None], template.variables[n].attrs.get("units")

    rows = scaled_rows(var, estar, ref, inverse, names, template, into)
    return None if rows is None else (rows, {"stacked_points": len(subs), "method": "stacked"})


def _similar_run(
    rs: Any, estar: np.ndarray, names: list[str], template: xr.Dataset, into: Any = None
) -> tuple[dict[str, np.ndarray], dict[str, Any]] | None:
    """One run of ``rs`` with the loads equivalent to (E*_k, p0); rows per point k (``into``:
    as :func:`._rows.scaled_rows` takes it)."""
    import json

    rs_ref, inverse = _similar_loads(rs, estar)
    try:
        ds = run(rs_ref, squeeze=False)
    except Exception as exc:  # noqa: BLE001 - judged against the plain path by run_block
        raise failed("contact_similarity", rs, exc) from exc
    if ds.attrs.get("status") != "success":
        return None
    for name, index in template.indexes.items():
        if name != "p0" and not np.array_equal(ds.indexes[name].values, index.values):
            return None  # another grid or other spectrum nodes: stacked point by point

    def var(n: str) -> tuple[tuple[str, ...], np.ndarray, Any]:
        v = ds.variables[n]
        return v.dims, np.asarray(v.values)[None], v.attrs.get("units")

    ref = np.array([float(rs.E_star)])
    rows = scaled_rows(var, estar[None], ref, inverse[None], names, template, into)
    return None if rows is None else (rows, json.loads(ds.attrs["xpersson_solver"]))
