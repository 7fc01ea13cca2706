"""The engine against its compiled limit on the speed design and on held-out scenes (issue 36).

For every scene of ``summary_design.design(n, seed)`` on which the engine marches ``cn``
levels (the ``jkr`` scene of ``summary.py``'s "engine alone" rows, at rtol 1e-6 and 1e-8):
``xpersson.engine.solve_batch`` on the problem the pipeline prepared
(:func:`cn_walls.engine_call_of`, compiled march built) against the C march of
``peers/c_march`` over the same levels and steps (:func:`cn_walls.levels_of`), and the
node-steps. Seed 36 is the design of ``summary.py``; ``--held-out SEED`` draws the held-out
scenes of ``summary.py --held-out SEED`` (:func:`summary_design.held_out`). A scene on which
the engine marches no level (the wall stays outside the window up to the last output: the
analytic start is exact) has no C counterpart: it is listed, with the engine's time, not
ranked.
CPU time (``time.process_time``), ``OPENBLAS_NUM_THREADS=1``, best of ``--rounds``
interleaved rounds, each timed call repeated to ~20 ms.

Usage: ``python benchmarks/engine_limit.py [--seeds 36 101 202] [--held-out 2026] [--rounds 5]``;
prints one row per scene and tolerance, and the worst ratio per design and tolerance.
``--against OTHER [--runs 3]``: the same benchmark on this tree and on the checkout ``OTHER``
(its ``src`` and plugins' ``src`` on ``PYTHONPATH``; e.g. a ``git worktree`` of an older
commit), each run a fresh process, alternated ``--runs`` times, rows prefixed by the tree: a
before/after that the shared machine's load changes less than two separate runs would.
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
from summary_design import design, held_out, scene, timed  # noqa: E402

PEERS = Path(os.environ.get("XPERSSON_PEERS", HERE.parents[1] / "shared" / "peers"))


def jkr_scene(spec: dict, rtol: float) -> dict:
    """The "engine alone (jkr) vs C march" scene of ``summary.py`` on ``spec``."""
    sc = scene(spec, "1000 Pa", boundary=SP.JKR)
    sc["material"] = dict(SP.JKR_MATERIAL)
    sc["solver"] = {"rtol": rtol, "method": "cn"}
    sc["output"] = {"zeta_per_decade": 4}
    return sc


def measure(lib, sc: dict, rounds: int) -> dict:
    """Engine-alone and C-march CPU times [s] of ``sc``, its levels' node-steps; without a
    marched ``cn`` level the engine's time and why (``no_march``)."""
    from march_vs_engine import c_march

    levels = levels_of(sc)
    fns = {"e": engine_call_of(sc)}
    if levels:
        fns["k"] = lambda: c_march(lib, levels)
    t = timed(fns, rounds)
    if not levels:
        return {"engine": t["e"], "no_march": SP._no_march(fns["e"]())}
    steps = sum(a * b * c for a, b, c in levels)
    return {"engine": t["e"], "c": t["k"], "ratio": t["e"] / t["k"], "node_steps": steps}


def run_design(lib, tag: str, scenes: list, rtols: list[float], rounds: int) -> None:
    """One row per scene and tolerance of ``scenes``, then the worst ratio per tolerance."""
    worst: dict[float, tuple[float, str]] = {}
    for label, spec in scenes:
        for rtol in rtols:
            head = f"{tag} {label:20s} rtol {rtol:.0e}:"
            try:
                m = measure(lib, jkr_scene(spec, rtol), rounds)
            except Exception as exc:  # noqa: BLE001 - reported, the design goes on
                print(f"{head} {type(exc).__name__}: {str(exc)[-120:]}")
                continue
            if "no_march" in m:
                print(f"{head} engine {m['engine'] * 1e3:8.3f} ms, {m['no_march']}", flush=True)
                continue
            print(
                f"{head} engine {m['engine'] * 1e3:8.3f} ms, C {m['c'] * 1e3:8.3f} ms, ratio"
                f" {m['ratio']:5.2f}, {m['node_steps']:.3g} node-steps",
                flush=True,
            )
            if m["ratio"] > worst.get(rtol, (0.0, ""))[0]:
                worst[rtol] = (m["ratio"], label)
    for rtol, (r, label) in sorted(worst.items()):
        print(f"{tag}: worst at rtol {rtol:.0e}: {r:.2f} ({label})")


def alternate(other: Path, runs: int, argv: list[str]) -> None:
    """This benchmark on this tree and on ``other`` in alternate fresh processes, ``runs``
    times each (``argv`` without ``--against``/``--runs``)."""
    import subprocess

    rest, skip = [], False
    for a in argv:
        if skip or a in ("--against", "--runs"):
            skip = not skip
            continue
        rest.append(a)
    trees = {"this": HERE.parent, "other": other.resolve()}
    for run in range(1, runs + 1):
        for tag, root in trees.items():
            srcs = [root / "src", *sorted(root.glob("plugins/*/src"))]
            env = {**os.environ, "PYTHONPATH": os.pathsep.join(map(str, srcs))}
            cmd = [sys.executable, __file__, *rest]
            out = subprocess.run(cmd, env=env, capture_output=True, text=True, check=False)
            for line in out.stdout.splitlines():
                if "no level" not in line:
                    print(f"{tag} {run} {line}", flush=True)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, nargs="*", default=[36])
    ap.add_argument("--held-out", type=int, nargs="*", default=[], metavar="SEED")
    ap.add_argument("--scenes", type=int, default=12)
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--rtols", type=float, nargs="+", default=[1e-6, 1e-8])
    ap.add_argument("--against", type=Path, default=None, metavar="OTHER")
    ap.add_argument("--runs", type=int, default=3)
    args = ap.parse_args(argv)
    if args.against is not None:
        alternate(args.against, args.runs, sys.argv[1:] if argv is None else argv)
        return
    from xpersson.engine import _compiled

    print("march:", "compiled" if _compiled.build() else "numpy (no numba)")
    lib = SP.c_march_lib(PEERS)
    if lib is None:
        return
    warnings.simplefilter("ignore")
    for seed in args.seeds:
        run_design(lib, f"seed {seed:4d}", design(args.scenes, seed), args.rtols, args.rounds)
    for seed in args.held_out:
        scenes = held_out(args.scenes, seed)
        run_design(lib, f"held-out {seed}", scenes, args.rtols, args.rounds)


if __name__ == "__main__":
    main()
