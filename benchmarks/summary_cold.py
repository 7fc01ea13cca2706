"""Cold rows of ``benchmarks/summary.py``: a path's first solve in a fresh interpreter.

Best-of rounds hide what a user who runs a study once pays: the first solve's lazy imports,
first-use caches, first allocations. A cold row runs the path's scene and its kernel's scene
each as the first solve of its own fresh interpreter (numpy, pandas, scipy.special, xarray
and ``xpersson`` imported: the libraries' own import time is the README's start-up row, the
same for any solve; ``set_options(compiled=True)`` as the benchmark sets it; no solve before)
and reports the CPU time of that one call: xpersson's first-use costs (its lazy modules,
plugin discovery, first caches, first allocations). The smaller of two such processes per
side (one is noisy on a shared machine).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys

from summary_design import load_range, scene

#: The first solve of one scene in a fresh interpreter; prints its CPU time [s].
_FIRST = """
import json, sys, time, warnings
warnings.simplefilter("ignore")
import numpy, pandas, scipy.special, xarray  # the libraries any solve loads (startup row)
import xpersson
xpersson.set_options(compiled=True)
scene = json.loads(sys.argv[1])
t = time.process_time()
xpersson.solve(scene)
print(json.dumps(time.process_time() - t))
"""


def first_solve(data: dict) -> float:
    """CPU time [s] of ``xpersson.solve(data)`` as the first solve of a fresh interpreter
    (this process's import path, ``OPENBLAS_NUM_THREADS=1``)."""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path), OPENBLAS_NUM_THREADS="1")
    out = subprocess.run(
        [sys.executable, "-c", _FIRST, json.dumps(data)],
        env=env,
        capture_output=True,
        text=True,
        check=True,
        timeout=600,
    )
    return float(json.loads(out.stdout.strip().splitlines()[-1]))


def cold_ratio(path: dict, kernel: dict, rounds: int) -> dict:
    """The cold row: ``path``'s first solve against ``kernel``'s, each in fresh interpreters
    (best of ``min(rounds, 2)``, at least one)."""
    t = {"s": float("inf"), "k": float("inf")}
    for _ in range(max(1, min(rounds, 2))):
        t["s"] = min(t["s"], first_solve(path))
        t["k"] = min(t["k"], first_solve(kernel))
    return {"time": t["s"], "kernel": t["k"], "ratio": t["s"] / t["k"]}


def sweep_eh_cold(spec: dict, rounds: int, quick: bool) -> dict:
    """The E x H sweep of one load per point (as ``sweep E x H, 1 load``) and the same number
    of plain loads (a range), each the first solve of a fresh interpreter."""
    from summary_paths import _eh

    n = 30 if quick else 100
    out = cold_ratio(_eh(spec, n, "100 kPa"), scene(spec, load_range(n * n)), rounds)
    out["note"] = "(first solve of a fresh interpreter each)"
    return out
