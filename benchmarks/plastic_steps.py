"""``plastic_scale_dependent`` per scene: node-steps, ms per load, and error / estimate.

The scene is the one of ``summary_paths.march_paths`` (steel, loads 5, 20, 100 MPa,
``summary_paths.PLASTIC`` on a spectrum of the design).  For every scene of the design
(``summary_design.design()``, seed 36, the scenes the step rules were tuned on) and for
held-out scenes (drawn with other seeds, never used to tune; only those whose solve marches):

* the grid levels the engine marched (``cn_walls.levels_of``): their node-steps, and whether
  a yield wall made the window stiff (``xpersson.engine._stiff``);
* CPU ms per load (``time.process_time``, best of ``--rounds`` after a warm-up, the compiled
  march on, ``OPENBLAS_NUM_THREADS=1``);
* held-out scenes only (``--check``): the engine's elastic area against the reference of
  ``plastic_design.accuracy`` (the same engine call at a tight tolerance): the worst ratio
  ``|A - A_ref| / error_estimate`` over loads and magnifications (the estimate is honest where
  the ratio is <= 1); and the plastic area's error over the tolerance of the load identity
  through which it is controlled (``rtol max(p0, Y) / Y``, absolute).  The wider held-out
  design (24+ scenes across the documented domain) is ``plastic_design.py``.

Usage: ``python benchmarks/plastic_steps.py [--rounds 3] [--check] [--held-out 6]``; writes
``benchmarks/results/plastic_steps.md``.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import sys  # noqa: E402
import warnings  # noqa: E402
from pathlib import Path  # noqa: E402

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from cn_walls import levels_of  # noqa: E402
from plastic_design import accuracy  # noqa: E402
from summary_design import best, design, scene  # noqa: E402
from summary_paths import PLASTIC, STEEL  # noqa: E402

import xpersson  # noqa: E402

LOADS = ["5 MPa", "20 MPa", "100 MPa"]
HELD_OUT_SEEDS = range(110, 160)  # (101, 102 were looked at while tuning)


def plastic_scene(spec: dict) -> dict:
    """The ``plastic_scale_dependent vs C march`` scene on ``spec``."""
    sc = scene(spec, LOADS, boundary=PLASTIC)
    sc["material"] = dict(STEEL)
    return sc


def stiff(sc: dict) -> bool:
    """Whether some load's march met a stiff window (spy on ``_stiff.stiff_at_end``)."""
    from xpersson.engine import _cn_control

    seen: list[bool] = []
    orig = _cn_control.stiff_at_end

    def spy(pbs, k):
        out = orig(pbs, k)
        seen.append(out)
        return out

    _cn_control.stiff_at_end = spy
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            xpersson.solve(sc)
    finally:
        _cn_control.stiff_at_end = orig
    return any(seen)


def cost(label: str, spec: dict, rounds: int) -> dict:
    """Node-steps, levels and CPU ms per load of the scene on ``spec``."""
    sc = plastic_scene(spec)
    levels = levels_of(sc)
    t = best({"s": lambda: xpersson.solve(sc)}, rounds)["s"]
    return {
        "scene": label,
        "levels": len(levels),
        "node_steps": sum(a * b * c for a, b, c in levels),
        "ms_per_load": t / len(LOADS) * 1e3,
        "stiff": stiff(sc) if levels else False,
    }


def honesty(spec: dict) -> dict:
    """Worst ``|A - A_ref| / estimate`` of the elastic area (``elastic``) and the plastic
    area's error over the tolerance of its load identity (``plastic``) against a tight
    reference (``plastic_design.accuracy``)."""
    acc = accuracy(plastic_scene(spec))
    return {"elastic": acc["err_est"], "plastic": acc["plastic"], "ref_status": acc["ref_status"]}


def held_out(n: int) -> list[tuple[str, dict]]:
    """``n`` scenes of other seeds whose plastic solve marches (the named two excluded)."""
    out: list[tuple[str, dict]] = []
    tuned = {label for label, _ in design()}
    for seed in HELD_OUT_SEEDS:
        for label, spec in design(12, seed)[2:]:
            if label in tuned or any(label == lb for lb, _ in out):
                continue
            if levels_of(plastic_scene(spec)):
                out.append((f"{label} (seed {seed})", spec))
                break
        if len(out) >= n:
            break
    return out


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--check", action="store_true", help="also error / estimate (held-out)")
    ap.add_argument("--held-out", type=int, default=6)
    args = ap.parse_args(argv)
    xpersson.set_options(compiled=True)
    lines = [
        "| scene | set | levels | node-steps | ms/load | stiff window | "
        "max err/est (elastic) | max err/(rtol scale) (plastic; reference status) |",
        "|---|---|---:|---:|---:|---|---:|---:|",
    ]
    rows = [(lb, sp, "design") for lb, sp in design()]
    rows += [(lb, sp, "held-out") for lb, sp in held_out(args.held_out)]
    worst = 0.0
    for label, spec, kind in rows:
        c = cost(label, spec, args.rounds)
        h = honesty(spec) if args.check and kind == "held-out" and c["levels"] else None
        e = f"{h['elastic']:.3g}" if h else "-"
        p = f"{h['plastic']:.3g} ({', '.join(h['ref_status'])})" if h else "-"
        if h:
            worst = max(worst, h["elastic"])
        line = (
            f"| {label} | {kind} | {c['levels']} | {c['node_steps']:.3g} | "
            f"{c['ms_per_load']:.1f} | {'yes' if c['stiff'] else 'no'} | {e} | {p} |"
        )
        print(line, flush=True)
        lines.append(line)
    text = "\n".join(lines)
    if args.check:
        text += f"\n\nWorst error / estimate (elastic area, held-out scenes): {worst:.3g}"
    out = HERE / "results"
    out.mkdir(exist_ok=True)
    (out / "plastic_steps.md").write_text(
        "# `plastic_scale_dependent`: node-steps, ms per load, error / estimate\n\n"
        f"CPU time, best of {args.rounds} rounds, compiled march, OPENBLAS_NUM_THREADS=1; "
        "shared 2-core machine. Reference: the engine at rtol 1e-8, atol 1e-14.\n\n" + text + "\n"
    )
    print(text)


if __name__ == "__main__":
    main()
