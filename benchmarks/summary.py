"""The README's speed table over a scene design: every path as a ratio to its own kernel.

Run from the checkout (one command regenerates the results and the README table)::

    python benchmarks/summary.py [--quick] [--rounds 3] [--scenes 12] [--check]
    python benchmarks/summary.py --paths "sweep E x H" "load strings"   # some rows again
    python benchmarks/summary.py --held-out 2026   # the design paths on held-out scenes
    python benchmarks/summary.py --held-out 2026 --paths leakage   # some of them again

One process, ``OPENBLAS_NUM_THREADS=1`` (set here before numpy is imported), CPU time of this
process (``time.process_time``; the machine may be shared), each quantity the best of
``--rounds`` rounds in which the quantities of a ratio are measured alternately, each round
timing ~20 ms of repeated calls (one call where a call is longer: ``summary_design.timed``). The
optional compiled kernels (numba) are built before any row is measured (:func:`warm_up`). The
scenes are a seeded design across the documented domain (:mod:`summary_design`: H 0.3-0.95, with
and without roll-off, 3-6 decades). Per path: the median and the **worst** ratio over the design
and the scene of the worst; the worst over a held-out design of the same domain drawn with
another seed (``--held-out SEED``: the design paths and the C-march rows, not the single paths);
the peak traced memory (``tracemalloc``) of the path on its worst scene.
Honest denominators: plain loads are given as range tables, the kernel runs on the same curves.
The C march (``../shared/peers/c_march`` beside the checkout or ``$XPERSSON_PEERS/c_march``,
built here with ``$CC``/``cc``; skipped without a compiler) and the two-grid scipy BDF peer
(``peer_scipy_mol.py`` there) are the engine's limit and peer. Wall times of the parallel row
are noisy on a shared machine (re-measure when quiet).

Writes ``benchmarks/results/summary.json`` and ``summary.md`` and the block between
``<!-- speed-table:start -->`` and ``<!-- speed-table:end -->`` of ``README.md``.
"""

from __future__ import annotations

import os

os.environ["OPENBLAS_NUM_THREADS"] = "1"

import argparse  # noqa: E402
import json  # noqa: E402
import platform  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

HERE = Path(__file__).resolve().parent
#: The peers (``../shared/peers`` beside the checkout, as ``engine_vs_peers.py``; or
#: ``$XPERSSON_PEERS``).
PEERS = Path(os.environ.get("XPERSSON_PEERS", HERE.parents[1] / "shared" / "peers"))
sys.path.insert(0, str(HERE))

import summary_paths as P  # noqa: E402
from summary_design import design, held_out, probe  # noqa: E402

import xpersson  # noqa: E402

START, END = "<!-- speed-table:start -->", "<!-- speed-table:end -->"
#: The README's one-load solve in a fresh interpreter and its imports (``startup.py``).
FIRST_SOLVE = (
    "import time; t = time.process_time(); import xpersson; "
    "xpersson.solve({'spectrum': {'model': 'self_affine', 'H': 0.8, 'q_L': '1e3 1/m', "
    "'q_r': '1e4 1/m', 'q_1': '1e8 1/m', 'h_rms': '1 um'}, 'material': {'E': '10 MPa', "
    "'nu': 0.5}, 'load': {'p0': '1 MPa'}}); print(time.process_time() - t)"
)
IMPORTS = (
    "import time; t = time.process_time(); import xarray, pint; print(time.process_time() - t)"
)


def warm_up(scenes) -> None:
    """Imports and entry points, and every optional compiled kernel built now (the state of a
    process that has run a study for a second or two: ``fresh_process.py`` measures how soon
    a study gets there), so that no row depends on the rows before it having crossed a
    kernel's build threshold."""
    from xpersson.engine import _compiled as march
    from xpersson.physics import _compiled as kernels

    xpersson.solve(P.scene(scenes[0][1], P.load_range(3)))
    march.build()
    kernels.kernel(float("inf"))


def accelerator() -> str:
    """The optional accelerator of this process: ``numba X.Y`` or ``none``."""
    try:
        import numba
    except ImportError:
        return "none"
    return f"numba {numba.__version__}"


