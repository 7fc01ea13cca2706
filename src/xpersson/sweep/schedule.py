"""How a sweep is spread: block sizes, when workers pay, the scheduler's client.

Serial in memory, blocks hold about :data:`BLOCK_CURVES` curves. On workers (a
:class:`distributed.LocalCluster` or a running scheduler), the study's serial CPU time is
measured first on a probe (:func:`xpersson.sweep.probe.probe`) and the study is cut into tasks
of about :data:`TASK_S` each (2 to 16 per worker, none larger than a serial block). A study
whose estimated serial time is below :func:`threshold_s` (:data:`PARALLEL_MIN_S`, plus
:data:`CLUSTER_STARTUP_S` where ``scheduler="processes"`` starts a cluster), or that is
memory-bound (:data:`MEMORY_BOUND_RATE`), runs in this process, with a warning and an
``xpersson_scheduler`` attribute saying so: above it the workers are faster in wall time. A
memory-bound study of at least :data:`THREADS_MIN_S` whose workers' cores are this machine's
runs on as many threads of this process (:func:`run_here`).
"""

from __future__ import annotations

import math
import os
import warnings
from typing import Any

from ..errors import XperssonWarning
from ._shm import in_process
from .plan import SweepPlan

__all__ = [
    "BLOCK_CURVES",
    "CLUSTER_STARTUP_S",
    "PARALLEL_MIN_S",
    "SERIAL_BLOCK_POINTS",
    "MEMORY_BOUND_RATE",
    "TASK_S",
    "THREADS_MIN_S",
    "here_threads",
    "memory_bound",
    "run_here",
    "points_per_block",
    "threshold_s",
    "too_small_for_a_cluster",
    "check_scheduler",
    "client_for",
]


#: Fewest curves (points x loads, when the sweep has that many) per block of a serial in-memory
#: sweep: a stacked block pays a fixed cost to assemble its Dataset, and a serial run has no
#: workers to balance (150 friction points: one block instead of 5, ~10 % less CPU).
SERIAL_BLOCK_POINTS = 256


#: Curves (points x loads) per block of a serial in-memory sweep: large enough that a block's
#: fixed costs (its first point solved alone, one stacked run, its Dataset) stay small, small
#: enough that a block's intermediate arrays (about 7 times its rows) stay a fraction of the
#: result: a 1e5-curve E x H x p0 study peaks at 1.7x its result with blocks of 5000 curves
#: (2.0x with 12 800, 2.5x with 25 000; ``benchmarks/summary.py``).
BLOCK_CURVES = 5_000


