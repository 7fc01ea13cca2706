"""Execute a sweep: resolve every point first, split into blocks, run them, combine.

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
import math
import os
import uuid
import warnings
from collections.abc import Callable
from typing import Any

import numpy as np
import xarray as xr

from ..errors import XperssonWarning
from ..memory import check_study
from ..pipeline import default_pressure_grid, progress_bar
from ..plugins import get_registry
from ..scene import SceneError, with_spectrum
from ._fastfail import warn_failures
from ._quiet import silenced
from ._shm import discard_pending, pack, same_machine, unpack
from ._workers import check_workers, ran_on
from .batched import SweepPoints, batch_capable, material_dims, resolved_region
from .blocks import Block, BlockResult, _assign, block_points, blocks_of, run_block
from .combine import finish
from .derived import derived_region
from .filling import Filling
from .folder import Transaction
from .parts import part_name
from .plan import SweepPlan
from .schedule import (
    BLOCK_CURVES,
    check_scheduler,
    client_for,
    points_per_block,
    too_small_for_a_cluster,
)

__all__ = ["solve_sweep", "resolve_points", "check_size"]


def _where(plan: SweepPlan, index: tuple[int, ...]) -> str:
    """A point's swept values, for messages."""
    return ", ".join(
        f"{g[0].path} = {g[0].values[i]:g}" for g, i in zip(plan.groups, index, strict=True)
    )


def _resolve_index(plan: SweepPlan, index: tuple[int, ...], registry: Any) -> Any:
    """Resolve one point; a :class:`SceneError` names the point's swept values."""
    try:
        return plan.point_scene(index).resolve(registry)
    except SceneError as exc:
        raise SceneError(f"sweep point {_where(plan, index)}: {exc}") from None


def _resolver(plan: SweepPlan, registry: Any, first: Any = None) -> Callable[..., Any]:
    """``resolve(index)``: :func:`_resolve_index`, the first point given as ``first`` when it
    was resolved already (:func:`check_size`)."""
    zero = (0,) * len(plan.shape)

    def resolve(index: tuple[int, ...]) -> Any:
        if first is not None and tuple(index) == zero:
            return first
        return _resolve_index(plan, index, registry)

    return resolve


def _spectrum_resolver(
    plan: SweepPlan, registry: Any, first_point: Any = None
) -> Callable[[tuple[int, ...]], Any]:
    """``resolve(index)`` for the sub-points of a batched region: when every swept parameter
    outside the material is a spectrum parameter, the first point is resolved in full and
    every later one rebuilds only its spectrum (:func:`~xpersson.scene._resolve.with_spectrum`:
    the same checks of the same inputs, the same result)."""
    material = material_dims(plan.groups)
    spectral = all(
        p.path.startswith("spectrum.")
        for g, m in zip(plan.groups, material, strict=True)
        if not m
        for p in g
    )
    first: list[Any] = []
    memo: dict[Any, Any] = {}  # spectrum values converted once for the whole sweep
    full = _resolver(plan, registry, first_point)

    def resolve(index: tuple[int, ...]) -> Any:
        if not (spectral and first):
            first.append(full(index))
            return first[-1]
        try:
            return with_spectrum(first[0], plan.point_scene(index), registry, memo)
        except SceneError as exc:
            raise SceneError(f"sweep point {_where(plan, index)}: {exc}") from None

    return resolve


def _region(
    plan: SweepPlan,
    start: tuple[int, ...],
    stop: tuple[int, ...],
    registry: Any,
    first: Any = None,
) -> Any:
    """The resolved points of a region: one resolve per non-material combination
    (:func:`.batched.resolved_region`), one per region where the swept parameters are declared
    stackable (``fast_paths.stacked_params``, :func:`.derived.derived_region`), or ``None``
    (resolve every point); ``first``: the sweep's first point, resolved already."""
    region = resolved_region(plan.groups, start, stop, _spectrum_resolver(plan, registry, first))
    if region is not None:
        return region
    return derived_region(
        plan,
        start,
        stop,
        _resolver(plan, registry, first),
        lambda i: _where(plan, i),
        registry,
    )