def _accelerated(meta: dict) -> str:
    """The header's words on the accelerator the table was measured with (runs before it was
    recorded had numba)."""
    acc = meta.get("accelerator", "numba")
    if acc == "none":
        return 'without numba (numpy paths only; the speeds below need `pip install ".[fast]"`)'
    return f'with {acc} (`pip install ".[fast]"`), its compiled kernels built first'


def _same_accelerator(meta: dict) -> None:
    """Refuse to merge rows measured with and without the accelerator into one table."""
    saved, now = meta.get("accelerator", accelerator()), accelerator()
    if (saved == "none") != (now == "none"):
        raise SystemExit(
            f"results/summary.json was measured with accelerator {saved!r}, this process has "
            f"{now!r}: install the same (numba: `pip install '.[fast]'`) or run the full table"
        )


def over_design(scenes, paths, rounds, quick, probes: list | None = None) -> dict:
    """``{path: {scene: measurement}}`` of every design path on every scene; ``probes``: the
    host probe (:func:`summary_design.probe`, ms) appended before each scene."""
    out: dict[str, dict] = {name: {} for name in paths}
    for label, spec in scenes:
        if probes is not None:
            probes.append(probe())
        for name, fn in paths.items():
            try:
                out[name][label] = fn(spec, rounds, quick)
            except Exception as exc:  # noqa: BLE001 - a path that fails is reported, not fatal
                out[name][label] = {"error": f"{type(exc).__name__}: {str(exc)[:160]}"}
            print(f"{label:22s} {name:34s} {_short(out[name][label])}", flush=True)
    return out


def _short(m: dict) -> str:
    if "error" in m:
        return m["error"]
    return f"{m['time'] * 1e3:9.2f} ms  kernel {m['kernel'] * 1e3:8.2f} ms  ratio {m['ratio']:.2f}"


def summarize(results: dict, targets: dict, memory: dict) -> list[dict]:
    """Per path: median and worst ratio over the scenes, the worst scene, its numbers."""
    rows = []
    for name, per in results.items():
        ok = {k: v for k, v in per.items() if "ratio" in v}
        if not ok:
            first = next(iter(per.values()), {"error": "not run"})
            rows.append({"path": name, "error": first.get("error", "not run")})
            continue
        target = targets.get(name)
        if target is not None and target[0] == "ms":  # worst by milliseconds per load
            worst = max(ok, key=lambda k: ok[k]["per_load_ms"])
        elif name.startswith("BDF"):  # a speed-up over the peer: the smallest is the worst
            worst = min(ok, key=lambda k: ok[k]["ratio"])
        else:
            worst = max(ok, key=lambda k: ok[k]["ratio"])
        ratios = [v["ratio"] for v in ok.values()]
        rows.append(
            {
                "path": name,
                "scenes": len(ok),
                "median": float(np.median(ratios)),
                "worst": ok[worst]["ratio"],
                "worst_scene": worst,
                "time": ok[worst]["time"],
                "kernel": ok[worst]["kernel"],
                "unit": ok[worst].get("unit", "s"),
                "target": target,
                "met": _met(target, ok[worst]),
                "note": ok[worst].get("note", ""),
                "per_load_ms": ok[worst].get("per_load_ms"),
                "peak_mib": memory.get(name),
                "failed": len(per) - len(ok),
            }
        )
    return rows


def _met(target: tuple | None, m: dict) -> bool | None:
    if target is None:
        return None
    kind, value = target
    return bool((m["per_load_ms"] if kind == "ms" else m["ratio"]) <= value)


