"""A sweep's blocks that its run solves stacked, analysed as that run analyses them.

Where every plugin of a sweep declares a stacked path and a block's points differ only in those
parameters (:func:`xpersson.pipeline.stacked.stack_reason`), the sweep's run computes each
analysis once for the block (``compute_stacked`` on a Dataset with a leading ``point``
dimension, with the block's point contexts: one engine call for the nodes of the whole block).
The point-by-point path agrees with it to round-off only, so :func:`xpersson.analyse` does the
same here: the blocks are the sweep's own in-memory blocks
(:func:`xpersson.sweep.schedule.points_per_block`, serial, in memory: ``xpersson.solve``'s
default), the block's Dataset is stacked from the points' stored Datasets and the contexts are
built as the stacked run builds them. A sweep run on workers or with ``chunk=`` was cut into
other blocks: its stacked analyses agree to round-off.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import xarray as xr

from ..pipeline import scene_context
from ..pipeline.assemble import add_outputs
from ..pipeline.frontend import diffusion_clock, spectrum_kinks
from ..pipeline.stacked import POINT, block_analyses, stack_reason
from ..pipeline.stages import load_walls, shared_tau
from ..plugins import fast_paths_on
from ..scene import ResolvedScene
from ..sweep.blocks import blocks_of
from ..sweep.plan import SweepPlan
from ..sweep.schedule import points_per_block

__all__ = ["stacked_blocks", "analyse_block"]

#: The variables a stacked run shares between its points where their spectrum and material are
#: the same (no ``point`` dimension there).
_SHARED = ("psd_C", "psd_exponent", "h_rms", "rms_slope", "E", "nu", "E_star")


def stacked_blocks(plan: SweepPlan, written: Sequence[ResolvedScene | None]) -> list[list[int]]:
    """The flat indices of the points of each block the sweep's run (serial, in memory) solves
    stacked, given every point's scene as written (``None``: not known; then none)."""
    if not fast_paths_on() or any(rs is None for rs in written) or plan.size < 2:
        return []
    rs0 = written[0]
    assert rs0 is not None
    per = points_per_block(plan, 1, None, True, rs0.p0.size)
    flat = np.arange(plan.size).reshape(plan.shape)
    out = []
    for block in blocks_of(plan, per):
        sl = tuple(slice(a, b) for a, b in zip(block.start, block.stop, strict=True))
        members = [int(k) for k in flat[sl].ravel()]
        if stack_reason([written[k] for k in members]) is None:
            out.append(members)
    return out


def analyse_block(points: Sequence[ResolvedScene], datasets: Sequence[xr.Dataset]) -> list[Any]:
    """The analyses of ``points`` (one block, their stored Datasets with ``p0``) as the stacked
    run computes them (:func:`xpersson.pipeline.stacked.block_analyses`): ``{name: (dims,
    values)}`` of each point, in order."""
    ctxs = [scene_context(rs) for rs in points]
    clocks = [
        diffusion_clock(c, rs.coefficient, kinks=spectrum_kinks(rs.psd))
        for rs, c in zip(points, ctxs, strict=True)
    ]
    walls = [
        load_walls(rs, c, k, rs.labels["boundary"])[0]
        for rs, c, k in zip(points, ctxs, clocks, strict=True)
    ]
    declared = all(shared_tau(rs.coefficient) for rs in points)
    stacked = _block_variables(datasets)
    block_analyses(points, ctxs, (walls, clocks, declared), stacked, datasets[0])
    names = [v for _, a in points[0].analyses for v in type(a).provides]
    outs: list[dict[str, Any]] = [{} for _ in points]
    for vname in names:
        dims, arr = stacked[vname]
        for k, out in enumerate(outs):
            out[vname] = (dims[1:], arr[k]) if POINT in dims else (dims, arr)
    return outs


def add_block_outputs(rs: ResolvedScene, ds: xr.Dataset, out: dict[str, Any]) -> None:
    """A point's share of a block's analyses added to its Dataset (checked, CF attributes)."""
    for name, analysis in rs.analyses:
        mine = {n: v for n, v in out.items() if n in type(analysis).provides}
        add_outputs(ds, mine, type(analysis).outputs, rs.labels[f"analyses.{name}"])


def _block_variables(datasets: Sequence[xr.Dataset]) -> dict[str, Any]:
    """The block's variables as the stacked run holds them, ``name -> (dims, values)``: every
    variable of the points with a leading ``point`` dimension, the spectrum's and material's
    once where the points share them."""
    first = datasets[0]
    out: dict[str, Any] = {}
    for name in first.data_vars:
        rows = [np.asarray(d.variables[name].values) for d in datasets]
        dims = first.variables[name].dims
        if name in _SHARED and all(np.array_equal(r, rows[0], equal_nan=True) for r in rows):
            out[str(name)] = (dims, rows[0])
        else:
            out[str(name)] = ((POINT, *dims), np.stack(rows))
    return out
