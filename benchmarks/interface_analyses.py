"""Cost of the interface analyses at 100 loads, as a ratio to the bare elastic solve (issue 10).

Run from the checkout (after ``pip install -r requirements-dev.txt``)::

    python benchmarks/interface_analyses.py [--loads 100] [--repeat 7]

One process, ``OPENBLAS_NUM_THREADS=1`` (set here before numpy is imported). The scene is the
physics.md §1.4 spectrum with ``--loads`` nominal pressures log-spaced from 1 kPa to 3 MPa
(A/A0 from 1e-3 to 1 - 1e-7). For each analysis the same scene is solved with only that
analysis requested; its cost is ``t(scene + analysis) - t(bare scene)``, reported per load and
as a ratio to the bare solve. Times are CPU times of this process (``time.process_time``: the
machine is shared, wall time measures the neighbours), the best of ``--repeat`` rounds in which
the bare scene and every analysis scene are solved in turn. The table is written to
``benchmarks/results/interface_analyses.md``.
"""

from __future__ import annotations

import os

os.environ["OPENBLAS_NUM_THREADS"] = "1"

import argparse  # noqa: E402
import platform  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

import xpersson  # noqa: E402

ANALYSES = {
    "elastic_energy": {},
    "mean_gap": {},
    "contact_stiffness": {},
    "gap_pdf": {},
    "leakage": {},
    "contact_area": {},
}


def scene(n: int, analyses: dict | None = None) -> dict:
    return {
        "spectrum": {"model": "self_affine", "H": 0.8, "q_L": "1e3 1/m", "q_r": "1e4 1/m",
                     "q_1": "1e8 1/m", "h_rms": "1 um"},
        "material": {"E": "10 MPa", "nu": 0.5},
        "load": {"p0": [f"{float(p)!r} Pa" for p in np.geomspace(1e3, 3e6, n)]},
        "analyses": analyses or {},
    }  # fmt: skip


def cpu(sc: dict) -> float:
    t = time.process_time()
    xpersson.solve(sc)
    return time.process_time() - t


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--loads", type=int, default=100)
    ap.add_argument("--repeat", type=int, default=7)
    args = ap.parse_args()
    n = args.loads
    scenes = {"": scene(n)} | {a: scene(n, {a: p}) for a, p in ANALYSES.items()}
    for sc in scenes.values():
        xpersson.solve(sc)  # warm-up (imports, caches)
    best = dict.fromkeys(scenes, float("inf"))
    for _ in range(args.repeat):  # interleaved rounds
        for key, sc in scenes.items():
            best[key] = min(best[key], cpu(sc))
    bare = best.pop("")
    rows = []
    for name, t in best.items():
        extra = max(t - bare, 0.0)
        rows.append((name, extra / n * 1e3, extra / bare))
    lines = [
        f"# Interface analyses: cost at {n} loads (ratio to the bare elastic solve)",
        "",
        f"Measured in one process by `python benchmarks/interface_analyses.py`, "
        f"OPENBLAS_NUM_THREADS=1, CPU time, best of {args.repeat} interleaved rounds; "
        f"{platform.machine()}, Python {platform.python_version()}, numpy {np.__version__}.",
        f"Bare elastic solve of the {n}-load scene: {bare * 1e3:.1f} ms "
        f"({bare / n * 1e3:.3f} ms per load).",
        "",
        "| analysis | extra time per load [ms] | ratio to the bare solve |",
        "|---|---:|---:|",
    ]
    lines += [f"| `{a}` | {ms:.3f} | {r:.2f} |" for a, ms, r in rows]
    text = "\n".join(lines) + "\n"
    print(text)
    out = Path(__file__).resolve().parent / "results" / "interface_analyses.md"
    out.write_text(text)


if __name__ == "__main__":
    main()
