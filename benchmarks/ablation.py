"""What each optional compiled kernel and each cache saves: every row it serves, timed with it
and without it.

Each kernel (or group of kernels fetched together) of the engine's compiled march
(``xpersson.engine._compiled.KERNELS``, but the ``fused`` level march the ``lean`` level
stands on) and of the gap distribution's (``xpersson.physics._compiled``) is taken out of
the process's built kernels around a call, so that the call runs the numpy path the kernel
replaces (the same numbers, bit for bit: the compiled path's contract), and put back after
it; each cache of ``xpersson.cache`` (kind ``cache``) is bypassed around a call (every look-up
computes, nothing is kept or found: the same numbers, as with ``XPERSSON_CACHE=off``, for that
cache alone). Its worth is the ratio of the two times, interleaved in one process
(``summary_design.timed``: best of ``--rounds`` rounds of ~20 ms of repeated calls each; CPU
time, ``OPENBLAS_NUM_THREADS=1``), on the rows it serves:

* engine kernels: the engine's own call (``cn_walls.engine_call_of``) and the whole ``solve``
  of the ``jkr`` scene of ``engine_limit.py`` at rtol 1e-6 and 1e-8 on every scene of the
  design (seed 36) and of the held-out draw 2026 on which it marches ``cn`` levels, and the
  "jkr, one load" and ``plastic_scale_dependent`` rows of ``summary.py``;
* physics kernels: the ``gap_pdf`` and ``leakage`` rows of ``summary.py`` at 100, 1000 and
  1e4 loads;
* caches: one closed-form load, 100 bare loads, ``gap_pdf`` and ``leakage`` at 100 loads,
  ``leakage`` at 1000, the two E x H sweeps (30 x 30 points, 10 x 10 x 10 loads), and the
  ``jkr``, ``plastic_scale_dependent`` and rtol 1e-6 engine rows, on the design; a cache is
  timed on the rows that look it up (none: not listed).

Each ``summary.py`` row on the worst scenes of its last saved run (``results/summary.json``,
``summary_heldout.json``: :func:`worst_scenes`), design and held-out, so that the rows follow
the table.

The first unit of each kind is a control: the same calls through the same wrapper with nothing
taken out, whose ratios are the timing's noise. A kernel whose median ratio is ~1.00 and whose
worst stays within that noise (about +-3 % on this machine) may not pay for its lines; whether
it does is then decided by the before/after of the rows nearest their targets, in alternating
fresh processes (``engine_limit.py --against``): a kernel that saves 2-3 % on the smallest
problem is inside one run's noise and outside three runs'. So were ``projected`` (engine) and
``erf_diff_series`` (physics) found and removed on 2026-11-30, and ``fourth`` and ``scale``
(engine) found, removed and put back: together they kept the held-out "engine alone" row at
2.98x the C march, not 3.12x (``results/ablation.md``).

Usage: ``python benchmarks/ablation.py [--kinds engine physics cache] [--only NAME ...]
[--rounds 3]``; prints one line per unit and row, then per unit the median and worst ratio.
"""

from __future__ import annotations

import os

os.environ["OPENBLAS_NUM_THREADS"] = "1"

import argparse  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import warnings  # noqa: E402
from collections.abc import Callable  # noqa: E402
from pathlib import Path  # noqa: E402

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import xpersson  # noqa: E402
from xpersson.engine import _compiled as engine_kernels  # noqa: E402
from xpersson.physics import _compiled as physics_kernels  # noqa: E402

#: Kernels fetched together (one taken out alone leaves its callers a None to call).
PHYSICS_GROUPS = (
    ("spline_rhs", "spline_slopes", "spline_coefficients", "spline_values"),
    ("df_logs", "df_sums"),
    ("node_panels", "node_segments", "node_kernel"),
    ("row_values", "shared_row_values"),
)
ENGINE_GROUPS = (("edges", "times", "tracks"),)
#: Kernels other kernels are built on (the lean level calls the fused level march).
ENGINE_BASE = ("fused",)

_LOADS = {"100 loads": 100, "1000 loads": 1000, "1e4 loads": 10_000}