def table(rows: list[dict], meta: dict, held: dict | None = None) -> str:
    held_rows = {r["path"]: r for r in (held or {}).get("rows", []) if "error" not in r}
    head = (
        f"Measured by `python benchmarks/summary.py` ({meta['date']}, {meta['scenes']} seeded "
        f"scenes: H 0.3-0.95, with and without roll-off, 3-6 decades; one process, "
        f"OPENBLAS_NUM_THREADS=1, CPU time per call, best of {meta['rounds']} interleaved rounds "
        "of ~20 ms of repeated calls each; "
        f"{_accelerated(meta)}; "
        f"{meta['machine']}). Ratio: the path's time over its kernel's on the same curves; "
        "worst over the design, and its scene. Memory: peak traced on the worst scene."
        + _probe_note(meta)
        + _partial(meta)
        + _held_note(held)
        + "\n\n"
        "| path | median | worst (scene) | worst: time / kernel | target | held-out worst "
        "(scene) | peak MiB |\n"
        "|---|---:|---|---|---|---|---:|\n"
    )
    lines = []
    for r in rows:
        if "error" in r:
            lines.append(f"| {r['path']} | - | not measured: {r['error'][:80]} | | | | |")
            continue
        target = ""
        if r["target"] is not None:
            kind, value = r["target"]
            target = f"<= {value:g}{'x' if kind == 'x' else ' ms/load'}: "
            target += "met" if r["met"] else "**not met**"
        mem = "" if r["peak_mib"] is None else f"{r['peak_mib']:.0f}"
        lines.append(
            f"| {r['path']} | {r['median']:.2f} | **{r['worst']:.2f}** ({r['worst_scene']}) | "
            f"{_fmt(r['time'], r['unit'])} / {_fmt(r['kernel'], r['unit'])}"
            f"{(' ' + r['note']) if r['note'] else ''} "
            f"| {target} | {_held_cell(held_rows.get(r['path']))} | {mem} |"
        )
    return head + "\n".join(lines) + "\n"


def _held_cell(h: dict | None) -> str:
    """The held-out worst ratio, its scene, and whether it meets the row's target."""
    if h is None:
        return "-"
    met = "" if h["met"] is None else (": met" if h["met"] else ": **not met**")
    ms = h.get("per_load_ms")
    per_load = f" ({ms:.3g} ms/load)" if ms is not None and h["target"][0] == "ms" else ""
    return f"{h['worst']:.2f}{per_load} ({h['worst_scene']}){met}"


def _held_note(held: dict | None) -> str:
    if not held:
        return ""
    m = held["meta"]
    return (
        f" Held-out: the design paths again on {m['scenes']} scenes drawn with seed "
        f"{m['seed']} ({m['date']}; `--held-out {m['seed']}`), worst of those"
        + (f" (host probe {_spread(m['probe_ms'])})" if m.get("probe_ms") else "")
        + "."
        + _partial(m).replace("Measured again", "Held-out rows measured again")
    )


def _spread(ms: list[float]) -> str:
    return f"{min(ms):.2f}-{max(ms):.2f} ms"


def _probe_note(meta: dict) -> str:
    """The host's drift over the run: the probe's range (runs before 2026-12-02 had none)."""
    ms = meta.get("probe_ms")
    if not ms:
        return ""
    return (
        f" Host probe (`summary_design.probe`: a fixed erf of 2e5 values, best of 3, before "
        f"each scene and at the end): {_spread(ms)} over the run; absolute times compare "
        "within that spread."
    )


def _partial(meta: dict) -> str:
    """The rows measured again after the full run (``--paths``), and when."""
    again = meta.get("partial") or {}
    if not again:
        return ""
    probes = meta.get("partial_probe_ms") or {}  # per re-measure's time stamp (from 2026-12-02)

    def when_(w: str) -> str:
        return f"{w}, host probe {_spread(probes[w])}" if probes.get(w) else w

    rows = "; ".join(f"{name} ({when_(when)})" for name, when in again.items())
    return f" Measured again (`--paths`, same design and rounds): {rows}."


def _live_probes(meta: dict, new: dict[str, list[float]]) -> dict[str, list[float]]:
    """The re-measures' host probes (``{time stamp: probes}``) still named by a row of
    ``meta["partial"]``, with ``new``'s added."""
    merged = {**meta.get("partial_probe_ms", {}), **new}
    live = set(meta.get("partial", {}).values())
    return {w: v for w, v in merged.items() if w in live}


def _fmt(value: float, unit: str = "s") -> str:
    if unit != "s":  # the memory row: MiB
        return f"{value:.0f} {unit}"
    return f"{value:.2f} s" if value >= 1 else f"{value * 1e3:.3g} ms"


