"""``gap_pdf`` and ``leakage`` between the load counts of the README's speed table.

The table (``benchmarks/summary.py``) measures the analyses at 100, 1000 and 1e4 loads. A claim
made at those counts must hold between them: the load table (``xpersson_interface._by_load``)
starts where the loads are 3 times its nodes, and the direct path below costs ~100 us per load.
Per scene of the speed design (``summary_design.design``, or ``--held-out SEED``'s draw) and
load count (range 1 kPa - 1 MPa), each analysis's whole solve over the bare solve of the same
loads (CPU time per solve, best of ``--rounds`` interleaved rounds of ~20 ms of repeated
solves each (``summary_design.timed``, as ``summary.py``), one process,
``OPENBLAS_NUM_THREADS=1``; the optional compiled kernels built first, as ``summary.py``
does: a fresh process runs small problems on numpy until its numpy work adds up to their
build's cost, a study's eighth to 14th solve here, ``fresh_process.py``); printed per scene,
then the worst per analysis and count. Writes
``results/load_counts[_SEED].json`` unless ``--check``.

    OPENBLAS_NUM_THREADS=1 python benchmarks/load_counts.py [--loads 150 200 300 600]
        [--held-out SEED] [--rounds 3] [--check]
"""

from __future__ import annotations

import argparse
import json
import sys
import warnings
from pathlib import Path

from summary_design import design, held_out, load_range, scene, timed

import xpersson

ANALYSES = ("gap_pdf", "leakage")


def measure(spec: dict, n: int, rounds: int) -> dict[str, float]:
    """Each analysis's solve over the bare solve of ``n`` loads on the scene ``spec``."""
    bare = scene(spec, load_range(n))
    fns = {"bare": lambda: xpersson.solve(bare)}
    for an in ANALYSES:
        sc = scene(spec, load_range(n), analyses={an: {}})
        fns[an] = lambda sc=sc: xpersson.solve(sc)
    for fn in fns.values():  # warm: caches and compiled kernels
        fn()
    t = timed(fns, rounds)
    return {an: t[an] / t["bare"] for an in ANALYSES} | {"bare_ms": t["bare"] * 1e3}


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--loads", type=int, nargs="+", default=[150, 200, 300, 600])
    ap.add_argument("--held-out", type=int, default=None)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--check", action="store_true", help="print only; write nothing")
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    from xpersson.engine import _compiled as march
    from xpersson.physics import _compiled as kernels

    march.build()  # (as summary.py's warm_up: every row with the kernels built)
    kernels.kernel(float("inf"))
    scenes = design(12, 36) if args.held_out is None else held_out(12, args.held_out)
    rows, worst = [], {}
    for name, spec in scenes:
        for n in args.loads:
            r = measure(spec, n, args.rounds)
            rows.append({"scene": name, "loads": n, **r})
            print(f"{name:22s} {n:6d} loads  " + "  ".join(f"{a} {r[a]:6.2f}" for a in ANALYSES))
            for an in ANALYSES:
                if r[an] > worst.get(f"{an} {n}", {"ratio": 0.0})["ratio"]:
                    worst[f"{an} {n}"] = {"ratio": round(r[an], 2), "scene": name}
    for key, w in worst.items():
        print(f"worst {key} loads: {w['ratio']:.2f}x ({w['scene']})")
    if not args.check:
        tag = "" if args.held_out is None else f"_{args.held_out}"
        out = Path(__file__).parent / "results" / f"load_counts{tag}.json"
        out.write_text(json.dumps({"rows": rows, "worst": worst}, indent=1) + "\n")
        print(f"wrote {out.name}")


if __name__ == "__main__":
    sys.exit(main())