_GRID_CHANGES = (
    "sweep: the swept parameters change the magnification grid (q_1/q_L differs "
    "between points); give output.zeta_max (at most the smallest q_1/q_L) or "
    "output.zeta so that every point shares one grid"
)


def resolve_points(plan: SweepPlan, registry: Any, first: Any = None) -> list[Any]:
    """Resolve every point before any work (bad input fails here, naming the point);
    ``first``: the first point resolved already (as :func:`check_size` returns it)."""
    registry = registry or get_registry()
    points: Any = _region(plan, (0,) * len(plan.shape), plan.shape, registry, first)
    if points is None:
        resolve = _resolver(plan, registry, first)
        points = [resolve(index) for index in plan.indices()]
    summary = _summary(points)
    if summary[0] is None:
        raise SceneError(_GRID_CHANGES)
    if summary[1] is not None:
        grid = np.linspace(*summary[1], points[0].p_points)
        points = [dataclasses.replace(rs, p=grid) for rs in points]
    return points


def _summary(points: list[Any]) -> tuple[np.ndarray | None, tuple[float, float] | None]:
    """(the shared zeta grid or None when the points differ, default pressure-grid bounds)."""
    if isinstance(points, SweepPoints):  # derived points share their sub-point's grids
        if any(rs.pressure_pdf and rs.p is None for rs in points.distinct()):
            points = list(points)
        else:
            points = points.distinct()
    zeta = points[0].zeta
    for rs in points[1:]:
        if rs.zeta.shape != zeta.shape or not np.array_equal(rs.zeta, zeta):
            return None, None
    if not (points[0].pressure_pdf and points[0].p is None):
        return zeta, None
    lo, hi = math.inf, -math.inf
    for rs in points:
        grid = default_pressure_grid(rs)
        lo, hi = min(lo, float(grid[0])), max(hi, float(grid[-1]))
    return zeta, (lo, hi)


def _resolve_block(plan: SweepPlan, block: Block, registry: Any) -> list[Any]:
    """Resolve the points of one block (a worker's task), in C order."""
    registry = registry or get_registry()
    region = _region(plan, block.start, block.stop, registry)
    if region is not None:
        return region
    ranges = (range(a, b) for a, b in zip(block.start, block.stop, strict=True))
    return [_resolve_index(plan, index, registry) for index in itertools.product(*ranges)]


def _run_token() -> str:
    """A dask key part unique to one submission: never an object's ``id()``, which a later
    sweep in the same process can reuse while the scheduler still knows the old key (a key
    collision leaves ``as_completed`` waiting for ever)."""
    return uuid.uuid4().hex


def _with_grid(points: Any, grid: np.ndarray) -> list[Any]:
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
    tag = _run_token()
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


