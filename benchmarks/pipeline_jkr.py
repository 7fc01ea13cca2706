"""The pipeline's fixed cost around the engine for one ``jkr`` load: a per-stage account.

For one scene of the speed design (``summary_paths._march_cases``: the ``jkr`` scene of a row
such as ``engine (jkr) vs C march, rtol 1e-6``), in one process, CPU time
(``time.process_time_ns``), best of interleaved rounds of repeated calls:

* ``solve``: ``xpersson.solve(scene)``;
* ``engine alone``: the engine's own call on the arguments the pipeline prepared
  (``cn_walls.engine_call_of``);
* ``pipeline, engine handed back``: ``xpersson.solve`` with ``engine.solve_batch`` replaced by
  one that returns the result it computed once: the pipeline's own cost, without the engine's
  caches and memory traffic between its pieces;
* each stage's inclusive time inside ``solve`` (the stage's function wrapped by a timer; a
  wrapper costs ~0.3 us per call).

``solve - engine alone - pipeline, engine handed back`` is what the engine and the pipeline
cost each other inside one solve (caches evicted between them: every piece costs 1.5-3x its
isolated time inside a solve).

Usage::

    OPENBLAS_NUM_THREADS=1 python benchmarks/pipeline_jkr.py [--vary]
    python benchmarks/pipeline_jkr.py --seed 36 --scene "flat H=0.39 4dec" --row "jkr, one load"
    python benchmarks/pipeline_jkr.py --seed 36 --scene "roll H=0.60 5dec" --closed-form --vary

``--vary`` gives every solve a new load (``p0`` changed in its ninth digit): each solve then
parses a new load and resolves a scene not seen before, as a user's next scene does.
``--closed-form`` measures the elastic scene of the row "one closed-form load vs its kernel"
(one absorbing wall: the closed form) on the named spectrum instead of a ``jkr`` row.
"""

from __future__ import annotations

import argparse
import functools
import importlib
import sys
import time
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))

#: (module, attribute, label) of the stages timed inside a solve (inclusive times; nested ones
#: are inside their parents: ``global_attributes`` inside ``attributes``).
STAGES = [
    ("xpersson.api", "as_scene", "as_scene (scene dict -> Scene)"),
    ("xpersson.api", "expand", "expand (is it a sweep?)"),
    ("xpersson.scene._scene", "Scene.resolve", "Scene.resolve (parse, plugins, spectrum)"),
    ("xpersson.pipeline.run", "scene_context", "scene_context"),
    ("xpersson.pipeline.run", "validate", "validate (jkr: sigma_a(1), Tabor warning)"),
    ("xpersson.pipeline.run", "diffusion_clock", "diffusion_clock"),
    ("xpersson.pipeline.run", "coefficient_arrays", "coefficient_arrays (tau, f; checked)"),
    ("xpersson.pipeline.run", "load_walls", "load_walls (jkr wall, PCHIP table; checked)"),
    ("xpersson.engine", "solve_batch", "engine.solve_batch"),
    ("xpersson.pipeline.run", "assemble", "assemble (core variables)"),
    ("xpersson.checks", "check_core", "check_core"),
    ("xpersson_adhesion.jkr", "JKRBoundary.interpret", "jkr interpret"),
    ("xpersson.pipeline.run", "add_outputs", "add_outputs (jkr's 11, checked)"),
    ("xpersson.pipeline.run", "diagnostics_notes", "diagnostics_notes (theory_validity)"),
    ("xpersson.pipeline.run", "attributes", "attributes (global, status, solver)"),
    ("xpersson.provenance", "global_attributes", "  of which global_attributes"),
    ("xpersson.pipeline._draft", "Draft.squeeze", "Draft.squeeze (one load)"),
    ("xpersson.pipeline.model_error", "attach", "model_error.attach"),
    ("xpersson.pipeline._draft", "Draft.dataset", "Draft.dataset"),
]


def _wrap(acc: dict[str, int], module: str, attr: str, label: str) -> None:
    """Replace ``module.attr`` (``Class.method`` allowed) by a timer adding to ``acc[label]``."""
    owner = importlib.import_module(module)
    *path, name = attr.split(".")
    for part in path:
        owner = getattr(owner, part)
    fn = owner.__dict__[name] if isinstance(owner, type) else getattr(owner, name)
    clock = time.process_time_ns

    @functools.wraps(fn)
    def timed(*args, **kwargs):
        t = clock()
        try:
            return fn(*args, **kwargs)
        finally:
            acc[label] = acc.get(label, 0) + clock() - t

    setattr(owner, name, timed)


