"""The fast paths of a block (issue 25): points solved as batches of equivalent loads
(:mod:`.batched`, contact similarity) or stacked in one run (:mod:`xpersson.pipeline.stacked`);
``None`` sends the block point by point (:func:`xpersson.sweep.blocks.run_block`).

``None`` means the fast path does not apply or cannot tell (a plugin without the declaration,
points that differ otherwise, a load that did not meet its tolerance, a first point that
failed on its own). A declared fast path that raises, or whose run lacks a variable of the plain
path or gives it another shape, raises :class:`~._fastfail.FastPathFailed` instead: the block is
then solved point by point and the failure is reported unless a point fails there too (the rule
is stated in :mod:`._fastfail`). These functions never change the warning filters: the sweep
silences the points' warnings once, in the calling thread (:mod:`.execute`).
"""

from __future__ import annotations

import json
from typing import Any

import numpy as np
import xarray as xr

from ..pipeline import run, squeeze_p0, stacked
from ..plugins import fast_paths_on
from ._ancillary import attach_block
from ._fastfail import FastPathFailed, declaring, failed
from .batched import SweepPoints, batched_block, scaled_ok
from .stacking import (
    Block,
    BlockResult,
    _digests,
    _own_names,
    _point_shaped,
    stack_rows,
    write_block_part,
)

__all__ = ["similar_block", "stacked_block"]


def _template(rs: Any, block: Block) -> xr.Dataset | None:
    """The first point solved on its own: coordinates and attributes of the block's Dataset.

    This is the plain path of that point, so a failure here is the point's own: ``None`` (it
    raised or did not meet its tolerance) sends the block point by point, which records it.
    """
    try:
        template = run(rs, squeeze=False)
    except Exception:  # noqa: BLE001 - the plain path of point 0: recorded point by point
        return None
    if template.attrs.get("status") != "success":
        return None
    return _point_shaped(template, block)


def _result(
    block: Block,
    rows: dict[str, np.ndarray],
    template: xr.Dataset,
    solver: list[dict[str, Any]],
    points: Any,
    part: str | None,
    part_attrs: dict[str, Any] | None,
) -> BlockResult:
    """The block's Dataset from its rows (every point solved) with its model error, written
    as a part if asked."""
    status = np.zeros(block.shape, dtype=np.int8)
    ds = stack_rows(rows, block, status, template)
    if points[0].p0_scalar:
        ds = squeeze_p0(ds)
    added = attach_block(ds, block, points)
    digests = _digests([set(template.variables).union(added)] * block.size, ds, block)
    out = BlockResult(block, ds, None, status, {}, digests, solver)
    if part is not None:
        out.sha256 = write_block_part(ds, part, out, part_attrs)
        out.dataset, out.part = None, part
    return out


def similar_block(
    block: Block,
    points: SweepPoints,
    part: str | None,
    part_attrs: dict[str, Any] | None = None,
    sink: Any = None,
    shared: dict[str, Any] | None = None,
) -> BlockResult | None:
    """The block solved as batches of loads (:mod:`.batched`), or ``None`` (point by point);
    ``sink``: the in-memory sweep's fill, whose arrays the rows are written into; ``shared``:
    the first block's template, reused as :func:`stacked_block` reuses it.

    Raises
    ------
    FastPathFailed
        The batched run raised (see :func:`.batched.batched_block`).
    """
    if not all(scaled_ok(rs) for rs in points.distinct()):
        return None  # a plugin without contact similarity: no template run wasted
    template = _first_template(block, points[0], part, shared)
    if template is None:
        return None
    got = batched_block(block, points, _own_names(template, block), template, sink)
    if got is None:
        return None
    rows, solver = got
    return _result(block, rows, template, solver, points, part, part_attrs)