def solve_sweep(
    plan: SweepPlan,
    registry: Any,
    *,
    scheduler: Any = None,
    progress: bool | None = False,
    output: str | os.PathLike[str] | None = None,
    chunk: int | None = None,
    workers: int | None = None,
    resume: bool | None = None,
    overwrite: bool = False,
) -> xr.Dataset:
    """Solve every point of ``plan`` and return one Dataset (see :func:`xpersson.solve`).

    With ``output`` the run is a transaction on that folder (:mod:`.folder`): locked, resumed
    when the folder holds the same study (``resume``), refused when it holds another one
    unless ``overwrite``.
    """
    check_scheduler(scheduler)
    asked = scheduler
    distributed = scheduler not in (None, "serial", "synchronous", "sync", "threads")
    estimate, nbytes = probe(plan, registry) if distributed and chunk is None else (None, 0.0)
    if estimate is not None and too_small_for_a_cluster(plan, estimate, scheduler, nbytes):
        scheduler, distributed = None, False
    first = check_size(plan, registry, scheduler, chunk, workers, output is None)
    points = None if distributed else resolve_points(plan, registry, first)
    client, own_cluster, n_workers = client_for(scheduler, workers)
    txn = None
    try:
        if client is not None:  # every worker has the scene's plugins: one line if not
            check_workers(
                client,
                _resolve_index(
                    plan, (0,) * len(plan.shape), registry or get_registry()
                ).plugin_records,
            )
        layout = {
            "points_per_block": points_per_block(
                plan,
                n_workers,
                chunk,
                client is None and scheduler != "threads" and output is None,
                points[0].p0.size if points is not None else 1,
                estimate,
            ),
            "multiple": n_workers if chunk is None else 1,
        }
        if output is not None:
            txn = Transaction.begin(output, plan, layout, resume=resume, overwrite=overwrite)
            layout = txn.layout
        blocks = blocks_of(plan, layout["points_per_block"], multiple=layout["multiple"])
        done = {} if txn is None else txn.reusable(blocks)
        if txn is not None and txn.damaged:
            warnings.warn(
                f"{len(txn.damaged)} damaged part(s) solved again; first: {txn.damaged[0]}",
                XperssonWarning,
                stacklevel=3,
            )
        parts = {
            b.number: (None if txn is None else str(txn.folder / part_name(b.number)))
            for b in blocks
        }
        tasks: list[tuple[Block, Any, str | None]]
        if points is None:  # resolved (and checked) on the workers, before any solving
            first, tasks = _resolve_on_workers(plan, registry, client, blocks, parts)
            points = [first]
        else:
            tasks = [(b, block_points(plan, points, b), parts[b.number]) for b in blocks]
        tasks = [t for t in tasks if t[0].number not in done]
        filling = Filling(plan)  # in memory: each block copied into the sweep's arrays
        local = client is not None and same_machine(client)
        results = _run_tasks(
            plan, tasks, registry, scheduler, client, n_workers, progress, txn, filling.add, local
        )
        warn_failures(results, stacklevel=4)  # out of the silenced run: the user sees it
        results = sorted([*results, *done.values()], key=lambda r: r.block.number)
        ds = finish(plan, points, results, txn, filling)
        if asked != scheduler:  # e.g. a small study asked for processes ran serially
            ds.attrs["xpersson_scheduler"] = ran_on(asked, scheduler, n_workers)
        return ds
    finally:
        if txn is not None:
            txn.release()
        if own_cluster is not None:
            client.close()
            own_cluster.close()


def check_size(
    plan: SweepPlan,
    registry: Any,
    scheduler: Any,
    chunk: int | None,
    workers: int | None,
    in_memory: bool,
) -> Any:
    """Refuse (before resolving the points) a study larger than the memory budget, from its
    first point's loads, magnifications and pressures; returns that point (resolved)."""
    rs = _resolve_index(plan, next(iter(plan.indices())), registry or get_registry())
    n_workers = 1 if scheduler in (None, "serial", "synchronous", "sync") else workers
    n_workers = n_workers or os.cpu_count() or 1
    n_p = (rs.p.size if rs.p is not None else rs.p_points) if rs.pressure_pdf else None
    check_study(
        plan.size,
        rs.p0.size,
        rs.zeta.size,
        n_p,
        block_points=chunk or max(1, math.ceil(plan.size / (4 * n_workers))),
        workers=n_workers,
        in_memory=in_memory,
    )
    return rs


def _run_tasks(
    plan: SweepPlan,
    tasks: list[tuple[Block, Any, str | None]],
    registry: Any,
    scheduler: Any,
    client: Any,
    n_workers: int,
    progress: bool | None,
    txn: Any,
    take: Callable[[BlockResult], None] | None = None,
    local: bool = False,
) -> list[BlockResult]:
    bar = progress_bar(plan.size, progress, "xpersson sweep")
    if bar is not None:
        bar.update(plan.size - sum(b.size for b, _, _ in tasks))  # reused parts
    attrs = None if txn is None else txn.part_attrs()
    try:
        return _execute(tasks, registry, scheduler, client, bar, n_workers, attrs, take, local)
    finally:
        if bar is not None:
            bar.close()


def serial_estimate(plan: SweepPlan, registry: Any) -> float:
    """The study's serial CPU time [s] (:func:`probe`)."""
    return probe(plan, registry)[0]