def points_per_block(
    plan: SweepPlan,
    workers: int,
    requested: int | None,
    serial_in_memory: bool = False,
    loads: int = 1,
    estimate: float | None = None,
) -> int:
    """Points per block: ``requested``, else

    * serial in memory: as many as make :data:`BLOCK_CURVES` curves (``loads`` per point), at
      least :data:`SERIAL_BLOCK_POINTS` curves;
    * on workers, with the study's measured serial time ``estimate`` [s]
      (:func:`~.probe.probe`): tasks of about :data:`TASK_S` each, 2 to 16 per worker, and
      no larger than a serial block (a block's intermediate arrays stay small, and the first
      block is the probe's, which is not solved again);
    * else a quarter of each worker's share.
    """
    if requested is not None:
        if requested < 1:
            raise ValueError(f"chunk: points per block must be >= 1, got {requested}")
        return int(requested)
    loads = max(1, loads)
    serial = max(BLOCK_CURVES // loads, min(plan.size, SERIAL_BLOCK_POINTS // loads), 1)
    if serial_in_memory:
        return serial
    workers = max(1, workers)
    if estimate is not None and math.isfinite(estimate):
        tasks = min(16 * workers, max(2 * workers, math.ceil(estimate / TASK_S)))
        return max(1, min(serial, math.ceil(plan.size / tasks)))
    return max(1, math.ceil(plan.size / (4 * workers)))


#: What ``scheduler="processes"`` costs before the first point is solved [s]: starting a
#: LocalCluster of single-threaded workers and importing xpersson in each (3-5 s measured by
#: ``benchmarks/sweep_scaling.py`` on a shared 2-core machine; the lower end is stated here).
CLUSTER_STARTUP_S = 3.0
#: Estimated serial CPU time [s] of a study (:func:`~.probe.probe`) below which workers do not
#: pay, on any distributed scheduler (on top of the cluster's start-up where
#: ``scheduler="processes"`` starts one): the probe, one round trip to the workers, the tasks'
#: scheduling and the workers' own per-block costs. Measured by ``benchmarks/summary.py`` and
#: CPU accounting on 2 local workers (the client's CPU before and after the tasks plus the
#: busier worker's, against the serial CPU): a CPU-bound plastic H sweep of 100 points x 3
#: loads (estimated 2.5 s) 1.00-1.10x serial, of 400 points (10 s) 0.82x serial wall. Measured
#: again with the measuring session at autogroup nice -19 (2 cores free), wall against serial,
#: bitwise equal: 100 points (1.0 s serial, estimated 1.9-2.0 s) 0.97-1.16x; 150 points
#: (1.5 s) 0.89-1.00x (median 0.97x); 400 points (4.1 s, estimated 7.7-8.9 s) 0.67-0.82x. The
#: probe overstates such sweeps about 2x (its second block of 4 points carries a block's
#: fixed costs), so 3 s estimated is about 1.5 s of serial CPU for them.
#: Below it the study runs in this process.
PARALLEL_MIN_S = 3.0
#: Serial CPU time [s] of one task on a worker: long enough that the scheduler's per-task
#: cost (a few ms) and the transfer of its result are small, short enough for 2 to 16 tasks
#: per worker (balance, results combined while others run).
TASK_S = 0.5


def threshold_s(scheduler: Any) -> float:
    """Estimated serial CPU time [s] above which ``scheduler`` (a distributed one) pays."""
    return PARALLEL_MIN_S + (CLUSTER_STARTUP_S if scheduler == "processes" else 0.0)


#: Result bytes per second of the study's serial CPU time above which a study is memory-bound
#: [B/s]: its worker processes would spend more moving the result than they save computing it,
#: at any size. An E x H study of one load makes about 450 MB/s (229 MiB for 0.5 s). Through
#: dask's sockets it took 3x serial; written in place in shared memory by 2 local workers
#: (:mod:`._shm`) it still needs, by CPU accounting, 1.35-1.45x the serial CPU on its critical
#: path (1.18-2.2x serial wall on the shared machine): a tmpfs page is 4 KiB
#: (``shmem_enabled = never``), and populating them cost the workers 3.7 ms of system time
#: per MB, where the serial run writes anonymous memory in 2 MiB pages. Workers that are
#: threads of this process (``LocalCluster(processes=False)``) pay dask's per-task costs and
#: its event loops' share of the GIL: the same study took 1.0-1.9x serial wall on them. Such
#: a study runs in this process instead, on threads where the workers' cores are this
#: machine's (:func:`here_threads`).
MEMORY_BOUND_RATE = 1e8
#: Estimated serial CPU time [s] above which a memory-bound study whose workers share this
#: machine runs on :func:`here_threads` threads of this process rather than on one: its
#: numbers are computed by numpy, scipy and the compiled kernels, which release the GIL for
#: most of the time (74 % of a block's samples, ``py-spy --gil``), and the threads write into
#: this process's own arrays (anonymous memory, 2 MiB pages). Measured on the shared 2-core
#: machine (the measuring session at autogroup nice -19), E x H studies of one load given a
#: LocalCluster(2), wall against serial (best of 8-10 interleaved rounds, bitwise equal; the
#: probe estimates them at 0.8-0.85x their serial CPU): 1e5 points (0.47-0.51 s serial)
#: 0.82-0.95x on 2 threads; 8e4 points (0.36 s) 0.90-0.94x; 6e4 points (0.28-0.29 s)
#: 0.92-1.09x in two runs (the probe's two blocks, solved before the threads start, are a sixth
#: of the study); 4e4 points (0.2 s) 1.05-1.09x.
THREADS_MIN_S = 0.3


def here_threads(scheduler: Any, workers: int | None = None) -> int:
    """Threads of this process a study that does not go to ``scheduler``'s workers runs on:
    the worker threads of a ``LocalCluster`` (its processes or threads of this one: their
    cores are this machine's) or of ``"processes"`` (``workers`` or the cores); 1 elsewhere
    (a scheduler elsewhere: this machine's cores are not the workers')."""
    if scheduler == "processes":
        return max(1, workers or os.cpu_count() or 1)
    local = in_process(scheduler) or type(getattr(scheduler, "cluster", None)).__name__ == (
        "LocalCluster"
    )
    if not local:
        return 1
    try:
        info = scheduler.scheduler_info().get("workers", {})
    except Exception:  # noqa: BLE001 - no answer: one thread
        return 1
    return max(1, sum(int(w.get("nthreads", 1)) for w in info.values()))


def too_small_for_a_cluster(
    plan: SweepPlan, estimate: float, scheduler: Any = "processes", nbytes: float = 0.0
) -> bool:
    """Whether the study, solved serially (``estimate`` [s], result ``nbytes`` [B],
    :func:`~xpersson.sweep.probe.probe`), takes less than :func:`threshold_s`, is memory-bound
    (:data:`MEMORY_BOUND_RATE`), or the workers are threads of this process
    (:func:`~._shm.in_process`: dask's threads pay nothing where the study's Python holds the
    GIL, and the memory-bound studies pay on threads without dask); then a warning says so and
    the sweep runs in this process (on :func:`here_threads` threads where it is memory-bound
    and longer than :data:`THREADS_MIN_S`: :func:`run_here`)."""
    limit = threshold_s(scheduler)
    bound = memory_bound(estimate, nbytes)
    threads = in_process(scheduler)
    if estimate >= limit and not bound and not threads:
        return False
    what = (
        "starting the worker processes and sending them the work costs"
        if scheduler == "processes"
        else "sending the work to the workers and the results back costs"
    )
    why = (
        f"its result ({nbytes / 1e6:.3g} MB) is memory-bound: moving it to this process costs "
        "more than the workers save computing it"
        if bound
        else f"{what} about {limit:g} s, more than this study of {plan.size} points takes "
        f"serially (about {estimate:.2g} s, measured on its first points)"
        if estimate < limit
        else "its workers are threads of this process, and the study's Python work holds the "
        "GIL (a plastic sweep took 1.07-1.11x serial on two of them)"
    )
    n = run_here(scheduler, estimate, nbytes)[1]
    where = "in this process" + (f" on {n} threads" if n > 1 else "")
    warnings.warn(
        f"scheduler={_name(scheduler)}: {why}; solving it {where}. Pass chunk= to run it on "
        "the workers anyway.",
        XperssonWarning,
        stacklevel=4,
    )
    return True


def memory_bound(estimate: float, nbytes: float) -> bool:
    """Whether a study of serial CPU time ``estimate`` [s] and result ``nbytes`` [B] is
    memory-bound (:data:`MEMORY_BOUND_RATE`)."""
    return math.isfinite(estimate) and nbytes > MEMORY_BOUND_RATE * max(estimate, 1e-9)


def run_here(
    scheduler: Any, estimate: float, nbytes: float, workers: int | None = None
) -> tuple[str | None, int]:
    """``(scheduler, workers)`` in this process for a study :func:`too_small_for_a_cluster`
    keeps here: ``("threads", n)`` for a memory-bound study longer than
    :data:`THREADS_MIN_S` whose workers share this machine (:func:`here_threads`), else
    ``(None, 1)`` (serial)."""
    if memory_bound(estimate, nbytes) and estimate >= THREADS_MIN_S:
        n = here_threads(scheduler, workers)
        if n > 1:
            return "threads", n
    return None, 1


def _name(scheduler: Any) -> str:
    if isinstance(scheduler, str):
        return repr(scheduler)
    return str(getattr(getattr(scheduler, "scheduler", None), "address", "a dask client"))


def check_scheduler(scheduler: Any) -> None:
    if scheduler is None or type(scheduler).__name__ == "Client":
        return
    if not isinstance(scheduler, str) or not (
        scheduler in ("serial", "synchronous", "sync", "threads", "processes") or ":" in scheduler
    ):
        raise ValueError(
            f"scheduler: {scheduler!r} is not allowed; one of None/'serial', 'threads', "
            "'processes', a scheduler address 'tcp://host:port' or a distributed.Client"
        )


def client_for(scheduler: Any, workers: int | None) -> tuple[Any, Any, int]:
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
