"""Execute a sweep: resolve every point first, split into blocks, run them, combine.

Schedulers: ``None``/``"serial"`` (default, in this process), ``"threads"`` (a thread pool),
``"processes"`` (a :class:`dask.distributed.LocalCluster`, one single-threaded worker process per
core), the address of a running dask scheduler (``"tcp://host:8786"``) or a
:class:`distributed.Client`. Tasks carry resolved scenes (SI floats, numpy arrays, plugin
instances) and return stacked numpy-backed Datasets or write netCDF parts; no pint object
enters the task graph.
"""

from __future__ import annotations

import math
import os
import warnings
from collections.abc import Callable
from typing import Any

import numpy as np
import xarray as xr

from ..errors import XperssonWarning
from ..memory import check_study
from ..pipeline import progress_bar
from ..plugins import get_registry
from ._fastfail import warn_failures
from ._onworkers import resolve_on_workers, run_on_workers, run_token
from ._quiet import silenced
from ._shm import MIN_BYTES, release, same_machine, share, shared_specs
from ._workers import check_workers, ran_on
from .blocks import Block, BlockResult, block_points, blocks_of, run_block
from .combine import finish
from .filling import Filling
from .folder import Transaction
from .parts import part_name
from .plan import SweepPlan
from .probe import Probe, probe, serial_estimate
from .resolve import resolve_index, resolve_points
from .schedule import (
    check_scheduler,
    client_for,
    points_per_block,
    run_here,
    too_small_for_a_cluster,
)

__all__ = ["solve_sweep", "resolve_points", "check_size", "probe", "serial_estimate"]

_resolve_index = resolve_index  # the name plugins' tests import


#: Estimated CPU time [s] of resolving a study's points (:class:`~.probe.Probe`) below which a
#: study on workers resolves them here and sends them with its tasks (the points of an E x H
#: study of 1e5: 14 ms here, 21 kB per block) instead of a round of resolve tasks on the
#: workers (about 50 ms of scheduling for 20 blocks on 2 local workers).
RESOLVE_HERE_S = 0.1


def _on_workers(scheduler: Any) -> bool:
    return scheduler not in (None, "serial", "synchronous", "sync", "threads")


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
    shm_bytes: float = MIN_BYTES,
) -> xr.Dataset:
    """Solve every point of ``plan`` and return one Dataset (see :func:`xpersson.solve`).

    With ``output`` the run is a transaction on that folder (:mod:`.folder`): locked, resumed
    when the folder holds the same study (``resume``), refused when it holds another one
    unless ``overwrite``. ``shm_bytes``: output variables at least this large [bytes] over the
    whole sweep are written by workers on this machine into shared memory (:mod:`._shm`).
    """
    check_scheduler(scheduler)
    asked = scheduler
    first = resolve_index(plan, (0,) * len(plan.shape), registry or get_registry())
    probed = checked = None
    if _on_workers(scheduler) and chunk is None:
        probed = probe(plan, registry)
        if too_small_for_a_cluster(plan, probed.estimate, scheduler, probed.nbytes):
            scheduler, workers = run_here(scheduler, probed.estimate, probed.nbytes, workers)
    check_size(plan, registry, scheduler, chunk, workers, output is None, first)
    here = probed is not None and probed.resolve_s < RESOLVE_HERE_S
    points = None if _on_workers(scheduler) and not here else resolve_points(plan, registry, first)
    client, own_cluster, n_workers = client_for(scheduler, workers)
    txn = token = None
    try:
        if client is not None:  # every worker has the scene's plugins: one line if not
            checked = check_workers(client, first.plugin_records)
        here_in_memory = client is None and scheduler != "threads" and output is None
        layout = _layout(plan, n_workers, chunk, here_in_memory, first, probed)
        if output is not None:
            txn = Transaction.begin(output, plan, layout, resume=resume, overwrite=overwrite)
            layout = txn.layout
        blocks = blocks_of(plan, layout["points_per_block"], multiple=layout["multiple"])
        done = _done(txn, blocks)
        filling = Filling(plan)  # in memory: each block copied into the sweep's arrays
        reused = _reuse(probed, blocks, first, txn)
        if client is not None and txn is None and same_machine(checked or {}):
            if probed is None:  # chunk= given: the layout from the first point, solved here
                probed = probe(plan, registry, points=1)
                reused = _reuse(probed, blocks, first, txn)
            if len(reused) < len(blocks):
                token = _shared_arrays(plan, client, probed, filling, shm_bytes)
        done.update((r.block.number, r) for r in reused)
        parts = {
            b.number: (None if txn is None else str(txn.folder / part_name(b.number)))
            for b in blocks
        }
        tasks: list[tuple[Block, Any, str | None]]
        if points is None:  # resolved (and checked) on the workers, before any solving
            first, tasks = resolve_on_workers(plan, registry, client, blocks, parts)
            points = [first]
        else:
            tasks = [(b, block_points(plan, points, b), parts[b.number]) for b in blocks]
        tasks = [t for t in tasks if t[0].number not in done]
        attrs = None if txn is None else txn.part_attrs()
        shared = probed.shared if reused else {}
        results = _run(
            plan,
            tasks,
            registry,
            scheduler,
            client,
            n_workers,
            progress,
            attrs,
            filling,
            shared,
            token,
            reused,
        )
        warn_failures(results, stacklevel=4)  # out of the silenced run: the user sees it
        results = sorted([*results, *done.values()], key=lambda r: r.block.number)
        ds = finish(plan, points, results, txn, filling)
        if asked != scheduler:  # e.g. a small study asked for processes ran serially
            ds.attrs["xpersson_scheduler"] = ran_on(asked, scheduler, n_workers)
        return ds
    finally:
        if token is not None:  # whatever the run's end: the workers drop their mappings
            release(client, token)
        if txn is not None:
            txn.release()
        if own_cluster is not None:
            client.close()
            own_cluster.close()


