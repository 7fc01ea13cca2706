"""Cost of the interface analyses at 100 loads, as a ratio to the bare elastic solve (issue 10).

Run from the checkout (after ``pip install -r requirements-dev.txt``)::

    python benchmarks/interface_analyses.py [--loads 100] [--repeat 7]

One process, ``OPENBLAS_NUM_THREADS=1`` (set here before numpy is imported). The scene is the
physics.md §1.4 spectrum with ``--loads`` nominal pressures log-spaced from 1 kPa to 3 MPa
(A/A0 from 1e-3 to 1 - 1e-7). For each analysis the same scene is solved with only that
analysis requested; its cost is ``t(scene + analysis) - t(bare scene)`` (best of ``--repeat``,
both measured in this run), reported per load and as a ratio to the bare solve. The table is
written to ``benchmarks/results/interface_analyses.md``.
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


def best(sc: dict, repeat: int) -> float:
    xpersson.solve(sc)  # warm-up (imports, caches)
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        xpersson.solve(sc)
        times.append(time.perf_counter() - t)
    return min(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--loads", type=int, default=100)
    ap.add_argument("--repeat", type=int, default=7)
    args = ap.parse_args()
    n = args.loads
    bare = best(scene(n), args.repeat)
    rows = []
    for name, params in ANALYSES.items():
        t = best(scene(n, {name: params}), args.repeat)
        extra = max(t - bare, 0.0)
        rows.append((name, extra / n * 1e3, extra / bare))
    lines = [
        f"# Interface analyses: cost at {n} loads (ratio to the bare elastic solve)",
        "",
        f"Measured in one process by `python benchmarks/interface_analyses.py`, "
        f"OPENBLAS_NUM_THREADS=1, best of {args.repeat}; {platform.machine()}, "
        f"Python {platform.python_version()}, numpy {np.__version__}.",
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
