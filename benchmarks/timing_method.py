"""The analysis rows of the speed table timed both ways: one call per round, and repeated calls.

``benchmarks/summary.py`` times every in-process row by :func:`summary_design.timed` (the best
of interleaved rounds, each ~20 ms of repeated calls). Until 2026-11-30 its sweep, analysis and
one-load rows took the best single call per round (:func:`summary_design.best`). This prints,
per scene of the speed design and analysis, the analysis solve and the bare solve of the same
loads (range 1 kPa - 1 MPa) and their ratio by either method, in one process (CPU time,
``OPENBLAS_NUM_THREADS=1``, the compiled kernels built first), and writes
``results/timing_method.md``.

    python benchmarks/timing_method.py [--loads 100] [--analyses gap_pdf leakage] [--rounds 3]
"""

from __future__ import annotations

import os

os.environ["OPENBLAS_NUM_THREADS"] = "1"

import argparse  # noqa: E402
import warnings  # noqa: E402
from pathlib import Path  # noqa: E402

from summary_design import best, design, load_range, scene, timed  # noqa: E402

import xpersson  # noqa: E402

OUT = Path(__file__).resolve().parent / "results" / "timing_method.md"


def both(spec: dict, analysis: str, n: int, rounds: int) -> dict[str, float]:
    """Analysis and bare solve [ms] of ``n`` loads on ``spec``: one call and repeated calls."""
    bare = scene(spec, load_range(n))
    with_analysis = scene(spec, load_range(n), analyses={analysis: {}})
    fns = {"s": lambda: xpersson.solve(with_analysis), "k": lambda: xpersson.solve(bare)}
    one, rep = best(fns, rounds), timed(fns, rounds)
    return {f"{k}_{m}": t[k] * 1e3 for m, t in (("one", one), ("rep", rep)) for k in fns}


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--loads", type=int, default=100)
    ap.add_argument("--analyses", nargs="+", default=["gap_pdf", "leakage"])
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    from xpersson.engine import _compiled as march
    from xpersson.physics import _compiled as kernels

    march.build()  # (as summary.py: every row with the kernels built)
    kernels.kernel(float("inf"))
    lines = [
        f"# Two timings of the analysis rows ({args.loads} loads, `benchmarks/timing_method.py`)",
        "",
        "Per scene of the speed design: the analysis solve / the bare solve [ms] and their ratio,",
        "timed by the best single call of 3 interleaved rounds (`one`) and by the best of 3",
        "interleaved rounds of ~20 ms of repeated calls (`rep`, the speed table's timing since",
        "2026-11-30). CPU time, one process, OPENBLAS_NUM_THREADS=1, compiled kernels built.",
        "",
        "| analysis | scene | one: solve / bare | one: ratio | rep: solve / bare | rep: ratio |",
        "|---|---|---|---:|---|---:|",
    ]
    for analysis in args.analyses:
        for label, spec in design(12, 36):
            t = both(spec, analysis, args.loads, args.rounds)
            row = (
                f"| {analysis} | {label} | {t['s_one']:.2f} / {t['k_one']:.3f} | "
                f"{t['s_one'] / t['k_one']:.2f} | {t['s_rep']:.2f} / {t['k_rep']:.3f} | "
                f"{t['s_rep'] / t['k_rep']:.2f} |"
            )
            print(row, flush=True)
            lines.append(row)
    OUT.write_text("\n".join(lines) + "\n")
    print(f"wrote {OUT.name}")


if __name__ == "__main__":
    main()
