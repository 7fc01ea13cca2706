"""The probe: a study's serial CPU time and result size, measured on its first block(s).

Before a sweep goes to dask workers, its first block is resolved and solved here
(:func:`probe`): the CPU time of this process scaled to the study is the serial estimate the
threshold rule reads (:func:`~.schedule.too_small_for_a_cluster`), and the block's Dataset
gives the output variables and their shapes (what :mod:`._shm` shares with local workers).
The block is kept: a study that then runs here, or on workers whose first block is the same,
does not solve it again.

Points solved as batches of loads (:mod:`.batched`) are probed on the first block a serial run
would use (:data:`~.schedule.BLOCK_CURVES` curves): its fixed costs are what the study's
blocks pay. Other points are probed on their first :data:`PROBE_POINTS` points, and the rate
is measured again on the next :data:`PROBE_POINTS` (the first template reused): the first
points' one-off costs (the template run, the spectrum's caches, imports) are counted once, not
once per point (a 20-point plastic sweep was estimated at 2.4 s from its first 4 points alone
and took 0.31 s).
"""

from __future__ import annotations

import dataclasses
import math
import time
from typing import Any

from ..plugins import get_registry
from ._quiet import silenced
from .batched import batch_capable
from .blocks import BlockResult, blocks_of, run_block
from .plan import SweepPlan
from .resolve import resolve_block, resolve_index
from .schedule import points_per_block

__all__ = ["PROBE_POINTS", "Probe", "probe", "serial_estimate"]

#: Points per probe block where the points are not solved as batches of loads.
PROBE_POINTS = 4


@dataclasses.dataclass
class Probe:
    """What the probe measured.

    Attributes
    ----------
    estimate : float
        The study's serial CPU time [s] (``inf``: the probe failed).
    nbytes : float
        The study's result size [bytes], scaled from the probe's block.
    result : BlockResult or None
        The probe's first block, solved (its Dataset kept).
    shared : dict
        The blocks' shared state after the probe (its first template), for a run here.
    resolve_s : float
        The CPU time [s] of resolving the study's points, scaled from the probe's block.
    """

    estimate: float
    nbytes: float
    result: BlockResult | None = None
    shared: dict[str, Any] = dataclasses.field(default_factory=dict)
    resolve_s: float = math.inf


def probe(plan: SweepPlan, registry: Any, points: int | None = None) -> Probe:
    """Solve the study's first block here and scale its CPU time and size to the study.

    ``points``: the probe block's points (the first block of ``blocks_of(plan, points)``);
    default as stated in the module. A probe that raises gives ``inf`` (the sweep reports
    failing points itself).
    """
    registry = registry or get_registry()
    t0 = time.process_time()
    rs = resolve_index(plan, (0,) * len(plan.shape), registry)
    again = points is None and not batch_capable(plan.groups, rs)
    if points is None:
        loads = max(1, rs.p0.size)
        points = PROBE_POINTS if again else points_per_block(plan, 1, None, True, loads)
    blocks = blocks_of(plan, max(1, min(plan.size, points)))
    shared: dict[str, Any] = {}
    with silenced():
        try:
            points0 = resolve_block(plan, blocks[0], registry)
            resolve_s = time.process_time() - t0
            first = run_block(blocks[0], points0, registry, shared=shared)
            t1 = time.process_time()
            rate = (t1 - t0) / blocks[0].size
            if again and len(blocks) > 1:  # the rate again, without the first point's costs
                _run(plan, blocks[1], registry, shared)
                rate = (time.process_time() - t1) / blocks[1].size
        except Exception:  # noqa: BLE001 - the sweep reports failing points itself
            return Probe(math.inf, math.inf)
    n0 = blocks[0].size
    nbytes = 0 if first.dataset is None else first.dataset.nbytes
    scale = plan.size / n0
    estimate = (t1 - t0) + (plan.size - n0) * rate
    return Probe(estimate, nbytes * scale, first, shared, resolve_s * scale)


def _run(plan: SweepPlan, block: Any, registry: Any, shared: dict[str, Any]) -> BlockResult:
    return run_block(block, resolve_block(plan, block, registry), registry, shared=shared)


def serial_estimate(plan: SweepPlan, registry: Any) -> float:
    """The study's serial CPU time [s] (:func:`probe`)."""
    return probe(plan, registry).estimate
