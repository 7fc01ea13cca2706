"""Run a sweep: resolve every point first, split into blocks, execute, combine.

Schedulers: ``None``/``"serial"`` (default, in this process), ``"threads"`` (a thread pool),
``"processes"`` (a :class:`dask.distributed.LocalCluster`, one single-threaded worker process per
core), the address of a running dask scheduler (``"tcp://host:8786"``) or a
:class:`distributed.Client`. Tasks carry resolved scenes (SI floats, numpy arrays, plugin
instances) and return stacked numpy-backed Datasets or write netCDF parts; no pint object
enters the task graph.
"""

from __future__ import annotations

import dataclasses
import itertools
import json
import math
import os
import sys
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from ._stack import POINT_STATUS, Block, BlockResult, run_block, stack
from .scene import SceneError
from .sweep import SweepPlan

__all__ = ["solve_sweep", "blocks_of", "combine", "INDEX"]

INDEX = "xpersson_index.json"


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


def _resolve_index(plan: SweepPlan, index: tuple[int, ...], registry: Any) -> Any:
    """Resolve one point; a :class:`SceneError` names the point's swept values."""
    try:
        return plan.point_scene(index).resolve(registry)
    except SceneError as exc:
        where = ", ".join(
            f"{g[0].path} = {g[0].values[i]:g}" for g, i in zip(plan.groups, index, strict=True)
        )
        raise SceneError(f"sweep point {where}: {exc}") from None


_GRID_CHANGES = (
    "sweep: the swept parameters change the magnification grid (q_1/q_L differs "
    "between points); give output.zeta_max (at most the smallest q_1/q_L) or "
    "output.zeta so that every point shares one grid"
)


def resolve_points(plan: SweepPlan, registry: Any) -> list[Any]:
    """Resolve every point before any work (bad input fails here, naming the point)."""
    from .plugins import get_registry

    registry = registry or get_registry()
    points = [_resolve_index(plan, index, registry) for index in plan.indices()]
    summary = _summary(points)
    if summary[0] is None:
        raise SceneError(_GRID_CHANGES)
    if summary[1] is not None:
        grid = np.linspace(*summary[1], points[0].p_points)
        points = [dataclasses.replace(rs, p=grid) for rs in points]
    return points


def _summary(points: list[Any]) -> tuple[np.ndarray | None, tuple[float, float] | None]:
    """(the shared zeta grid or None when the points differ, default pressure-grid bounds)."""
    from . import _pipeline

    zeta = points[0].zeta
    for rs in points[1:]:
        if rs.zeta.shape != zeta.shape or not np.array_equal(rs.zeta, zeta):
            return None, None
    if not (points[0].pressure_pdf and points[0].p is None):
        return zeta, None
    lo, hi = math.inf, -math.inf
    for rs in points:
        grid = _pipeline.default_pressure_grid(rs)
        lo, hi = min(lo, float(grid[0])), max(hi, float(grid[-1]))
    return zeta, (lo, hi)


def _resolve_block(plan: SweepPlan, block: Block, registry: Any) -> list[Any]:
    """Resolve the points of one block (a worker's task), in C order."""
    from .plugins import get_registry

    registry = registry or get_registry()
    ranges = (range(a, b) for a, b in zip(block.start, block.stop, strict=True))
    return [_resolve_index(plan, index, registry) for index in itertools.product(*ranges)]


def _with_grid(points: list[Any], grid: np.ndarray) -> list[Any]:
    return [dataclasses.replace(rs, p=grid) for rs in points]


def _first(points: list[Any]) -> Any:
    return points[0]


def _resolve_on_workers(
    plan: SweepPlan, registry: Any, client: Any, blocks: list[Block], parts: dict[int, Any]
) -> tuple[Any, list[tuple[Block, Any, str | None]]]:
    """Resolve every point on the workers before any solving; the points stay there.

    Returns the first resolved point (for the archive's attributes) and the solve tasks, whose
    points are futures. A bad point raises its :class:`SceneError` here, before any solve task
    is submitted, as :func:`resolve_points` does in the serial path.
    """
    tag = f"{os.getpid()}-{id(blocks)}"
    # blocks spread evenly over the workers (by points): solve tasks follow their points (data
    # locality), so this placement is what balances the solving
    addresses = sorted(client.scheduler_info().get("workers", {})) or [None]
    owner = _assign(blocks, len(addresses))
    resolved = [
        client.submit(
            _resolve_block,
            plan,
            b,
            registry,
            pure=False,
            key=f"xpersson-resolve-{b.number}-{tag}",
            workers=None if addresses[0] is None else [addresses[owner[i]]],
            allow_other_workers=True,
        )
        for i, b in enumerate(blocks)
    ]
    # one round trip: every block's summary and the first point
    summaries = [client.submit(_summary, f, pure=False) for f in resolved]
    *summaries, first = client.gather([*summaries, client.submit(_first, resolved[0], pure=False)])
    zeta = summaries[0][0]
    if any(z is None or z.shape != zeta.shape or not np.array_equal(z, zeta) for z, _ in summaries):
        raise SceneError(_GRID_CHANGES)
    if summaries[0][1] is not None:
        lo = min(b[0] for _, b in summaries)
        hi = max(b[1] for _, b in summaries)
        grid = np.linspace(lo, hi, first.p_points)
        resolved = [client.submit(_with_grid, f, grid, pure=False) for f in resolved]
        first = dataclasses.replace(first, p=grid)
    return first, [(b, f, parts[b.number]) for b, f in zip(blocks, resolved, strict=True)]


