"""A sweep on dask workers: its points resolved there, its blocks solved there, their results
read back as they finish (through shared memory where the workers share this machine's,
:mod:`._shm`)."""

from __future__ import annotations

import dataclasses
import uuid
from collections.abc import Callable
from typing import Any

import numpy as np

from ..scene import SceneError
from ._quiet import silenced
from ._shm import attached, settle
from .blocks import Block, BlockResult, _assign, run_block
from .plan import SweepPlan
from .resolve import GRID_CHANGES, grid_summary, resolve_block

__all__ = ["resolve_on_workers", "run_on_workers", "run_token"]


def run_token() -> str:
    """A dask key part unique to one submission: never an object's ``id()``, which a later
    sweep in the same process can reuse while the scheduler still knows the old key (a key
    collision leaves ``as_completed`` waiting for ever)."""
    return uuid.uuid4().hex


def _with_grid(points: Any, grid: np.ndarray) -> list[Any]:
    return [dataclasses.replace(rs, p=grid) for rs in points]


def _first(points: list[Any]) -> Any:
    return points[0]


def resolve_on_workers(
    plan: SweepPlan, registry: Any, client: Any, blocks: list[Block], parts: dict[int, Any]
) -> tuple[Any, list[tuple[Block, Any, str | None]]]:
    """Resolve every point on the workers before any solving; the points stay there.

    Returns the first resolved point (for the archive's attributes) and the solve tasks, whose
    points are futures. A bad point raises its :class:`SceneError` here, before any solve task
    is submitted, as :func:`resolve_points` does in the serial path.
    """
    tag = run_token()
    # blocks spread evenly over the workers (by points): solve tasks follow their points (data
    # locality), so this placement is what balances the solving
    addresses = sorted(client.scheduler_info().get("workers", {})) or [None]
    owner = _assign(blocks, len(addresses))
    resolved = [
        client.submit(
            resolve_block,
            plan,
            b,
            registry,
            pure=False,
            key=f"xpersson-resolve-{b.number}-{tag}",
            workers=None if addresses[0] is None else [addresses[owner[i]]],
            # (only with workers named: distributed refuses it without; no worker had
            # registered yet when the scheduler was asked, a race seen in CI)
            allow_other_workers=addresses[0] is not None,
        )
        for i, b in enumerate(blocks)
    ]
    # one round trip: every block's summary and the first point
    summaries = [client.submit(grid_summary, f, pure=False) for f in resolved]
    *summaries, first = client.gather([*summaries, client.submit(_first, resolved[0], pure=False)])
    zeta = summaries[0][0]
    if any(z is None or z.shape != zeta.shape or not np.array_equal(z, zeta) for z, _ in summaries):
        raise SceneError(GRID_CHANGES)
    if summaries[0][1] is not None:
        lo = min(b[0] for _, b in summaries)
        hi = max(b[1] for _, b in summaries)
        grid = np.linspace(lo, hi, first.p_points)
        resolved = [client.submit(_with_grid, f, grid, pure=False) for f in resolved]
        first = dataclasses.replace(first, p=grid)
    return first, [(b, f, parts[b.number]) for b, f in zip(blocks, resolved, strict=True)]


def run_on_workers(
    tasks: list[tuple[Block, Any, str | None]],
    registry: Any,
    client: Any,
    bar: Any,
    attrs: dict[str, Any] | None,
    take: Callable[[BlockResult, list[str]], None],
    token: str | None = None,
    early: list[BlockResult] | None = None,
) -> list[BlockResult]:
    """Submit the block tasks and read their results as they finish (transfers overlap the
    blocks still running); ``take(result, written)`` fills each into the sweep's arrays.
    ``token``: the run's shared arrays (:func:`._shm.share`), which its workers write their
    rows into (``written``: those variables, not sent back). ``early``: results had already
    (the probe's blocks), filled in while the workers run."""
    from distributed import as_completed

    key = run_token()
    futures = [
        client.submit(
            _silenced_block,
            b,
            pts,
            registry,
            part,
            attrs,
            token,
            pure=False,
            key=f"xpersson-block-{b.number}-{key}",
        )
        for b, pts, part in tasks
    ]
    order = {fut.key: i for i, fut in enumerate(futures)}
    results: list[Any] = [None] * len(futures)
    try:
        for res in early or ():
            take(res, [])
        for fut, (res, written) in as_completed(futures, with_results=True):
            results[order[fut.key]] = res
            take(res, written)
            fut.release()  # the worker's copy too: the fill holds the values now
            if bar is not None:
                bar.update(res.block.size)
    finally:  # a failed run: the blocks not read are cancelled
        for fut, res in zip(futures, results, strict=True):
            if res is None:
                fut.cancel()
    return results


def _silenced_block(
    block: Block,
    points: Any,
    registry: Any,
    part: str | None,
    attrs: dict[str, Any] | None,
    token: str | None = None,
) -> tuple[BlockResult, list[str]]:
    """A block task on a dask worker, its points' warnings silenced there. Where the run
    shares its arrays with this worker (``token``, :func:`._shm.attached`) the block's rows go
    there and its first template serves the worker's later blocks; returns the result and the
    variables written there (:func:`._shm.settle`)."""
    got = attached(token)
    shared = None if got is None else dict(got[1])  # this task's view of the run's dict
    with silenced():
        res = run_block(block, points, registry, part, None, attrs, shared)
    if got is None:
        return res, []
    if "first" in shared and "first" not in got[1]:
        got[1]["first"] = shared["first"]  # one assignment: safe for threads of one worker
    return settle(res, got[0])