def _layout(
    plan: SweepPlan,
    n_workers: int,
    chunk: int | None,
    here_in_memory: bool,
    first: Any,
    probed: Probe | None,
) -> dict[str, int]:
    """Points per block (:func:`.schedule.points_per_block`) and their multiple."""
    estimate = None if probed is None else probed.estimate
    per = points_per_block(plan, n_workers, chunk, here_in_memory, first.p0.size, estimate)
    return {"points_per_block": per, "multiple": n_workers if chunk is None else 1}


def _done(txn: Any, blocks: list[Block]) -> dict[int, BlockResult]:
    """The blocks a resumed folder holds already (a warning names damaged parts)."""
    done = {} if txn is None else txn.reusable(blocks)
    if txn is not None and txn.damaged:
        warnings.warn(
            f"{len(txn.damaged)} damaged part(s) solved again; first: {txn.damaged[0]}",
            XperssonWarning,
            stacklevel=4,
        )
    return done


def _run(
    plan: SweepPlan,
    tasks: list[tuple[Block, Any, str | None]],
    registry: Any,
    scheduler: Any,
    client: Any,
    n_workers: int,
    progress: bool | None,
    attrs: dict[str, Any] | None,
    filling: Filling,
    shared: dict[str, Any],
    token: str | None,
    early: list[BlockResult],
) -> list[BlockResult]:
    """Run the tasks here or on the workers, with a progress bar when asked; ``early``: results
    had already (the probe's), filled in before the tasks run here, while they run on the
    workers."""
    bar = progress_bar(plan.size, progress, "xpersson sweep")
    try:
        if bar is not None:
            bar.update(plan.size - sum(b.size for b, _, _ in tasks))  # reused blocks
        if client is not None:
            return run_on_workers(tasks, registry, client, bar, attrs, filling.add, token, early)
        for res in early:
            filling.add(res)
        return _execute(tasks, registry, scheduler, bar, n_workers, attrs, filling, shared)
    finally:
        if bar is not None:
            bar.close()


def _reuse(probed: Probe | None, blocks: list[Block], first: Any, txn: Any) -> list[BlockResult]:
    """The probe's blocks that are blocks of the layout (in memory, where the probe resolved
    their points alike: not where the sweep's pressure grid spans every point)."""
    if probed is None or txn is not None or (first.pressure_pdf and first.p is None):
        return []
    where = {(b.start, b.stop): b for b in blocks}
    out = []
    for res in probed.results:
        block = where.get((res.block.start, res.block.stop))
        if block is not None:
            res.block = block
            out.append(res)
    return out