def write(rows: list[dict], meta: dict, raw: dict, check: bool, memory: dict) -> str:
    held_file = HERE / "results" / "summary_heldout.json"
    held = json.loads(held_file.read_text()) if held_file.exists() else None
    text = table(rows, meta, held)
    print(text)
    if check:
        return text
    out = HERE / "results"
    (out / "summary.json").write_text(
        json.dumps(
            {"meta": meta, "rows": rows, "raw": raw, "memory": memory}, indent=1, default=float
        )
    )
    (out / "summary.md").write_text("# Speed summary\n\n" + text)
    readme = HERE.parent / "README.md"
    body = readme.read_text()
    if START in body and END in body:
        head, rest = body.split(START, 1)
        readme.write_text(head + START + "\n" + text + END + rest.split(END, 1)[1])
    return text


def _select(texts: list[str] | None) -> tuple[dict, list[str], dict]:
    """The design paths, C-march rows and single paths whose names contain one of ``texts``
    (all design paths and C-march rows, no single path, when ``texts`` is None)."""
    if texts is None:
        return dict(P.DESIGN_PATHS), [k for k in P.TARGETS if "C march" in k], {}
    paths = {k: f for k, f in P.DESIGN_PATHS.items() if any(t in k for t in texts)}
    march = [k for k in P.TARGETS if "C march" in k and any(t in k for t in texts)]
    again = {k: f for k, f in P.AGAIN.items() if any(t in k for t in texts)}
    if not paths and not march and not again:
        names = [*P.DESIGN_PATHS, *P.AGAIN]
        raise SystemExit(f"no design path matches {texts}; paths: {names}")
    return paths, march, again


def some_paths(texts: list[str], rounds: int | None, check: bool) -> str:
    """Measure the design paths named by ``texts`` again over the saved design; keep the rest
    of ``results/summary.json`` (its date and rounds note the full run)."""
    saved = json.loads((HERE / "results" / "summary.json").read_text())
    _same_accelerator(saved["meta"])
    paths, march, again = _select(texts)
    scenes = list(saved["meta"]["design"].items())
    warm_up(scenes)
    rounds = rounds or int(saved["meta"]["rounds"])
    probes: list[float] = []  # this re-measure's own host probe (the full run's stays its own)
    raw = {**saved["raw"], **over_design(scenes, paths, rounds, False, probes)}
    lib = P.c_march_lib(PEERS) if march else None
    if lib is not None:  # the engine's rows against the C march (all four measured together)
        raw.update(
            {k: v for k, v in P.march_paths(lib, scenes, rounds, False).items() if k in march}
        )
        paths.update(dict.fromkeys(march))
    for fn in again.values():
        raw.update(fn(rounds))
    memory = {**saved.get("memory", {}), **P.memory({k: raw[k] for k in paths}, scenes, False)}
    meta = dict(saved["meta"])
    now = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    meta["partial"] = {**meta.get("partial", {}), **dict.fromkeys([*paths, *again], now)}
    probes.append(probe())
    meta["partial_probe_ms"] = _live_probes(meta, {now: probes})
    return write(summarize(raw, P.TARGETS, memory), meta, raw, check, memory)


