"""The engine against its compiled limit on the speed design and on held-out scenes (issue 36).

For every scene of ``summary_design.design(n, seed)`` on which the engine marches ``cn``
levels (the ``jkr`` scene of ``summary.py``'s "engine alone" rows, at rtol 1e-6 and 1e-8):
``xpersson.engine.solve_batch`` on the problem the pipeline prepared
(:func:`cn_walls.engine_call_of`, compiled march built) against the C march of
``peers/c_march`` over the same levels and steps (:func:`cn_walls.levels_of`), and the
node-steps. Seed 36 is the design of ``summary.py``; other seeds are held-out scenes.
CPU time (``time.process_time``), ``OPENBLAS_NUM_THREADS=1``, best of ``--rounds``
interleaved rounds, each timed call repeated to ~20 ms.

Usage: ``python benchmarks/engine_limit.py [--seeds 36 101 202] [--rounds 5]``; prints one row
per marching scene and tolerance, and the worst ratio per seed and tolerance.
"""

from __future__ import annotations

import os

os.environ["OPENBLAS_NUM_THREADS"] = "1"

import argparse  # noqa: E402
import sys  # noqa: E402
import warnings  # noqa: E402
from pathlib import Path  # noqa: E402

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import summary_paths as SP  # noqa: E402
from cn_walls import engine_call_of, levels_of  # noqa: E402
from summary_design import best, design, scene  # noqa: E402

PEERS = Path(os.environ.get("XPERSSON_PEERS", HERE.parents[1] / "shared" / "peers"))


def jkr_scene(spec: dict, rtol: float) -> dict:
    """The "engine alone (jkr) vs C march" scene of ``summary.py`` on ``spec``."""
    sc = scene(spec, "1000 Pa", boundary=SP.JKR)
    sc["material"] = dict(SP.JKR_MATERIAL)
    sc["solver"] = {"rtol": rtol, "method": "cn"}
    sc["output"] = {"zeta_per_decade": 4}
    return sc


def measure(lib, sc: dict, rounds: int) -> dict | None:
    """Engine-alone and C-march CPU times [s] of ``sc``, its levels' node-steps (None: no
    ``cn`` level marched)."""
    from march_vs_engine import c_march

    levels = levels_of(sc)
    if not levels:
        return None
    fns = {"e": engine_call_of(sc), "k": lambda: c_march(lib, levels)}
    reps = {k: SP._repeated(f) for k, f in fns.items()}
    t = best({k: many for k, (many, _) in reps.items()}, rounds)
    t = {k: t[k] / reps[k][1] for k in t}
    steps = sum(a * b * c for a, b, c in levels)
    return {"engine": t["e"], "c": t["k"], "ratio": t["e"] / t["k"], "node_steps": steps}


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, nargs="+", default=[36])
    ap.add_argument("--scenes", type=int, default=12)
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--rtols", type=float, nargs="+", default=[1e-6, 1e-8])
    args = ap.parse_args(argv)
    from xpersson.engine import _compiled

    print("march:", "compiled" if _compiled.build() else "numpy (no numba)")
    lib = SP.c_march_lib(PEERS)
    if lib is None:
        return
    warnings.simplefilter("ignore")
    for seed in args.seeds:
        worst: dict[float, tuple[float, str]] = {}
        for label, spec in design(args.scenes, seed):
            for rtol in args.rtols:
                try:
                    m = measure(lib, jkr_scene(spec, rtol), args.rounds)
                except Exception as exc:  # noqa: BLE001 - reported, the design goes on
                    print(f"seed {seed:4d} {label:20s} rtol {rtol:.0e}: {type(exc).__name__}:"
                          f" {str(exc)[-120:]}")  # fmt: skip
                    continue
                if m is None:
                    continue
                print(
                    f"seed {seed:4d} {label:20s} rtol {rtol:.0e}: engine {m['engine'] * 1e3:8.3f}"
                    f" ms, C {m['c'] * 1e3:8.3f} ms, ratio {m['ratio']:5.2f},"
                    f" {m['node_steps']:.3g} node-steps",
                    flush=True,
                )
                if m["ratio"] > worst.get(rtol, (0.0, ""))[0]:
                    worst[rtol] = (m["ratio"], label)
        for rtol, (r, label) in sorted(worst.items()):
            print(f"seed {seed}: worst at rtol {rtol:.0e}: {r:.2f} ({label})")


if __name__ == "__main__":
    main()