def worst_scenes(tag: str) -> dict[str, str]:
    """Each path's worst scene in the saved table of ``tag`` (``"d"``: the design,
    ``results/summary.json``; ``"h"``: the held-out draw 2026, ``summary_heldout.json``), so
    that the rows follow the table's latest run."""
    import json

    name = "summary.json" if tag == "d" else "summary_heldout.json"
    rows = json.loads((HERE / "results" / name).read_text())["rows"]
    return {r["path"]: r["worst_scene"] for r in rows if r.get("worst_scene")}


def _analysis_rows() -> list[tuple[str, int, str, str]]:
    """``(analysis, loads, "d" or "h", scene)`` of the ``gap_pdf`` / ``leakage`` rows' worst
    scenes (:func:`worst_scenes`)."""
    out = set()
    for tag in ("d", "h"):
        for path, name in worst_scenes(tag).items():
            an, _, count = path.partition(", ")
            if an in ("gap_pdf", "leakage"):
                out.add((an, _LOADS[count], tag, name))
    return sorted(out)


def _specs() -> dict[str, dict]:
    from summary_design import design, held_out

    return {"d": dict(design(12, 36)), "h": dict(held_out(12, 2026))}


def engine_rows() -> dict[str, Callable[[], object]]:
    """The engine kernels' rows: label -> call."""
    import summary_paths as sp
    from cn_walls import engine_call_of, levels_of
    from engine_limit import jkr_scene

    specs, rows = _specs(), {}
    for tag, scenes in specs.items():
        for name, spec in scenes.items():
            if not levels_of(jkr_scene(spec, 1e-6)):  # (no cn level marched: nothing to time)
                continue
            for rtol in (1e-6, 1e-8):
                sc = jkr_scene(spec, rtol)
                rows[f"{tag} {name} engine alone {rtol:.0e}"] = engine_call_of(sc)
                rows[f"{tag} {name} solve {rtol:.0e}"] = _solve(sc)
    for tag in specs:  # (the one-load jkr row's worst scene, as its plastic row's)
        name = worst_scenes(tag)["jkr, one load vs C march"]
        for label, (sc, _, _) in sp._march_cases(specs[tag][name]).items():
            if "rtol" not in label:  # (the one-load jkr and the plastic rows)
                rows[f"{tag} {name} {label.split(' vs ')[0]}"] = _solve(sc)
    return rows


def physics_rows() -> dict[str, Callable[[], object]]:
    """The gap distribution's kernels' rows: label -> call."""
    from summary_design import load_range, scene

    specs = _specs()
    return {
        f"{tag} {name} {an} {n}": _solve(scene(specs[tag][name], load_range(n), analyses={an: {}}))
        for an, n, tag, name in _analysis_rows()
    }


def cache_rows() -> dict[str, Callable[[], object]]:
    """The caches' rows (each on its path's worst design scene, :func:`worst_scenes`): label
    -> call."""
    import summary_paths as sp
    from summary_design import load_range, scene

    d, w = _specs()["d"], worst_scenes("d")

    def at(path: str, loads: object, **kw: object) -> Callable[[], object]:
        return _solve(scene(d[w[path]], loads, **kw))

    rows = {
        "one load": at("one closed-form load vs its kernel", "100 kPa"),
        "100 loads": at("leakage, 100 loads", load_range(100)),
        "gap_pdf 100": at("gap_pdf, 100 loads", load_range(100), analyses={"gap_pdf": {}}),
        "leakage 100": at("leakage, 100 loads", load_range(100), analyses={"leakage": {}}),
        "leakage 1000": at("leakage, 1000 loads", load_range(1000), analyses={"leakage": {}}),
        "sweep E x H 30 x 30": _solve(sp._eh(d[w["sweep E x H, 1 load"]], 30, "100 kPa")),
        "sweep E x H x 10 loads 10 x 10": _solve(
            sp._eh(d[w["sweep E x H x 10 loads"]], 10, load_range(10))
        ),
    }
    for label, (sc, _, _) in sp._march_cases(d[w["jkr, one load vs C march"]]).items():
        if "rtol 1e-8" not in label:
            rows[label.split(" vs ")[0]] = _solve(sc)
    return rows