def _points_per_block(plan: SweepPlan, workers: int, requested: int | None) -> int:
    if requested is not None:
        if requested < 1:
            raise ValueError(f"chunk: points per block must be >= 1, got {requested}")
        return int(requested)
    return max(1, math.ceil(plan.size / (4 * max(1, workers))))


def _progress_bar(total: int | None, progress: bool | None, desc: str, unit: str = "point") -> Any:
    show = sys.stderr.isatty() if progress is None else bool(progress)
    if not show:
        return None
    try:
        from tqdm.auto import tqdm
    except ImportError:  # pragma: no cover - optional extra
        warnings.warn("progress needs tqdm: pip install 'xpersson[progress]'", stacklevel=3)
        return None
    return tqdm(
        total=total,
        desc=desc,
        unit=unit,
        unit_scale=unit != "point",
        file=sys.stderr,
        dynamic_ncols=True,
    )


def solve_sweep(
    plan: SweepPlan,
    registry: Any,
    *,
    scheduler: Any = None,
    progress: bool | None = False,
    output: str | os.PathLike[str] | None = None,
    chunk: int | None = None,
    workers: int | None = None,
) -> xr.Dataset:
    """Solve every point of ``plan`` and return one Dataset (see :func:`xpersson.solve`)."""
    _check_scheduler(scheduler)
    distributed = scheduler not in (None, "serial", "synchronous", "sync", "threads")
    points = None if distributed else resolve_points(plan, registry)
    client, own_cluster, n_workers = _client(scheduler, workers)
    try:
        blocks = blocks_of(
            plan,
            _points_per_block(plan, n_workers, chunk),
            multiple=n_workers if chunk is None else 1,
        )
        parts = {b.number: None for b in blocks}
        tasks: list[tuple[Block, Any, str | None]]
        if points is None:  # resolved (and checked) on the workers, before any solving
            first, tasks = _resolve_on_workers(plan, registry, client, blocks, parts)
            points = [first]
        folder = None
        if output is not None:
            folder = Path(output)
            folder.mkdir(parents=True, exist_ok=True)
        parts = {
            b.number: (None if folder is None else str(folder / f"part-{b.number:05d}.nc"))
            for b in blocks
        }
        if not distributed:
            tasks = [(b, _block_points(plan, points, b), parts[b.number]) for b in blocks]
        else:
            tasks = [(b, pts, parts[b.number]) for b, pts, _ in tasks]
        bar = _progress_bar(plan.size, progress, "xpersson sweep")
        try:
            results = _execute(tasks, registry, scheduler, client, bar, n_workers)
        finally:
            if bar is not None:
                bar.close()
    finally:
        if own_cluster is not None:
            client.close()
            own_cluster.close()
    return _finish(plan, points, blocks, results, folder)


def _block_points(plan: SweepPlan, points: list[Any], block: Block) -> list[Any]:
    flat = np.arange(plan.size).reshape(plan.shape)
    sl = tuple(slice(a, b) for a, b in zip(block.start, block.stop, strict=True))
    return [points[i] for i in flat[sl].ravel()]


def _check_scheduler(scheduler: Any) -> None:
    if scheduler is None or type(scheduler).__name__ == "Client":
        return
    if not isinstance(scheduler, str) or not (
        scheduler in ("serial", "synchronous", "sync", "threads", "processes") or ":" in scheduler
    ):
        raise ValueError(
            f"scheduler: {scheduler!r} is not allowed; one of None/'serial', 'threads', "
            "'processes', a scheduler address 'tcp://host:port' or a distributed.Client"
        )


