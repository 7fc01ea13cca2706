"""Blocks of a sweep: split the grid into blocks, solve a block's points, stack them.

:func:`blocks_of` cuts the sweep grid into hyper-rectangles (the tasks). :func:`run_block` runs
on the workers: a block of points is solved by a declared fast path or point by point by the
ordinary pipeline and reduced to one Dataset whose every variable carries the block's sweep
dimensions in front of its own. A point that raised is filled with NaN (``""`` for strings) and
flagged in ``point_status``.
"""

from __future__ import annotations

import json
import math
from typing import Any

import numpy as np
import xarray as xr

from ..pipeline import run, squeeze_p0
from ._ancillary import attach_block
from ._fastfail import FastPathFailed
from .batched import SweepPoints
from .fast import similar_block, stacked_block
from .plan import SweepPlan
from .stacking import (
    PART_ATTR,
    POINT_STATUS,
    Block,
    BlockResult,
    _digests,
    stack,
    stack_rows,
    write_block_part,
)

__all__ = [
    "Block",
    "BlockResult",
    "blocks_of",
    "block_points",
    "run_block",
    "stack",
    "POINT_STATUS",
    "PART_ATTR",
    "write_block_part",
    "stack_rows",
]


def blocks_of(plan: SweepPlan, points_per_block: int, multiple: int = 1) -> list[Block]:
    """Split the sweep grid into hyper-rectangles of at most about ``points_per_block`` points.

    Inner dimensions are taken whole while they fit; the dimension where the split happens is
    cut into nearly equal pieces (lengths differ by at most one), their number rounded up to a
    multiple of ``multiple`` where the dimension allows (the number of workers: every worker
    then gets the same number of equal blocks).
    """
    shape = plan.shape
    pieces: list[list[int]] = [[n] for n in shape]  # lengths of the pieces along each dim
    remaining = max(1, int(points_per_block))
    for d in range(len(shape) - 1, -1, -1):
        if shape[d] <= remaining:  # the whole dimension fits: go outwards
            remaining //= shape[d]
            continue
        count = math.ceil(shape[d] / max(1, remaining))
        count = min(shape[d], math.ceil(count / multiple) * multiple)
        pieces[d] = [len(a) for a in np.array_split(np.arange(shape[d]), count)]
        for e in range(d):  # outer dimensions: one value per block
            pieces[e] = [1] * shape[e]
        break
    starts = [np.concatenate([[0], np.cumsum(p)[:-1]]).astype(int) for p in pieces]
    coords = plan.coords()
    out = []
    for number, gi in enumerate(np.ndindex(*(len(p) for p in pieces))):
        start = tuple(int(starts[d][g]) for d, g in enumerate(gi))
        stop = tuple(a + pieces[d][g] for d, (a, g) in enumerate(zip(start, gi, strict=True)))
        bc = {}
        for name, (dim, values, attrs) in coords.items():
            d = plan.dims.index(dim)
            bc[name] = (dim, values[start[d] : stop[d]], attrs)
        out.append(Block(number, tuple(int(g) for g in gi), start, stop, plan.dims, bc))
    return out


def _assign(blocks: list[Block], n: int) -> list[int]:
    """Worker index of each block: largest blocks first, each to the least loaded worker."""
    load = [0] * max(1, n)
    out = [0] * len(blocks)
    for k in sorted(range(len(blocks)), key=lambda k: -blocks[k].size):
        w = min(range(len(load)), key=load.__getitem__)
        out[k] = w
        load[w] += blocks[k].size
    return out


def block_points(plan: SweepPlan, points: Any, block: Block) -> Any:
    """The resolved points of a block, in C order (a :class:`SweepPoints` region where the
    sweep's points are one)."""
    if isinstance(points, SweepPoints):
        return points.region(block.start, block.stop)
    flat = np.arange(plan.size).reshape(plan.shape)
    sl = tuple(slice(a, b) for a, b in zip(block.start, block.stop, strict=True))
    return [points[i] for i in flat[sl].ravel()]