def probe(plan: SweepPlan, registry: Any) -> tuple[float, float]:
    """The study's serial CPU time [s] and result size [bytes], measured on a probe: its first
    block of the layout a serial run would use, capped at :data:`BLOCK_CURVES` curves where its
    points are solved as batches of loads (:mod:`.batched`), else its first 4 points; resolved
    and solved here (CPU time of this process), the result discarded (``inf`` where it fails).
    """
    import time

    registry = registry or get_registry()
    t0 = time.process_time()
    rs = _resolve_index(plan, (0,) * len(plan.shape), registry)
    loads = max(1, rs.p0.size)
    size = BLOCK_CURVES // loads if batch_capable(plan.groups, rs) else 4
    block = blocks_of(plan, max(1, min(plan.size, size)))[0]
    with silenced():
        try:
            res = run_block(block, _resolve_block(plan, block, registry), registry)
        except Exception:  # noqa: BLE001 - the sweep reports failing points itself
            return math.inf, math.inf
    scale = plan.size / block.size
    nbytes = 0 if res.dataset is None else res.dataset.nbytes
    return (time.process_time() - t0) * scale, nbytes * scale


def _execute(
    tasks: list[tuple[Block, list[Any], str | None]],
    registry: Any,
    scheduler: Any,
    client: Any,
    bar: Any,
    n_workers: int = 1,
    attrs: dict[str, Any] | None = None,
    take: Callable[[BlockResult], None] | None = None,
    local: bool = False,
) -> list[BlockResult]:
    """Run the block tasks; the points' warnings are silenced (:func:`._quiet.silenced`) by
    this thread around the whole in-process run, by each task on a dask worker.

    ``take(result)`` is called on each result as it arrives (the in-memory fill,
    :class:`~.filling.Filling`: the block's Dataset is copied and dropped at once). ``local``:
    the workers share this machine's memory; their large arrays come through it (:mod:`._shm`)."""
    tick: Callable[[], None] | None = None if bar is None else (lambda: bar.update(1))
    take = take or (lambda res: None)
    out = []
    if client is None and scheduler != "threads":
        with silenced():
            # the stacked path's template, reused across blocks; the fill batched rows go to
            fill = getattr(take, "__self__", None)
            shared: dict[str, Any] = {"sink": fill if isinstance(fill, Filling) else None}
            for b, pts, part in tasks:
                out.append(run_block(b, pts, registry, part, tick, attrs, shared))
                take(out[-1])
        return out
    if client is None:
        from concurrent.futures import ThreadPoolExecutor

        with silenced(), ThreadPoolExecutor(max_workers=max(1, n_workers)) as pool:
            futures = [
                pool.submit(run_block, b, pts, registry, part, tick, attrs)
                for b, pts, part in tasks
            ]
            for f in futures:
                out.append(f.result())
                take(out[-1])
        return out
    from distributed import as_completed

    token = _run_token()
    futures = [
        client.submit(
            _silenced_block,
            b,
            pts,
            registry,
            part,
            attrs,
            local,
            pure=False,
            key=f"xpersson-block-{b.number}-{token}",
        )
        for b, pts, part in tasks
    ]
    order = {fut.key: i for i, fut in enumerate(futures)}
    results: list[Any] = [None] * len(futures)
    # results are fetched as their blocks finish: transfers overlap the blocks still running
    try:
        for fut, got in as_completed(futures, with_results=True):
            res = unpack(*got) if local else got
            results[order[fut.key]] = res
            take(res)
            fut.release()  # the worker's copy too: the fill holds the values now
            if bar is not None:
                bar.update(res.block.size)
    finally:  # a failed run: the shared-memory segments of blocks not read are removed
        discard_pending([f for f, r in zip(futures, results, strict=True) if r is None], local)
    return results


def _silenced_block(
    block: Block,
    points: Any,
    registry: Any,
    part: str | None,
    attrs: dict[str, Any] | None,
    local: bool = False,
) -> Any:
    """A block task on a dask worker, its points' warnings silenced there; ``local``: its
    large arrays left in shared memory (:func:`._shm.pack`)."""
    with silenced():
        res = run_block(block, points, registry, part, None, attrs)
    return pack(res) if local else res
