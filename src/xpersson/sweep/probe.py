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
        The study's result size [bytes], scaled from the probe's first block.
    results : list of BlockResult
        The probe's blocks, solved (their Datasets kept).
    shared : dict
        The blocks' shared state after the probe (its first template), for a run here.
    resolve_s : float
        The CPU time [s] of resolving the study's points, scaled as ``estimate``.
    """

    estimate: float
    nbytes: float
    results: list[BlockResult] = dataclasses.field(default_factory=list)
    shared: dict[str, Any] = dataclasses.field(default_factory=dict)
    resolve_s: float = math.inf


def probe(plan: SweepPlan, registry: Any, points: int | None = None) -> Probe:
    """Solve the study's first two blocks here; its CPU time is the first block's plus the
    second's rate over the other points (the first block alone where the study has one).

    ``points``: one probe block of this many points (the first block of ``blocks_of(plan,
    points)``: the layout of the study's variables, no estimate wanted); default as stated in
    the module. A probe that raises gives ``inf`` (the sweep reports failing points itself).
    """
    registry = registry or get_registry()
    t0 = time.process_time()
    rs = resolve_index(plan, (0,) * len(plan.shape), registry)
    count = 2 if points is None else 1
    if points is None:
        batched = batch_capable(plan.groups, rs)
        points = points_per_block(plan, 1, None, True, max(1, rs.p0.size)) if batched else 0
    blocks = blocks_of(plan, max(1, min(plan.size, points or PROBE_POINTS)))[:count]
    shared: dict[str, Any] = {}
    results, times = [], []  # (resolve, total) CPU seconds per block
    with silenced():
        try:
            for b in blocks:
                start = t0 if not times else time.process_time()
                pts = resolve_block(plan, b, registry)
                resolved = time.process_time()
                results.append(run_block(b, pts, registry, shared=shared))
                times.append((resolved - start, time.process_time() - start))
        except Exception:  # noqa: BLE001 - the sweep reports failing points itself
            return Probe(math.inf, math.inf)
    (r0, c0), n0 = times[0], blocks[0].size
    if len(times) > 1:  # the first block as it cost, the others at the second one's rate
        (r1, c1), n1 = times[1], blocks[1].size
        estimate, resolve_s = c0 + c1 * (plan.size - n0) / n1, r0 + r1 * (plan.size - n0) / n1
    else:
        estimate, resolve_s = c0 * plan.size / n0, r0 * plan.size / n0
    ds = results[0].dataset
    nbytes = (0 if ds is None else ds.nbytes) * plan.size / n0
    return Probe(estimate, nbytes, results, shared, resolve_s)


def serial_estimate(plan: SweepPlan, registry: Any) -> float:
    """The study's serial CPU time [s] (:func:`probe`)."""
    return probe(plan, registry).estimate
