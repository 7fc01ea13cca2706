"""Combine the blocks of a sweep into one Dataset: statuses, constant dimensions, attributes.

In memory the block Datasets fill preallocated arrays as they arrive (:mod:`.filling`;
:func:`xarray.combine_nested` where they do not fit); for a sweep written to a folder the parts
and the index are written and the folder is opened lazily (:mod:`.parts`).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from ..scene import SceneError
from ._fastfail import failure_attrs
from .blocks import PART_ATTR, POINT_STATUS, BlockResult, stack, write_block_part
from .filling import Filling
from .parts import differing_grids, finalize, open_parts, part_name, read_part
from .plan import SweepPlan
from .stacking import digest_list, document_regridded, varies_along_all

__all__ = ["combine", "constant_along", "finish"]


def finish(
    plan: SweepPlan,
    points: list[Any],
    results: list[BlockResult],
    txn: Any = None,
    filling: Filling | None = None,
) -> xr.Dataset:
    """Combine the blocks' results into the sweep's Dataset (written as parts to the folder of
    the :class:`~.folder.Transaction` ``txn`` and opened lazily from there, when given).

    ``filling`` holds the blocks already copied into the sweep's arrays as they arrived
    (:class:`~.filling.Filling`); the others are copied in here."""
    folder: Path | None = None if txn is None else txn.folder
    filling = filling or Filling(plan)
    status, messages = _point_messages(plan, results)
    absorbed = {id(r) for r in filling.absorbed}
    ok = [r for r in results if r.dataset is not None or r.part is not None or id(r) in absorbed]
    if not ok:
        first = messages[0]["message"] if messages else "no message"
        if messages and all(m["message"].startswith("SceneError: ") for m in messages):
            where = ", ".join(f"{k} = {v:g}" for k, v in messages[0]["point"].items())
            raise SceneError(
                f"every point of the sweep was refused; first ({where}): "
                + first.removeprefix("SceneError: ")
            )
        raise RuntimeError("every point of the sweep failed; first: " + first)
    template = filling.template if filling.absorbed else _template(ok[0])
    for res in results:  # blocks where every point failed: NaN blocks from a template
        if res.dataset is None and res.part is None and id(res) not in absorbed:
            empty = [None] * res.block.size
            ds = stack(empty, res.block, res.status, template=template)
            if folder is not None:
                res.part = str(folder / part_name(res.block.number))
                res.sha256 = write_block_part(ds, res.part, res, txn.part_attrs())
            else:
                res.dataset = ds
    constant = _constant_dims(plan, results)
    attrs = _global_attrs(plan, points, results, status, messages, template)
    if folder is not None:
        txn.complete(plan, results, {"constant": constant, "attrs": attrs})
        return open_parts(folder)
    blocks = [r.dataset for r in results if r.dataset is not None]
    regridded = differing_grids(blocks, list(plan.dims))  # (before the fill takes them)
    for res in results:
        filling.add(res)
    ds = filling.dataset()
    if ds is None:  # blocks of other layouts: every result has its Dataset back
        ds = combine([r.dataset for r in results], [r.block.grid_index for r in results], plan.dims)
    out = finalize(ds, constant, attrs)
    document_regridded(out, regridded)  # (the blocks joined on the union of their grids)
    return out


def _point_messages(
    plan: SweepPlan, results: list[BlockResult]
) -> tuple[np.ndarray, list[dict[str, Any]]]:
    """The status of every point and the message of every point that did not succeed."""
    status = np.zeros(plan.shape, dtype=np.int8)
    messages: list[dict[str, Any]] = []
    coords = plan.coords()
    for res in results:
        b = res.block
        status[tuple(slice(a, c) for a, c in zip(b.start, b.stop, strict=True))] = res.status
        for k, msg in sorted(res.messages.items()):
            local = np.unravel_index(k, b.shape)
            index = tuple(int(a + i) for a, i in zip(b.start, local, strict=True))
            where = {
                name: float(values[index[plan.dims.index(dim)]])
                for name, (dim, values, _) in coords.items()
            }
            st = int(res.status.ravel()[k])
            messages.append({"point": where, "status": _status_name(st), "message": msg})
    return status, messages


def _template(res: BlockResult) -> xr.Dataset:
    """The Dataset of a solved block (a template for failed blocks: :func:`stack` cuts it to one
    point, dropping the sweep dimensions, their coordinates and ``point_status``)."""
    if res.dataset is not None:
        return res.dataset
    ds = read_part(res.part)
    ds.attrs.pop(PART_ATTR, None)
    return ds


def _status_name(code: int) -> str:
    return {v: k for k, v in POINT_STATUS.items()}[code]


def _constant_dims(plan: SweepPlan, results: list[BlockResult]) -> dict[str, list[str]]:
    """For each stacked variable, the sweep dimensions along which it never changes (failed
    points do not count)."""
    names = {n for r in results for n in r.digests}
    out: dict[str, list[str]] = {}
    for name in names:
        if any(varies_along_all(r.digests.get(name), r.block) for r in results):
            continue  # it changes along every sweep dimension in a block: constant along none
        grid, every = _digest_grid(plan, results, name)
        if every:
            dims = [
                dim
                for d, dim in enumerate(plan.dims)
                if plan.shape[d] >= 2 and np.all(grid == np.take(grid, [0], axis=d))
            ]
        else:
            dims = constant_along(grid, plan)
        if dims:
            out[name] = dims
    return out


def constant_along(grid: Any, plan: SweepPlan) -> list[str]:
    """The sweep dimensions along which an object grid of point fingerprints (shape
    ``plan.shape``; ``None``: a failed point) never changes.

    A dimension of one value says nothing about a dependence and is kept out; a dimension is
    constant only where at least two solved points along it agree (a single solved point, the
    others failed, says nothing: the dimension and its NaN stay).
    """
    dims = []
    for d, dim in enumerate(plan.dims):
        if plan.shape[d] < 2:
            continue
        moved = np.moveaxis(grid, d, -1).reshape(-1, plan.shape[d])
        solved = [[x for x in row if x is not None] for row in moved]
        if any(len(row) >= 2 for row in solved) and all(len(set(row)) <= 1 for row in solved):
            dims.append(dim)
    return dims


def _digest_grid(plan: SweepPlan, results: list[BlockResult], name: str) -> tuple[Any, bool]:
    """The fingerprints of ``name`` over the sweep grid and whether every point has one: a
    ``(*shape, 2)`` uint64 array where every block holds them as an array (every point
    solved, :func:`~.stacking._digests`), else an object array (``None``: a failed point)."""
    held = [r.digests.get(name) for r in results]
    if all(isinstance(h, np.ndarray) for h in held):
        grid = np.empty((*plan.shape, 2), np.uint64)
        for r, h in zip(results, held, strict=True):
            b = r.block
            grid[tuple(slice(a, c) for a, c in zip(b.start, b.stop, strict=True))] = h.reshape(
                (*b.shape, 2)
            )
        return grid, True
    grid = np.full(plan.shape, None, dtype=object)
    for r, h in zip(results, held, strict=True):
        b = r.block
        sl = tuple(slice(a, c) for a, c in zip(b.start, b.stop, strict=True))
        if h is not None:
            grid[sl] = np.array(digest_list(h), dtype=object).reshape(b.shape)
    return grid, all(x is not None for x in grid.flat)


def combine(datasets: list[Any], grid_index: list[tuple[int, ...]], dims: tuple[str, ...]) -> Any:
    """Combine block Datasets (in memory or lazily opened) into one over the sweep grid."""
    counts = [max(g[d] for g in grid_index) + 1 for d in range(len(dims))]
    nested: Any = np.empty(counts, dtype=object)
    for ds, g in zip(datasets, grid_index, strict=True):
        nested[g] = ds
    return xr.combine_nested(
        nested.tolist(),
        concat_dim=list(dims),
        data_vars="minimal",
        coords="minimal",
        join="outer",
        compat="override",
        combine_attrs="override",
    )


def _global_attrs(
    plan: SweepPlan,
    points: list[Any],
    results: list[BlockResult],
    status: np.ndarray,
    messages: list[dict[str, Any]],
    template: xr.Dataset,
) -> dict[str, Any]:
    attrs = dict(template.attrs)
    resolved = json.loads(attrs.get("xpersson_scene", "{}")) or dict(points[0].resolved)
    for param in plan.params:
        node = resolved
        parts = param.path.split(".")
        for part in parts[:-1]:
            node = node.setdefault(part, {})
        node[parts[-1]] = [param.scene_value(i) for i in range(len(param.values))]
    if (
        points[0].p is not None
        and plan.base.get("output", {}).get("p") is None
        and (points[0].pressure_pdf)
    ):
        resolved.setdefault("output", {})["p"] = [f"{float(x)!r} Pa" for x in points[0].p]
    resolved["sweep"] = {
        **dict(plan.scene.data.get("sweep", {})),
        "order": [p.path for p in plan.params],
    }
    attrs["xpersson_scene"] = json.dumps(resolved, sort_keys=True)
    attrs["xpersson_sweep"] = json.dumps(
        {
            "dims": list(plan.dims),
            "shape": list(plan.shape),
            "parameters": {p.path: p.name for p in plan.params},
            "points": int(plan.size),
        }
    )
    n_bad = int(np.count_nonzero(status))
    n_fail = int(np.count_nonzero(status == POINT_STATUS["failed"]))
    if n_bad == 0:
        attrs["status"] = "success"
        attrs["status_message"] = f"all {plan.size} sweep points met the requested tolerance"
    else:
        attrs["status"] = "failed" if n_fail else "tolerance_not_met"
        head = "; ".join(
            ", ".join(f"{k} = {v:g}" for k, v in m["point"].items()) + f": {m['message']}"
            for m in messages[:3]
        )
        attrs["status_message"] = (
            f"{n_bad} of {plan.size} sweep points did not succeed ({n_fail} failed): {head}"
        )
    attrs["xpersson_point_messages"] = json.dumps(messages)
    solver = [s for r in results for s in r.solver]
    if solver:
        attrs["xpersson_solver"] = json.dumps(
            {
                "method": solver[0].get("method"),
                "methods_used": sorted({m for s in solver for m in s.get("methods_used", [])}),
                "rtol": solver[0].get("rtol"),
                "atol": solver[0].get("atol"),
                "max_error_estimate": float(max(s.get("max_error_estimate", 0.0) for s in solver)),
                "work": {
                    "nsteps": int(sum(s.get("work", {}).get("nsteps", 0) for s in solver)),
                    "wall_time_s": float(
                        sum(s.get("work", {}).get("wall_time_s", 0.0) for s in solver)
                    ),
                },
            }
        )
    attrs.update(failure_attrs(results))  # fast paths that failed where the plain did not
    return attrs
