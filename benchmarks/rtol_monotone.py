"""Work against tolerance: a looser rtol must never cost the ``cn`` engine more.

For every scene and rtol (1e-2 .. 1e-8; 1e-2 .. 1e-7 on the walls' scenes) this records the
node-steps the engine marched (every grid level: loads x nodes x steps), its finest grid, its
true error (against the closed form, or against the engine at rtol 1e-9 where there is none)
and its own error estimate, and flags every rtol that costs more than the next tighter one.

Scenes: the peers' named fixed-wall scenes and the linearly moving wall of
``engine_vs_peers.py``, its design scenes (``design(12, seed)``, A/A0 = 0.1 .. 1e-4) for seeds
36 and 2026, and the engine problems of the speed design's ``jkr`` and
``plastic_scale_dependent`` scenes (``summary_paths._march_cases``) for the same seeds.
Default ``atol`` (``1e-7 rtol``): the window, and with it the time plan of a grid, then depends
on rtol too, so two tolerances that choose the same levels may differ by a base step (a few %).

Writes ``benchmarks/results/rtol_monotone.md``.  Usage: ``python benchmarks/rtol_monotone.py
[--seeds 36,2026] [--no-walls]`` (~2-4 minutes).
"""

from __future__ import annotations

import os

os.environ["OPENBLAS_NUM_THREADS"] = "1"

import argparse  # noqa: E402
import dataclasses  # noqa: E402
import sys  # noqa: E402
import warnings  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import engine_vs_peers as evp  # noqa: E402
from summary_design import design  # noqa: E402
from summary_paths import _march_cases  # noqa: E402

import xpersson  # noqa: E402
from xpersson.engine import _cn  # noqa: E402

RTOLS = (1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8)
WALL_RTOLS = RTOLS[:-1]
REF_RTOL = 1e-9


def marched(fn) -> tuple[object, int]:
    """``fn()`` and the node-steps of every ``cn`` level it marched."""
    seen: list[int] = []
    orig = _cn._march

    def spy(pbs, plan, n, *args):
        level = orig(pbs, plan, n, *args)
        seen.append(len(pbs) * (n + 1) * int(level.nsteps))
        return level

    _cn._march = spy
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return fn(), sum(seen)
    finally:
        _cn._march = orig


def _row(rtol: float, area, est, exact, work: int, nodes: int, ref_est=0.0) -> dict:
    """One rtol's row; ``ref_est``: the reference's own error estimate where ``exact`` is the
    engine at ``REF_RTOL`` (err/est is then judged against both estimates: a run that is more
    accurate than its reference cannot be told from it)."""
    area, exact = np.asarray(area, float), np.asarray(exact, float)
    est = np.asarray(est, float) + np.asarray(ref_est, float)
    err = np.abs(area - exact)
    judged = err > 1e-15
    return {
        "rtol": rtol,
        "work": work,
        "nodes": nodes,
        "err_tol": float(np.max(err / (rtol * np.abs(exact) + 1e-7 * rtol))),
        "err_est": float(np.max(err[judged] / est[judged])) if judged.any() else 0.0,
    }


def closed_form_rows(case) -> list[dict]:
    """The rtol rows of one ``engine_vs_peers`` scene (exact area known)."""
    rows = []
    for rtol in RTOLS:
        res, work = marched(
            lambda r=rtol: xpersson.engine.solve(
                case.tau, case.p0, case.lower, None, method="cn", rtol=r
            )
        )
        rows.append(_row(rtol, res.area, res.error_estimate, case.area, work, res.n_nodes))
    return rows


def problems(scene: dict) -> list:
    """The engine problems ``cn`` solved for ``scene`` (one per batch)."""
    got = []
    orig = _cn.CNMethod.run

    def run(self):
        got.append(self.problem)
        return orig(self)

    _cn.CNMethod.run = run
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            xpersson.solve(scene)
    finally:
        _cn.CNMethod.run = orig
    return got


def _at(pb, rtol: float):
    return dataclasses.replace(pb, rtol=rtol, atol=1e-7 * rtol)