def _best(fns: dict[str, object], calls: int, rounds: int) -> dict[str, float]:
    """Per call [us]: the best of ``rounds`` interleaved rounds of ``calls`` calls each."""
    out = {k: float("inf") for k in fns}
    for _ in range(rounds):
        for k, fn in fns.items():
            t = time.process_time_ns()
            for _ in range(calls):
                fn()
            out[k] = min(out[k], (time.process_time_ns() - t) / calls / 1e3)
    return out


def _varied(sc: dict, vary: bool):
    """A function of no argument giving ``sc``, or with ``vary`` a copy of it at a new load each
    call (``p0`` times ``1 + k 1e-9``, k counting up: every solve resolves and solves a scene
    not seen before, as a user's next scene; no per-scene cache can pay)."""
    if not vary:
        return lambda: sc
    import copy

    import xpersson

    p0 = float(xpersson.Scene(sc).resolve().p0[0])
    count = iter(range(1, 1 << 62))

    def new() -> dict:
        out = copy.copy(sc)
        out["load"] = {"p0": f"{p0 * (1 + next(count) * 1e-9)!r} Pa"}
        return out

    return new


def account(
    sc: dict, calls: int, rounds: int, vary: bool = False
) -> tuple[dict[str, float], dict[str, float]]:
    """``(totals, stages)`` [us per solve] of scene ``sc`` (see the module's docstring;
    ``vary``: a new load at every solve, :func:`_varied`)."""
    from cn_walls import engine_call_of

    import xpersson
    from xpersson import engine

    alone = engine_call_of(sc)
    result = alone()
    real = engine.solve_batch
    scene = _varied(sc, vary)

    def handed_back() -> None:
        engine.solve_batch = lambda *a, **k: result
        try:
            xpersson.solve(scene())
        finally:
            engine.solve_batch = real

    fns = {"solve": lambda: xpersson.solve(scene()), "engine alone": alone}
    fns["pipeline, engine handed back"] = handed_back
    for fn in fns.values():  # warm: caches, the compiled march
        for _ in range(10):
            fn()
    totals = _best(fns, calls, rounds)
    acc: dict[str, int] = {}
    for module, attr, label in STAGES:
        _wrap(acc, module, attr, label)
    stages: dict[str, float] = {}
    for _ in range(rounds):
        acc.clear()
        for _ in range(calls):
            xpersson.solve(scene())
        for label, ns in acc.items():
            stages[label] = min(stages.get(label, float("inf")), ns / calls / 1e3)
    return totals, stages


def main(argv: list[str] | None = None) -> None:
    from summary_design import design, held_out
    from summary_paths import _march_cases

    from xpersson.engine import _compiled

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=2026, help="36: the design; else held-out")
    ap.add_argument("--scene", default="flat H=0.48 5dec")
    ap.add_argument("--row", default="engine (jkr) vs C march, rtol 1e-6")
    ap.add_argument("--calls", type=int, default=300)
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument(
        "--closed-form",
        action="store_true",
        help="the row 'one closed-form load vs its kernel' instead (elastic, 100 kPa)",
    )
    ap.add_argument("--vary", action="store_true", help="a new load at every solve")
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    _compiled.build()  # the compiled march, as summary.py's rows
    specs = dict(design(12, 36) if args.seed == 36 else held_out(12, args.seed))
    if args.closed_form:
        from summary_design import scene

        args.row = "one closed-form load (elastic, 100 kPa)"
        sc = scene(specs[args.scene], "100 kPa")
    else:
        sc = _march_cases(specs[args.scene])[args.row][0]
    totals, stages = account(sc, args.calls, args.rounds, args.vary)
    how = ", a new load each solve" if args.vary else ""
    print(f"seed {args.seed}: {args.scene}: {args.row} (us per solve, CPU, best of rounds{how})")
    for label, us in totals.items():
        print(f"  {label:44s} {us:8.0f}")
    rest = totals["solve"] - totals["engine alone"] - totals["pipeline, engine handed back"]
    print(f"  {'solve - engine alone - pipeline alone':44s} {rest:8.0f}")
    print("  stages inside solve (inclusive):")
    for _, _, label in STAGES:
        if label in stages:
            print(f"    {label:42s} {stages[label]:8.1f}")


if __name__ == "__main__":
    main()