def held_out_run(seed: int, rounds: int | None, check: bool, texts: list[str] | None) -> str:
    """The design paths and the C-march rows (those named by ``texts``, or all) on
    :func:`summary_design.held_out` scenes (``results/summary_heldout.json``: rows measured
    again replace their earlier values when the seed is the same), then the table re-rendered
    from the saved full run."""
    scenes = held_out(12, seed)
    paths, march, _ = _select(texts)
    rounds = rounds or 3
    warm_up(scenes)
    probes: list[float] = []
    raw = over_design(scenes, paths, rounds, False, probes)
    lib = P.c_march_lib(PEERS) if march else None
    if lib is not None:
        raw.update(
            {k: v for k, v in P.march_paths(lib, scenes, rounds, False).items() if k in march}
        )
    probes.append(probe())
    file = HERE / "results" / "summary_heldout.json"
    meta = {"date": time.strftime("%Y-%m-%d"), "seed": seed, "scenes": len(scenes)}
    meta["probe_ms"] = probes
    meta["rounds"], meta["design"], meta["accelerator"] = rounds, dict(scenes), accelerator()
    if not check:
        _same_accelerator(json.loads((HERE / "results" / "summary.json").read_text())["meta"])
    if texts is not None and file.exists():
        before = json.loads(file.read_text())
        if before["meta"]["seed"] == seed:
            now = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
            partial = {**before["meta"].get("partial", {}), **dict.fromkeys(raw, now)}
            meta = {**before["meta"], "partial": partial}
            meta["partial_probe_ms"] = _live_probes(meta, {now: probes})
            raw = {**before["raw"], **raw}
    held = {"meta": meta, "rows": summarize(raw, P.TARGETS, {}), "raw": raw}
    if check:  # a fresh seed's worst rows, printed (nothing written)
        text = table(held["rows"], {**meta, "machine": platform.machine()})
        print(text)
        return text
    file.write_text(json.dumps(held, indent=1, default=float))
    saved = json.loads((HERE / "results" / "summary.json").read_text())
    rows = summarize(saved["raw"], P.TARGETS, dict(saved.get("memory", {})))
    return write(rows, saved["meta"], saved["raw"], False, saved.get("memory", {}))


def cpu_model() -> str:
    """The processor's model name (``/proc/cpuinfo``; ``platform.processor()`` elsewhere): the
    absolute times of two runs compare only on the same model (a 2026-12-02 run on "AMD EPYC"
    took 1.5-2.5x the times of the 2026-11-30 run)."""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown processor"


def main(argv: list[str] | None = None) -> str:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=None, help="default 3 (--quick: 1)")
    ap.add_argument("--scenes", type=int, default=12, help="scenes of the design (>= 12)")
    ap.add_argument("--quick", action="store_true", help="1 round, smaller sweeps")
    ap.add_argument("--check", action="store_true", help="print only; write nothing")
    ap.add_argument("--no-parallel", action="store_true", help="skip the LocalCluster row")
    ap.add_argument(
        "--from-json", action="store_true", help="re-render results/summary.json (no measuring)"
    )
    ap.add_argument(
        "--paths",
        nargs="+",
        metavar="TEXT",
        help="measure only the design paths whose name contains one of these texts (no single "
        "or parallel rows); the other rows are kept from results/summary.json, the table is "
        "rendered in full",
    )
    ap.add_argument(
        "--held-out",
        type=int,
        metavar="SEED",
        help="measure the design paths and the C-march rows on 12 scenes drawn with SEED "
        "(not the design's 36) and add their worst to the table",
    )
    args = ap.parse_args(argv)
    if args.held_out is not None:
        return held_out_run(args.held_out, args.rounds, args.check, args.paths)
    if args.paths:
        return some_paths(args.paths, args.rounds, args.check)
    if args.from_json:
        saved = json.loads((HERE / "results" / "summary.json").read_text())
        rows = summarize(saved["raw"], P.TARGETS, dict(saved.get("memory", {})))
        return write(rows, saved["meta"], saved["raw"], args.check, saved.get("memory", {}))
    rounds = args.rounds or (1 if args.quick else 3)
    scenes = design(max(12, args.scenes))
    warm_up(scenes)
    probes: list[float] = []
    raw = over_design(scenes, P.DESIGN_PATHS, rounds, args.quick, probes)
    raw.update(P.single_paths(PEERS, scenes, rounds, args.quick))
    if not args.no_parallel:
        raw.update(P.parallel_path(rounds, args.quick))
    memory = P.memory(raw, scenes, args.quick)
    probes.append(probe())
    meta = {
        "date": time.strftime("%Y-%m-%d"),
        "scenes": len(scenes),
        "rounds": rounds,
        "quick": args.quick,
        "accelerator": accelerator(),
        "machine": f"{platform.machine()} ({cpu_model()}), {os.cpu_count()} cores, Python "
        f"{platform.python_version()}, numpy {np.__version__}",
        "design": dict(scenes),
        "probe_ms": probes,
    }
    return write(summarize(raw, P.TARGETS, memory), meta, raw, args.check, memory)


if __name__ == "__main__":
    main()