def reference_rows(pb) -> list[dict] | None:
    """The rtol rows of one engine problem against the engine at ``REF_RTOL`` (None: the
    reference did not succeed)."""
    ref, _ = marched(lambda: _cn.CNMethod(_at(pb, REF_RTOL)).run())
    if not np.all(np.asarray(ref.status) == "success"):
        return None
    rows = []
    for rtol in WALL_RTOLS:
        raw, work = marched(lambda r=rtol: _cn.CNMethod(_at(pb, r)).run())
        rows.append(_row(rtol, raw.area, raw.error_estimate, ref.area, work,
                         int(np.max(raw.n_nodes)), ref.error_estimate))  # fmt: skip
    return rows


def wall_cases(seeds: list[int]) -> list[tuple[str, object]]:
    """(label, problem) of the ``jkr`` and plastic scenes of the speed design that march."""
    out, seen = [], set()
    for seed in seeds:
        for name, spec in design(12, seed):
            if repr(spec) in seen:
                continue
            seen.add(repr(spec))
            cases = _march_cases(spec)
            for kind, key in (("jkr", "engine (jkr) vs C march, rtol 1e-6"),
                              ("plastic", "plastic_scale_dependent vs C march")):  # fmt: skip
                out += [(f"seed {seed}: {name}, {kind}", pb) for pb in problems(cases[key][0])]
    return out


def looser_dearer(rows: list[dict]) -> list[str]:
    """``rtol a > b: x``: the rtols (loose to tight) whose work exceeds the next tighter one's."""
    return [
        f"{a['rtol']:g} > {b['rtol']:g}: {a['work'] / b['work']:.2f}x"
        for a, b in zip(rows, rows[1:], strict=False)
        if a["work"] > b["work"]
    ]


def write(results: list[tuple[str, list[dict]]], path: Path) -> None:
    lines = [
        "# Work against tolerance (cn)",
        "",
        "Node-steps per rtol (loose to tight); `looser dearer`: an rtol that cost more than the "
        "next tighter one (ratio); worst true error / tolerance and worst true error / own "
        "estimate over the rtols (errors below 1e-15 not judged; for the `jkr` and plastic rows, "
        "whose reference is the engine at rtol 1e-9, the estimate is the run's plus the "
        "reference's own). Command: "
        "`python benchmarks/rtol_monotone.py`.",
        "",
        "| scene | node-steps per rtol | finest grid per rtol | looser dearer | "
        "worst err/tol | worst err/est |",
        "|---|---|---|---|---:|---:|",
    ]
    for label, rows in results:
        work = " / ".join(f"{r['work']:.3g}" for r in rows)
        nodes = " / ".join(str(r["nodes"]) for r in rows)
        dear = "; ".join(looser_dearer(rows)) or "-"
        e_tol = max(r["err_tol"] for r in rows)
        e_est = max(r["err_est"] for r in rows)
        lines.append(f"| {label} | {work} | {nodes} | {dear} | {e_tol:.2f} | {e_est:.2f} |")
    path.write_text("\n".join(lines) + "\n")


def main(argv: list[str] | None = None) -> list[tuple[str, list[dict]]]:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", default="36,2026")
    ap.add_argument("--no-walls", action="store_true", help="skip the jkr and plastic scenes")
    ap.add_argument("--out", type=Path, default=HERE / "results" / "rtol_monotone.md")
    args = ap.parse_args(argv)
    seeds = [int(s) for s in args.seeds.split(",")]
    cases = [evp.named_case(n) for n in evp.NAMED] + [evp.moving_case()]
    for seed in seeds:
        cases += evp.design_cases(seed, 12)
    results, seen = [], set()
    for case in cases:
        if (float(case.tau[-1]), case.p0) in seen:  # (the named design scenes of every seed)
            continue
        seen.add((float(case.tau[-1]), case.p0))
        results.append((case.name, closed_form_rows(case)))
        print(results[-1][0], looser_dearer(results[-1][1]), flush=True)
    for label, pb in [] if args.no_walls else wall_cases(seeds):
        rows = reference_rows(pb)
        if rows is not None and any(r["work"] for r in rows):
            results.append((label, rows))
            print(label, looser_dearer(rows), flush=True)
    write(results, args.out)
    return results


if __name__ == "__main__":
    main()