def run_block(
    block: Block,
    points: list[Any],
    registry: Any,
    part: str | None = None,
    callback: Any = None,
    part_attrs: dict[str, Any] | None = None,
    shared: dict[str, Any] | None = None,
) -> BlockResult:
    """Solve the points of a block and stack them (the task a worker runs).

    A declared fast path is tried first (:mod:`.fast`); the point-by-point path is the
    reference and isolates a failing point (recorded in ``point_status``, its message kept). A
    fast path that failed (:class:`~._fastfail.FastPathFailed`) where the point-by-point path
    then solved every point is recorded in the result's ``fast_path_failures`` (the rule:
    :mod:`._fastfail`). The warning filters are not touched here: the caller decides, in its
    own thread, what the points' warnings do (:func:`xpersson.sweep.execute.solve_sweep`).

    Parameters
    ----------
    block : Block
        The block.
    points : list of ResolvedScene
        The resolved scenes of its points, in C order.
    registry : Registry
        Plugin registry (pickles).
    part : str, optional
        Write the stacked Dataset to this netCDF file and return only the summary.
    callback : callable, optional
        Called with no argument after each point (progress in the serial path).
    part_attrs : dict, optional
        The run identity stored in the part (see :func:`write_block_part`).
    shared : dict, optional
        Kept across the blocks of one serial in-memory sweep: the stacked path's template
        point (see :func:`~xpersson.sweep.fast.stacked_block`) and ``"sink"``, the sweep's
        :class:`~.filling.Filling` (batched rows written into its arrays).
    """
    failure = None
    try:
        if isinstance(points, SweepPoints):
            sink = None if part is not None or shared is None else shared.get("sink")
            fast = similar_block(block, points, part, part_attrs, sink, shared)
        else:
            fast = stacked_block(block, points, part, part_attrs, shared)
    except FastPathFailed as exc:
        fast, failure = None, exc
    if fast is not None:
        if callback is not None:
            for _ in range(block.size):
                callback()
        return fast
    return _point_by_point(block, points, part, callback, part_attrs, failure)


def _point_by_point(
    block: Block,
    points: list[Any],
    part: str | None,
    callback: Any,
    part_attrs: dict[str, Any] | None,
    failure: FastPathFailed | None,
) -> BlockResult:
    """:func:`run_block` on the plain path: every point solved on its own."""
    results: list[xr.Dataset | None] = []
    status = np.zeros(block.size, dtype=np.int8)
    messages: dict[int, str] = {}
    for k, rs in enumerate(points):
        try:
            ds = run(rs, squeeze=False)
        except Exception as exc:  # noqa: BLE001 - a failing point is recorded, not fatal
            results.append(None)
            status[k] = POINT_STATUS["failed"]
            messages[k] = f"{type(exc).__name__}: {exc}"
        else:
            results.append(ds)
            if ds.attrs.get("status") != "success":
                status[k] = POINT_STATUS["tolerance_not_met"]
                messages[k] = f"{ds.attrs.get('status')}: {ds.attrs.get('status_message')}"
        if callback is not None:
            callback()
    solver = [json.loads(ds.attrs["xpersson_solver"]) for ds in results if ds is not None]
    if all(ds is None for ds in results):
        return BlockResult(block, None, None, status.reshape(block.shape), messages)
    ds = stack(results, block, status.reshape(block.shape))
    if points[0].p0_scalar:  # single-load points: p0 a scalar coordinate, squeezed once here
        ds = squeeze_p0(ds)
    added = attach_block(ds, block, points)  # the model error, as on the fast paths
    present = [None if r is None else set(r.variables).union(added) for r in results]
    digests = _digests(present, ds, block)
    out = BlockResult(block, ds, None, status.reshape(block.shape), messages, digests, solver)
    if failure is not None and not np.any(status == POINT_STATUS["failed"]):
        out.fast_path_failures = [str(failure)]  # the fast path failed, the plain one did not
    if part is not None:
        missing = {
            n: [k for k, p in enumerate(present) if p is not None and n not in p] for n in digests
        }
        out.sha256 = write_block_part(
            ds, part, out, part_attrs, {n: v for n, v in missing.items() if v}
        )
        out.dataset, out.part = None, part
    return out
