"""Where one ``xpersson.solve`` spends its time: the pipeline's stages, per solve.

The fixed cost of the pipeline around one load (issue 36), on scenes of the speed design
(``summary_design.py``): the elastic closed-form load of the row "one closed-form load vs its
kernel", the ``jkr`` load of "jkr, one load vs C march" and that scene at ``rtol = 1e-6`` with
the ``cn`` march (the engine rows), on 'roll H=0.30 6dec'; and the ``jkr`` load on
'roll H=0.39 4dec', the design's worst scene of the "jkr, one load" row (its wall moves: the
``cn`` march runs, with the compiled march built here as the row builds it). Each stage is a
function of the pipeline wrapped with a CPU-time counter (``time.process_time_ns``, this
process only: the machine may be shared); a stage's time includes the stages it calls
(``attributes`` holds ``global_attributes``, ``engine.solve_batch`` holds ``finish_batch``).
The table gives, per scene, the round (of ``--rounds``, ``--solves`` solves each) with the
smallest total, in microseconds per solve.

Run: ``OPENBLAS_NUM_THREADS=1 python benchmarks/solve_stages.py [--rounds 7] [--solves 40]``.
Compare two versions of the code by running it with each one's ``PYTHONPATH``.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import collections  # noqa: E402
import copy  # noqa: E402
import importlib  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402
from pathlib import Path  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))

from summary_design import design, scene  # noqa: E402
from summary_paths import JKR, JKR_MATERIAL  # noqa: E402

import xpersson  # noqa: E402

P = "xpersson.pipeline."
#: (module, function, the modules that imported it by name, label)
STAGES = [
    ("xpersson.api", "expand", (), "sweep.expand (is it a sweep?)"),
    ("xpersson.scene._scene", "resolve_scene", (), "Scene.resolve"),
    (P + "stages", "validate", (P + "run",), "validate"),
    (P + "frontend", "diffusion_clock", (P + "run",), "diffusion_clock"),
    (P + "stages", "coefficient_arrays", (P + "run",), "coefficient_arrays"),
    (P + "stages", "load_walls", (P + "run",), "load_walls"),
    ("xpersson.engine", "solve_batch", (), "engine.solve_batch"),
    ("xpersson.engine._result", "finish_batch", ("xpersson.engine._api",), "  finish_batch"),
    (P + "assemble", "assemble", (P + "run",), "assemble"),
    ("xpersson.checks", "check_core", (), "check_core"),
    (P + "assemble", "add_outputs", (P + "run",), "add_outputs"),
    (P + "assemble", "diagnostics_notes", (P + "run",), "diagnostics_notes"),
    (P + "assemble", "attributes", (P + "run",), "attributes"),
    ("xpersson.provenance", "global_attributes", (), "  global_attributes"),
    (P + "assemble", "squeeze_p0", (P + "run",), "squeeze_p0"),
    (P + "model_error", "attach", ("xpersson.api",), "model_error.attach"),
]


def _jkr(spec: dict) -> dict:
    """The "jkr, one load" row's scene on a design spectrum."""
    jkr = scene(spec, "1000 Pa", boundary=JKR)
    jkr["material"] = dict(JKR_MATERIAL)
    return jkr


def scenes() -> dict[str, dict]:
    """Three scenes on the design's scene 'roll H=0.30 6dec', the jkr load on 'roll H=0.39
    4dec'."""
    specs = dict(design())
    spec = specs["roll H=0.30 6dec"]
    jkr = _jkr(spec)
    tight = copy.deepcopy(jkr)
    tight["solver"] = {"rtol": 1e-6, "method": "cn"}
    tight["output"] = {"zeta_per_decade": 4}
    return {
        "elastic, one load": scene(spec, "100 kPa"),
        "jkr, one load": jkr,
        "jkr, cn": tight,
        "jkr, one load (H=0.39 4dec)": _jkr(specs["roll H=0.39 4dec"]),
    }


def instrument(spent: dict[str, float]) -> None:
    """Wrap every stage with a CPU-time counter adding to ``spent[label]`` [ns]."""
    for mod, name, users, label in STAGES:
        module = importlib.import_module(mod)
        fn = getattr(module, name, None)
        if fn is None:  # another version of the code: no such stage
            continue

        def timed(*args, _fn=fn, _label=label, **kwargs):
            t0 = time.process_time_ns()
            try:
                return _fn(*args, **kwargs)
            finally:
                spent[_label] += time.process_time_ns() - t0

        setattr(module, name, timed)
        for user in users:
            setattr(importlib.import_module(user), name, timed)


def measure(sc: dict, spent: dict[str, float], rounds: int, solves: int) -> dict[str, float]:
    """Per-solve microseconds of every stage in the round with the smallest total."""
    for _ in range(50):  # warm-up: imports, process caches, the compiled march's rule
        xpersson.solve(sc)
    best: dict[str, float] | None = None
    for _ in range(rounds):
        spent.clear()
        t0 = time.process_time_ns()
        for _ in range(solves):
            xpersson.solve(sc)
        row = {k: v / solves / 1e3 for k, v in spent.items()}
        row["solve (total)"] = (time.process_time_ns() - t0) / solves / 1e3
        if best is None or row["solve (total)"] < best["solve (total)"]:
            best = row
    assert best is not None
    return best


def main(argv: list[str] | None = None) -> str:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--solves", type=int, default=40)
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    from xpersson.engine import _compiled

    _compiled.build()  # the compiled march in force, as the C-march rows have it
    spent: dict[str, float] = collections.defaultdict(float)
    instrument(spent)
    rows = {k: measure(sc, spent, args.rounds, args.solves) for k, sc in scenes().items()}
    labels = ["solve (total)"] + [label for *_, label in STAGES]
    lines = [
        "| stage [us per solve] | " + " | ".join(rows) + " |",
        "|---" + "|---:" * len(rows) + "|",
    ]
    for label in labels:
        cells = [f"{r[label]:.0f}" if label in r else "-" for r in rows.values()]
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    text = "\n".join(lines)
    print(text)
    return text


if __name__ == "__main__":
    main()
