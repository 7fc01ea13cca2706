"""The LocalCluster rows of ``benchmarks/summary.py``: a study's wall time on a local dask
cluster of two processes against the same study run serially (:func:`parallel_path`)."""

from __future__ import annotations

import os
import re
import statistics
import time
import warnings

from summary_design import load_range, scene

import xpersson
from xpersson.api import as_scene, expand
from xpersson.plugins import get_registry
from xpersson.sweep._shm import in_process
from xpersson.sweep.probe import serial_estimate

STEEL = {"E": "210 GPa", "nu": 0.3}
PLASTIC = {"model": "plastic_scale_dependent", "Y1": "3 GPa", "n": 0.1}


def _ratio(t: float, k: float, **extra: object) -> dict:
    return {"time": t, "kernel": k, "ratio": t / k, **extra}


def _eh_study(spec: dict, n: int) -> tuple[dict, str]:
    """E x H (n x 100 points), one load: batched, memory-bound (2.3 kB of result per 5 us):
    on local workers its variables are written in place in shared memory."""
    study = scene(spec)
    study["material"]["E"] = {"start": "1 MPa", "stop": "100 MPa", "num": n}
    study["spectrum"]["H"] = {"start": 0.3, "stop": 0.95, "num": 100, "spacing": "linear"}
    return study, f"E x H {n * 100:.0e} points"


def _plastic_study(spec: dict, n: int) -> tuple[dict, str]:
    """H (n points) x 3 loads, plastic_scale_dependent: CPU-bound (about 15 ms per point)."""
    study = scene(spec, ["5 MPa", "20 MPa", "100 MPa"], boundary=PLASTIC)
    study["material"] = dict(STEEL)
    study["spectrum"]["H"] = {"start": 0.3, "stop": 0.95, "num": n, "spacing": "linear"}
    return study, f"plastic H {n} points x 3 loads"


#: The LocalCluster rows: name -> (study builder, size, --quick size).
PARALLEL = {
    "LocalCluster(2) wall vs serial wall": (_eh_study, 1000, 100),
    "LocalCluster(2) wall vs serial wall, above the threshold": (_plastic_study, 400, 100),
}


def _burn(n: int) -> int:
    """A pure-Python loop: the machine's own parallel ceiling (no numpy, no memory)."""
    s = 0
    for i in range(n):
        s += i * i
    return s


def ceiling(client, rounds: int = 3, n: int = 5_000_000) -> float:
    """Two loops in this process over the same two loops on the cluster's two workers (wall,
    best of interleaved rounds): about 2 on free cores, about 1 where other sessions keep them
    busy (Linux shares the CPUs between sessions, and the workers are in this one's)."""
    ts, tp = [], []
    for _ in range(rounds):
        t0 = time.perf_counter()
        _burn(n), _burn(n)
        ts.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        client.gather(client.map(_burn, [n, n], pure=False))
        tp.append(time.perf_counter() - t0)
    return min(ts) / min(tp)


def _workers_cpu(client) -> float:
    """The CPU time [s] the cluster's worker processes have used so far (0 for threads of
    this process: their CPU is this process's)."""
    return sum(client.run(time.process_time).values()) if not in_process(client) else 0.0


def _cluster_round(study: dict, client) -> tuple[float, float, bool, str, float, float]:
    """One interleaved round: serial wall, cluster wall [s], bitwise equal, where it ran,
    serial CPU, cluster CPU [s] (this process's and the workers')."""
    t0, c0 = time.perf_counter(), time.process_time()
    a = xpersson.solve(study)
    ts, cs = time.perf_counter() - t0, time.process_time() - c0
    with warnings.catch_warnings():  # below the threshold: the warning says it ran here
        warnings.simplefilter("ignore")
        w0 = _workers_cpu(client)
        t0, c0 = time.perf_counter(), time.process_time()
        b = xpersson.solve(study, scheduler=client)
        tp, cp = time.perf_counter() - t0, time.process_time() - c0
        cp += _workers_cpu(client) - w0
    equal = list(a.variables) == list(b.variables) and all(
        a[v].dims == b[v].dims and a[v].dtype == b[v].dtype and a[v].equals(b[v])
        for v in a.variables
    )
    return ts, tp, equal, b.attrs.get("xpersson_scheduler", "workers"), cs, cp


#: Interleaved rounds of the LocalCluster rows, at least (the machine is shared: the best of
#: many rounds is the time of the quietest).
CLUSTER_ROUNDS = 8


def parallel_path(rounds: int, quick: bool = False) -> dict:
    """Studies on LocalCluster(2) against serial (:data:`PARALLEL`): a 1e5-point E x H study
    (memory-bound: the rule, ``xpersson.sweep.schedule.MEMORY_BOUND_RATE``, runs it in the
    client's process, on as many threads as the local workers, ``THREADS_MIN_S``; on the
    workers, ``sweep_scaling.py --crossover``, its variables would be written in place in
    shared memory, ``xpersson.sweep._shm``) and a plastic H sweep (CPU-bound, above
    ``PARALLEL_MIN_S``: on the workers). Wall times (perf_counter), best of at least
    :data:`CLUSTER_ROUNDS` interleaved rounds, the cluster started and warmed up first; ratio =
    cluster wall / serial wall (< 1: the cluster pays), with the median of the rounds' ratios
    and the CPU (this process's and the workers', best of the rounds) beside; results compared
    bit for bit (values, dims, dtypes, variable order); the machine's parallel ceiling
    (:func:`ceiling`) beside. On a machine shared with other sessions, run it where they do not
    take the cores (a session of its own at a low autogroup nice value, say)."""
    from distributed import Client, LocalCluster
    from summary_design import design

    spec = design()[0][1]
    cluster = LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None, silence_logs=40
    )
    client = Client(cluster)
    out = {}
    try:
        warm = scene(spec, load_range(3))
        warm["material"]["E"] = ["1 MPa", "2 MPa", "3 MPa", "4 MPa"]
        xpersson.solve(warm, scheduler=client, chunk=1)  # imports on the workers
        for name, (build, size, small) in PARALLEL.items():
            study, label = build(spec, small if quick else size)
            _cluster_round(study, client)  # warm-up: each worker's first blocks of this study
            got = [_cluster_round(study, client) for _ in range(max(CLUSTER_ROUNDS, rounds))]
            ts, tp = min(g[0] for g in got), min(g[1] for g in got)
            cs, cp = min(g[4] for g in got), min(g[5] for g in got)
            median = statistics.median(g[1] / g[0] for g in got)
            equal, where = all(g[2] for g in got), got[-1][3]
            where = re.sub(r"tcp://[^;)]*", "the cluster's address", where)  # no port in files
            est = serial_estimate(expand(as_scene(study), get_registry()), get_registry())
            note = (
                f"(wall; estimated serial {est:.2g} s; ran: {where}; results bitwise equal: "
                f"{equal}; median of the rounds' ratios {median:.2f}; CPU {cp:.3g} s / "
                f"{cs:.3g} s (this process and the workers); {os.cpu_count()} cores, two loops "
                f"{ceiling(client):.2f}x faster on the workers at the time; best of {len(got)} "
                "interleaved rounds)"
            )
            out[name] = {label: _ratio(tp, ts, note=note)}
            print(f"{name}: {tp:.3g} s / {ts:.3g} s {note}", flush=True)
            print("  rounds (serial, cluster):", [(round(g[0], 3), round(g[1], 3)) for g in got])
            print("  CPU (serial, cluster):", [(round(g[4], 3), round(g[5], 3)) for g in got])
    finally:
        client.close()
        cluster.close()
    return out


__all__ = ["PARALLEL", "parallel_path"]