def _solve(sc: dict) -> Callable[[], object]:
    return lambda: xpersson.solve(sc)  # (the scenes' warnings: silenced by main)


def _units(kind: str) -> list[tuple[str, ...]]:
    """The kernels of ``kind`` as the units taken out together."""
    if kind == "cache":
        from xpersson import cache

        return [(), *((n,) for n in cache._REGISTRY)]
    if kind == "engine":
        names = [k for k in engine_kernels.KERNELS if k not in ENGINE_BASE]
        groups = ENGINE_GROUPS
    else:
        names = list(physics_kernels._STATE["fns"])
        groups = PHYSICS_GROUPS
    grouped = {n for g in groups for n in g}
    return [(), *groups, *((n,) for n in names if n not in grouped)]  # (): the control


def without(kind: str, names: tuple[str, ...], fn: Callable[[], object]) -> Callable[[], object]:
    """``fn`` with the kernels ``names`` taken out of the built ones (the caches ``names``
    bypassed) for the call."""
    if kind == "cache":
        return _bypassed(names, fn)
    state = engine_kernels._STATE if kind == "engine" else physics_kernels._STATE["fns"]

    def call() -> object:
        kept = {n: state[n] for n in names}
        for n in names:
            state[n] = None
        try:
            return fn()
        finally:
            state.update(kept)

    return call


def _bypassed(names: tuple[str, ...], fn: Callable[[], object]) -> Callable[[], object]:
    from xpersson import cache

    caches = [cache._REGISTRY[n] for n in names]

    def call() -> object:
        for c in caches:  # (instance attributes: the class's methods answer again after)
            c.get = lambda key, compute: cache.freeze(compute())
            c.peek = lambda key: None
        try:
            return fn()
        finally:
            for c in caches:
                del c.get, c.peek

    return call


def _lookups(names: tuple[str, ...]) -> int:
    from xpersson import cache

    return sum(cache._REGISTRY[n].hits + cache._REGISTRY[n].misses for n in names)


def measure(
    kind: str, rows: dict, units: list, rounds: int
) -> list[tuple[str, float, float, float]]:
    """Per unit: its name, the median, the worst and the best ratio (without / with) over the
    rows of ``rows`` it serves."""
    from summary_design import timed

    summary = []
    for unit in units:
        label = "+".join(unit) or "(control: nothing taken out)"
        ratios = []
        for row, fn in rows.items():
            if kind == "cache" and unit:  # (only the rows that look the cache up)
                before = _lookups(unit)
                fn()
                if _lookups(unit) == before:
                    continue
            off = without(kind, unit, fn)
            fn(), off()  # (each path's caches and first calls before the timing)
            t = timed({"with": fn, "without": off}, rounds)
            ratios.append(t["without"] / t["with"])
            print(
                f"{label:60s} {row:44s} with {t['with'] * 1e3:8.3f} ms, without"
                f" {t['without'] * 1e3:8.3f} ms: {ratios[-1]:.3f}",
                flush=True,
            )
        if ratios:
            summary.append((label, statistics.median(ratios), max(ratios), min(ratios)))
    return summary


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--kinds", nargs="+", default=["engine", "physics", "cache"])
    ap.add_argument("--only", nargs="*", default=None, metavar="NAME")
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")  # (the scenes' own warnings, e.g. steep slopes)
    if not (engine_kernels.build() and physics_kernels.kernel(float("inf")) is not None):
        sys.exit("ablation: needs numba and the compiled kernels on")
    summary = []
    for kind in args.kinds:
        rows = {"engine": engine_rows, "physics": physics_rows, "cache": cache_rows}[kind]()
        for fn in rows.values():  # (every cache each row registers, before the units)
            fn()
        units = [u for u in _units(kind) if args.only is None or set(u) & set(args.only) or not u]
        summary += [(kind, *s) for s in measure(kind, rows, units, args.rounds)]
    print(f"\n{'kind':8s} {'unit':60s} median  worst   best")
    for kind, label, med, worst, best in summary:
        print(f"{kind:8s} {label:60s} {med:6.3f} {worst:6.3f} {best:6.3f}")


if __name__ == "__main__":
    main()