def _client(scheduler: Any, workers: int | None) -> tuple[Any, Any, int]:
    """(client, cluster we own, number of workers) for a scheduler request."""
    if scheduler in (None, "serial", "synchronous", "sync"):
        return None, None, 1
    if scheduler == "threads":
        return None, None, workers or os.cpu_count() or 1
    try:
        from distributed import Client, LocalCluster
    except ImportError as exc:
        raise ImportError(
            f"scheduler={scheduler!r} needs dask.distributed: pip install 'xpersson[parallel]'"
        ) from exc
    if isinstance(scheduler, Client):
        return scheduler, None, max(1, len(scheduler.scheduler_info().get("workers", {})))
    if scheduler == "processes":
        n = workers or os.cpu_count() or 1
        cluster = LocalCluster(
            n_workers=n,
            threads_per_worker=1,
            processes=True,
            dashboard_address=None,
            silence_logs=50,
        )
        return Client(cluster), cluster, n
    if isinstance(scheduler, str) and ":" in scheduler:  # tcp://host:8786, host:8786
        client = Client(scheduler)
        return client, client, max(1, len(client.scheduler_info().get("workers", {})))
    raise ValueError(
        f"scheduler: {scheduler!r} is not allowed; one of None/'serial', 'threads', 'processes', "
        "a scheduler address 'tcp://host:port' or a distributed.Client"
    )


def _execute(
    tasks: list[tuple[Block, list[Any], str | None]],
    registry: Any,
    scheduler: Any,
    client: Any,
    bar: Any,
    n_workers: int = 1,
) -> list[BlockResult]:
    tick: Callable[[], None] | None = None if bar is None else (lambda: bar.update(1))
    if client is None and scheduler != "threads":
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return [run_block(b, pts, registry, part, True, tick) for b, pts, part in tasks]
    if client is None:
        from concurrent.futures import ThreadPoolExecutor

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            with ThreadPoolExecutor(max_workers=max(1, n_workers)) as pool:
                futures = [
                    pool.submit(run_block, b, pts, registry, part, False, tick)
                    for b, pts, part in tasks
                ]
                return [f.result() for f in futures]
    from distributed import as_completed

    futures = [
        client.submit(
            run_block,
            b,
            pts,
            registry,
            part,
            True,
            None,
            pure=False,
            key=f"xpersson-block-{b.number}-{os.getpid()}-{id(tasks)}",
        )
        for b, pts, part in tasks
    ]
    order = {fut.key: i for i, fut in enumerate(futures)}
    results: list[Any] = [None] * len(futures)
    # results are fetched as their blocks finish: transfers overlap the blocks still running
    for fut, res in as_completed(futures, with_results=True):
        results[order[fut.key]] = res
        if bar is not None:
            bar.update(res.block.size)
    return results


def _finish(
    plan: SweepPlan,
    points: list[Any],
    blocks: list[Block],
    results: list[BlockResult],
    folder: Path | None,
) -> xr.Dataset:
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
    ok = [r for r in results if r.dataset is not None or r.part is not None]
    if not ok:
        first = messages[0]["message"] if messages else "no message"
        if messages and all(m["message"].startswith("SceneError: ") for m in messages):
            where = ", ".join(f"{k} = {v:g}" for k, v in messages[0]["point"].items())
            raise SceneError(
                f"every point of the sweep was refused; first ({where}): "
                + first.removeprefix("SceneError: ")
            )
        raise RuntimeError("every point of the sweep failed; first: " + first)
    template = _template(ok[0])
    for res in results:  # blocks where every point failed: NaN blocks from a template
        if res.dataset is None and res.part is None:
            empty = [None] * res.block.size
            ds = stack(empty, res.block, res.status, template=template)
            if folder is not None:
                from .io import to_netcdf

                res.part = str(folder / f"part-{res.block.number:05d}.nc")
                to_netcdf(ds, res.part, overwrite=True)
            else:
                res.dataset = ds
    constant = _constant_dims(plan, results)
    attrs = _global_attrs(plan, points, results, status, messages, template)
    if folder is not None:
        index = {
            "format": "xpersson-parts-1",
            "dims": list(plan.dims),
            "shape": list(plan.shape),
            "parts": [[list(r.block.grid_index), Path(r.part).name] for r in results],
            "constant": constant,
            "attrs": attrs,
        }
        tmp = folder / f".{INDEX}.tmp"
        tmp.write_text(json.dumps(index, indent=1), encoding="utf-8")
        os.replace(tmp, folder / INDEX)
        from .io import open_parts

        return open_parts(folder)
    ds = _combine_in_memory(plan, results)
    if ds is None:
        ds = combine([r.dataset for r in results], [r.block.grid_index for r in results], plan.dims)
    return finalize(ds, constant, attrs)


def _template(res: BlockResult) -> xr.Dataset:
    """The Dataset of a solved block (a template for failed blocks: :func:`stack` cuts it to one
    point, dropping the sweep dimensions, their coordinates and ``point_status``)."""
    if res.dataset is not None:
        return res.dataset
    from ._cf import decode
    from .io import ENGINE

    with xr.open_dataset(res.part, engine=ENGINE) as ds:
        return decode(ds.load())