def _shared_arrays(
    plan: SweepPlan,
    client: Any,
    probed: Probe,
    filling: Filling,
    shm_bytes: float,
) -> str | None:
    """Share the sweep's large output arrays, laid out as the probe's block, with the workers
    where they run on this machine (:func:`._shm.share`) and lay the fill out on them; returns
    the run's token, or ``None`` (nothing shared). A large variable whose every point in the
    probe held the same row is not shared: blocks whose points all hold it again send nothing
    of it, the fill writes the row here."""
    ds = probed.results[0].dataset if probed.results else None
    if ds is None:
        return None
    token = run_token()
    specs = shared_specs(ds, plan.dims, plan.shape, shm_bytes)
    same = _same_rows(probed, specs)
    specs = {n: v for n, v in specs.items() if n not in same}
    arrays = share(client, specs, token, {n: d for n, (d, _) in same.items()})
    if arrays is None:
        return None
    filling.sink.update(arrays)
    if not filling.prepare(ds, {n: r for n, (_, r) in same.items()}):
        release(client, token)
        return None
    return token


def _same_rows(probed: Probe, names: Any) -> dict[str, tuple[Any, Any]]:
    """``{name: (fingerprint, row)}`` of the variables among ``names`` whose every point in the
    probe's blocks (two points at least) held the same values (their row fingerprints equal)."""
    out: dict[str, tuple[Any, Any]] = {}
    if sum(r.block.size for r in probed.results) < 2:
        return out
    ds = probed.results[0].dataset
    for name in names:
        held = [r.digests.get(name) for r in probed.results]
        if all(isinstance(h, np.ndarray) for h in held):
            ref = held[0][0]
            if all(np.all(h == ref) for h in held):
                var = ds.variables[name]
                out[name] = (ref, var.values[(0,) * len(probed.results[0].block.dims)].copy())
    return out


def check_size(
    plan: SweepPlan,
    registry: Any,
    scheduler: Any,
    chunk: int | None,
    workers: int | None,
    in_memory: bool,
    first: Any = None,
) -> Any:
    """Refuse (before resolving the points) a study larger than the memory budget, from its
    first point's loads, magnifications and pressures; returns that point (resolved, or
    ``first``: resolved already)."""
    rs = (
        first
        if first is not None
        else resolve_index(plan, next(iter(plan.indices())), registry or get_registry())
    )
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


def _execute(
    tasks: list[tuple[Block, list[Any], str | None]],
    registry: Any,
    scheduler: Any,
    bar: Any,
    n_workers: int,
    attrs: dict[str, Any] | None,
    filling: Filling,
    shared: dict[str, Any],
) -> list[BlockResult]:
    """Run the block tasks in this process (``"threads"``: a thread pool), the points'
    warnings silenced (:func:`._quiet.silenced`) by this thread around the whole run; each
    result is filled in as it arrives (:class:`~.filling.Filling`: the block's Dataset copied
    and dropped at once). ``shared``: the blocks' shared state (the probe's first template)."""
    tick: Callable[[], None] | None = None if bar is None else (lambda: bar.update(1))
    out = []
    # the stacked path's template, reused across blocks (one assignment: threads share it);
    # the fill batched rows go to (in place; a block whose rows it could not give is copied)
    shared["sink"] = filling
    if scheduler != "threads":
        with silenced():
            for b, pts, part in tasks:
                out.append(run_block(b, pts, registry, part, tick, attrs, shared))
                filling.add(out[-1])
        return out
    from concurrent.futures import ThreadPoolExecutor

    with silenced(), ThreadPoolExecutor(max_workers=max(1, n_workers)) as pool:
        futures = [
            pool.submit(run_block, b, pts, registry, part, tick, attrs, shared)
            for b, pts, part in tasks
        ]
        for f in futures:
            out.append(f.result())
            filling.add(out[-1])
    return out