def _shared_template(shared: dict[str, Any] | None, rs: Any) -> xr.Dataset | None:
    """An earlier block's template where it serves this block's first point ``rs``: the two
    points stack (same plugins, grids, loads and spectrum nodes; only declared parameters
    differ), so coordinates, variables and their attributes agree."""
    first = shared.get("first") if shared else None
    if first is None:
        return None
    template, rs0 = first
    if not np.array_equal(rs.p0, rs0.p0) or stacked.stack_reason([rs0, rs]) is not None:
        return None
    return template


def _first_template(
    block: Block, rs: Any, part: str | None, shared: dict[str, Any] | None
) -> xr.Dataset | None:
    """The template of a block whose first point is ``rs``: an earlier block's
    (:func:`_shared_template`; in memory only), else ``rs`` solved on its own (kept in
    ``shared`` for the later blocks)."""
    template = _shared_template(shared if part is None else None, rs)
    if template is not None:
        return template
    template = _template(rs, block)
    if template is not None and shared is not None and part is None:
        shared["first"] = (template, rs)  # one assignment: a worker's threads share it
    return template


def stacked_block(
    block: Block,
    points: list[Any],
    part: str | None,
    part_attrs: dict[str, Any] | None = None,
    shared: dict[str, Any] | None = None,
) -> BlockResult | None:
    """The block's points stacked in one run (:func:`xpersson.pipeline.stacked.run_stacked`),
    or ``None`` (point by point: a plugin without a stacked path, points that differ otherwise,
    a load that did not meet its tolerance, a first point that failed on its own).

    ``shared`` (a dict kept across the blocks of one in-memory sweep) holds the first
    template: a later block whose points stack with it reuses it instead of solving its own
    first point again (the sweep's Dataset takes its global attributes from the first block;
    a block written as a part always solves its own).

    Raises
    ------
    FastPathFailed
        The stacked run raised, or lacks a variable of the plain path, or gives it another
        shape.
    """
    if not fast_paths_on() or stacked.stack_reason(points) is not None:
        return None
    return _stacked(block, points, part, part_attrs, shared)


def _stacked(
    block: Block,
    points: list[Any],
    part: str | None,
    part_attrs: dict[str, Any] | None,
    shared: dict[str, Any] | None,
) -> BlockResult | None:
    """:func:`stacked_block` of a block whose points stack. Its template is an earlier
    block's, else its first point's Dataset assembled from the stacked run
    (:meth:`~xpersson.pipeline.stacked.StackedRun.point_dataset`, no second solve of that
    point), else that point solved on its own (a finite body)."""
    template = _shared_template(shared if part is None else None, points[0])
    reused = template is not None
    if template is None and points[0].geometry is not None:
        template = _first_template(block, points[0], part, shared)
        if template is None:
            return None
    try:
        got = stacked.run_stacked(points)
    except Exception as exc:  # noqa: BLE001 - judged against the plain path by run_block
        raise failed("stacked_params", points[0], exc) from exc
    if got is None:
        return None  # a load did not meet its tolerance: each status recorded point by point
    if template is None:
        own = got.point_dataset()
        if own is None:
            return None  # the first point did not succeed: recorded point by point
        template = _point_shaped(own, block)
        if shared is not None and part is None:
            shared["first"] = (template, points[0])  # one assignment: threads share it
    names = _own_names(template, block)
    rows = {}
    for n in names:
        want = template.variables[n]
        r = None if n not in got else stacked.rows_of(got, n, want.dims, len(points))
        if r is None or r.shape[1:] != want.shape:
            got_shape = "missing" if r is None else f"shape {r.shape[1:]}"
            raise FastPathFailed(
                "stacked_params",
                declaring(points[0], "stacked_params"),
                f"variable {n!r} of the plain path (shape {want.shape}): {got_shape} in the "
                "stacked run",
            )
        rows[n] = r.astype(want.dtype, copy=False)
    solver = [] if reused else [json.loads(template.attrs["xpersson_solver"])]
    return _result(block, rows, template, solver, points, part, part_attrs)