def _status_name(code: int) -> str:
    return {v: k for k, v in POINT_STATUS.items()}[code]


def _constant_dims(plan: SweepPlan, results: list[BlockResult]) -> dict[str, list[str]]:
    """For each stacked variable, the sweep dimensions along which it never changes (failed
    points do not count)."""
    names = {n for r in results for n in r.digests}
    out: dict[str, list[str]] = {}
    for name in names:
        grid = np.full(plan.shape, None, dtype=object)
        for r in results:
            b = r.block
            sl = tuple(slice(a, c) for a, c in zip(b.start, b.stop, strict=True))
            if name in r.digests:
                grid[sl] = np.array(r.digests[name], dtype=object).reshape(b.shape)
        dims = []
        for d, dim in enumerate(plan.dims):
            if plan.shape[d] < 2:  # one value says nothing about a dependence: keep the dim
                continue
            moved = np.moveaxis(grid, d, -1).reshape(-1, plan.shape[d])
            solved = [[x for x in row if x is not None] for row in moved]
            # constant only where at least two solved points along the dimension agree (a
            # single solved point, the others failed, says nothing: the dim and its NaN stay)
            if any(len(row) >= 2 for row in solved) and all(len(set(row)) <= 1 for row in solved):
                dims.append(dim)
        if dims:
            out[name] = dims
    return out


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


def _combine_in_memory(plan: SweepPlan, results: list[BlockResult]) -> xr.Dataset | None:
    """Combine in-memory block Datasets by filling preallocated arrays (the common case).

    Every block must hold the same variables with the same non-sweep dimensions and the same
    non-sweep coordinates, and every sweep dimension of a variable must lead it in the order of
    the sweep; otherwise ``None`` (the caller falls back to :func:`combine`).
    """
    dims = plan.dims
    first = results[0].dataset
    names = list(first.variables)
    out: dict[str, xr.Variable] = {}
    for name in names:
        var = first.variables[name]
        swept = [d for d in var.dims if d in dims]
        if not swept:  # a non-sweep coordinate or constant: the same in every block
            ref = var.values
            for r in results[1:]:
                other = r.dataset.variables.get(name)
                if (
                    other is None
                    or other.dims != var.dims
                    or not np.array_equal(other.values, ref, equal_nan=ref.dtype.kind in "fc")
                ):
                    return None
            out[name] = var.copy(deep=False)
            continue
        k = len(swept)
        if tuple(var.dims[:k]) != tuple(swept) or swept != [d for d in dims if d in swept]:
            return None
        axes = [dims.index(d) for d in swept]
        parts = [r.dataset.variables.get(name) for r in results]
        if any(p is None or p.dims != var.dims or p.shape[k:] != var.shape[k:] for p in parts):
            return None
        dtype = np.result_type(*(p.dtype for p in parts))
        full = np.empty(tuple(plan.shape[a] for a in axes) + var.shape[k:], dtype=dtype)
        filled = np.zeros(full.shape[:k], dtype=bool)
        for r, p in zip(results, parts, strict=True):
            sl = tuple(slice(r.block.start[a], r.block.stop[a]) for a in axes)
            full[sl] = p.values
            filled[sl] = True
        if not filled.all():
            return None
        out[name] = xr.Variable(var.dims, full, dict(var.attrs))
    if any(set(r.dataset.variables) != set(names) for r in results[1:]):
        return None
    coord_names = set(first.coords)
    return xr.Dataset(
        {n: v for n, v in out.items() if n not in coord_names},
        coords={n: v for n, v in out.items() if n in coord_names},
        attrs=dict(first.attrs),
    )[list(first.data_vars)]


def finalize(ds: xr.Dataset, constant: dict[str, list[str]], attrs: dict[str, Any]) -> xr.Dataset:
    """Drop the sweep dimensions along which a variable never changes; set the sweep's attrs.

    The kept value is the one of any solved point (failed points hold NaN and are skipped).
    """
    for name, dims in constant.items():
        if name not in ds.variables:
            continue
        var = ds[name]
        dims = [d for d in dims if d in var.dims]
        if var.dtype.kind in "fc":
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)
                reduced = var.max(dims, skipna=True, keep_attrs=True)
        elif var.dtype.kind in "iub":
            ok = ds["point_status"] != POINT_STATUS["failed"]
            reduced = var.where(ok, var.min()).max(dims, keep_attrs=True).astype(var.dtype)
        else:
            reduced = var.isel({d: 0 for d in dims}, drop=True)
        reduced.attrs = dict(var.attrs)
        if name in ds.coords:
            ds = ds.assign_coords({name: reduced})
        else:
            ds[name] = reduced
    ds.attrs = dict(attrs)
    return ds


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
    return attrs
