"""Fault campaign of archives and sweep folders (issue 24; not in CI).

    OPENBLAS_NUM_THREADS=1 python benchmarks/faults.py --kills 30 --races 10 --corrupt 200 \
        --hostile 200 --hangs 6 --issue37 200 --out faults.json  # --only disk,forge,...

Scenarios, each counted (runs, silent wrong results, tracebacks, hangs, lost parts), and the
seven classes of issue 37 (``--issue37 N`` faults each, :mod:`faults37`):

- ``kill``: a sweep into a folder (fresh, overwriting another study, resuming an interrupted
  run) killed with SIGKILL at a random moment, then the folder opened (must be the complete
  study or a clean error, never something else) and the study re-run (must equal the
  uninterrupted study bit for bit; reused parts are counted).
- ``race``: 4 CLI runs started together into one new folder, half of them a different study:
  every exit code 0 or 2 (one line), the folder afterwards exactly one of the two studies.
- ``corrupt``: random bytes (zeros, random, one flipped bit; 1 B to 4 KiB) written into an
  archive or into a part of a sweep folder, then opened (and the folder resumed): the contents
  identical to the original or a clean :class:`~xpersson.errors.ArchiveError`.
- ``hostile``: random mutations of a sweep index (types, sizes, names, numbers) and hostile
  scenes given to ``xpersson validate`` (towers of exponents, huge sweeps, long strings):
  a clean error or an untouched result, within the time limit.
- ``hang``: sweeps whose analysis never returns at random points, with
  ``[solver] plugin_time_limit``, serial and threads, run by the CLI: the hanging points
  failed naming the plugin, the others equal to their own solves, the run ends.

Silent wrong = a result that opens without error and differs from every study written into
the folder; traceback = an exception other than the documented ones (or a traceback on a CLI's
stderr); hang = a child process past its time limit.
"""

from __future__ import annotations

import argparse
import json
import os
import random
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import xpersson
from xpersson.errors import ArchiveError, SceneError
from xpersson.sweep import INDEX
from xpersson.sweep.parts import seal_index

BASE: dict[str, Any] = {
    "spectrum": {
        "model": "self_affine",
        "H": [0.7, 0.8],
        "q_L": "1e3 1/m",
        "q_r": "1e4 1/m",
        "q_1": "1e8 1/m",
        "h_rms": "1 um",
    },
    "material": {"E": ["5 MPa", "7 MPa", "10 MPa", "14 MPa", "20 MPa", "28 MPa"], "nu": 0.5},
    "load": {"p0": ["1e4 Pa", "1e5 Pa", "1e6 Pa"]},
    "output": {"zeta_per_decade": 3},
}
OTHER = json.loads(json.dumps(BASE))
OTHER["material"]["E"][2] = "11 MPa"
CHUNK = 1
DELAY = 0.25
"""Seconds added to every point of a killed run (spreads the kills over the solving)."""
RUNNER = """
import json, sys, time
import xpersson
from xpersson.sweep import blocks
run = blocks.run
def slow(*a, **k):
    time.sleep({delay})
    return run(*a, **k)
blocks.run = slow
scene, folder, overwrite = json.loads(sys.argv[1]), sys.argv[2], sys.argv[3] == "1"
xpersson.solve(scene, output=folder, chunk={chunk}, overwrite=overwrite)
"""
TIMES = ("date_created", "history", "xpersson_solver")


def _toml(data: dict[str, Any]) -> str:
    lines = []
    for section, table in data.items():
        if section == "analyses":
            lines += [f"[analyses.{k}]" for k in table]
            continue
        lines.append(f"[{section}]")
        lines += [f"{k} = {json.dumps(v)}" for k, v in table.items()]
    return "\n".join(lines) + "\n"


def _same(a: Any, b: Any) -> bool:
    a, b = a.load().copy(), b.load().copy()
    for key in TIMES:
        a.attrs.pop(key, None)
        b.attrs.pop(key, None)
    return bool(a.identical(b))


def _open(path: Path, refs: list[Any], tally: dict[str, int]) -> str:
    """Open and classify: 'ref<i>' (equal to a reference), 'error' (clean), 'wrong', 'traceback'."""
    try:
        ds = xpersson.open_dataset(path)
    except (ArchiveError, FileNotFoundError) as exc:
        if "\n" in str(exc):
            tally["traceback"] += 1
        return "error"
    except Exception as exc:  # noqa: BLE001 - counted
        tally["traceback"] += 1
        tally.setdefault("examples", []).append(f"{type(exc).__name__}: {exc}"[:300])
        return "traceback"
    for i, ref in enumerate(refs):
        if _same(ds, ref):
            return f"ref{i}"
    tally["silent_wrong"] += 1
    return "wrong"


def _new_tally() -> dict[str, int]:
    return {"runs": 0, "silent_wrong": 0, "traceback": 0, "hang": 0, "lost": 0}


# -- kill -----------------------------------------------------------------------------------------
def kill_campaign(n: int, rng: random.Random, work: Path, refs: dict[str, Any]) -> dict[str, Any]:
    """SIGKILL at a moment drawn uniformly over an uninterrupted run's duration (timed first)."""
    t0 = time.perf_counter()
    _run_killed(work / "kill-timing", BASE, False, 600.0)
    duration = time.perf_counter() - t0
    shutil.rmtree(work / "kill-timing")
    out: dict[str, Any] = {"run_seconds": round(duration, 2)}
    for mode in ("fresh", "overwrite", "resume"):
        tally = _new_tally() | {"killed_mid_run": 0, "parts_reused": 0, "open_error": 0}
        for i in range(n):
            folder = work / f"kill-{mode}-{i}"
            if mode == "overwrite":
                shutil.copytree(refs["other_folder"], folder)
            elif mode == "resume":  # an interrupted run to resume
                _run_killed(folder, BASE, False, rng.uniform(0.0, duration))
            after = rng.uniform(0.0, duration)
            alive = _run_killed(folder, BASE, mode == "overwrite", after, tally)
            tally["runs"] += 1
            tally["killed_mid_run"] += int(alive)
            seen = _open(folder, [refs["base"], refs["other"]], tally)
            tally["open_error"] += int(seen == "error")
            before = {p.name: p.stat().st_mtime_ns for p in folder.glob("part-*.nc")}
            try:
                ds = xpersson.solve(BASE, output=folder, chunk=CHUNK)
            except ArchiveError as exc:  # killed before the index was replaced: another study
                if "different study" not in str(exc):
                    tally["traceback"] += 1
                ds = xpersson.solve(BASE, output=folder, chunk=CHUNK, overwrite=True)
            if not _same(ds, refs["base"]):
                tally["lost"] += 1
            after_run = {p.name: p.stat().st_mtime_ns for p in folder.glob("part-*.nc")}
            tally["parts_reused"] += sum(before.get(k) == v for k, v in after_run.items())
            shutil.rmtree(folder)
        out[mode] = tally
    return out


def _run_killed(
    folder: Path, scene: dict, overwrite: bool, after: float, tally: dict | None = None
) -> bool:
    """Start a slowed sweep into ``folder``; SIGKILL it ``after`` seconds; True if it was
    still running."""
    code = RUNNER.format(delay=DELAY, chunk=CHUNK)
    args = [sys.executable, "-c", code, json.dumps(scene), str(folder), "1" if overwrite else "0"]
    proc = subprocess.Popen(args, stderr=subprocess.PIPE, text=True)
    try:
        proc.wait(after)
        alive = False
    except subprocess.TimeoutExpired:
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait()
        alive = True
    err = proc.stderr.read() if proc.stderr else ""
    if tally is not None and "Traceback" in err:
        tally["traceback"] += 1
    return alive


# -- race -----------------------------------------------------------------------------------------
def race_campaign(n: int, work: Path) -> dict[str, Any]:
    tally = _new_tally() | {"processes": 0, "exit0": 0, "refused_busy": 0, "refused_study": 0}
    files, refs = [], []
    for k, sc in enumerate((BASE, OTHER)):
        f = work / f"race{k}.toml"
        f.write_text(_toml(sc), encoding="utf-8")
        files.append(f)
        cmd = ["xpersson", "run", str(f), "-o", f"{work}/race-ref{k}/", "--quiet"]
        subprocess.run(cmd, check=True, capture_output=True)
        refs.append(xpersson.open_dataset(work / f"race-ref{k}").load())
    for i in range(n):
        folder = work / f"race-{i}"
        procs = [
            subprocess.Popen(
                ["xpersson", "run", str(files[k % 2]), "-o", f"{folder}/", "--quiet"],
                stderr=subprocess.PIPE,
                text=True,
            )
            for k in range(4)
        ]
        for p in procs:
            try:
                _, err = p.communicate(timeout=300)
            except subprocess.TimeoutExpired:
                p.kill()
                tally["hang"] += 1
                continue
            tally["processes"] += 1
            tally["exit0"] += int(p.returncode == 0)
            tally["refused_busy"] += int(p.returncode == 2 and "another run" in err)
            tally["refused_study"] += int(p.returncode == 2 and "different study" in err)
            if "Traceback" in err or p.returncode not in (0, 2):
                tally["traceback"] += 1
        tally["runs"] += 1
        seen = _open(folder, refs, tally)
        if seen == "error":
            tally["lost"] += 1
        shutil.rmtree(folder)
    return tally


# -- corrupt --------------------------------------------------------------------------------------
def _damage(path: Path, rng: random.Random) -> None:
    data = bytearray(path.read_bytes())
    k = rng.randrange(len(data))
    kind = rng.choice(["zeros", "random", "bit"])
    if kind == "bit":
        data[k] ^= 1 << rng.randrange(8)
    else:
        n = rng.choice([1, 16, 256, 4096])
        chunk = bytes(n) if kind == "zeros" else rng.randbytes(n)
        data[k : k + n] = chunk[: len(data) - k]
    path.write_bytes(data)


def corrupt_campaign(n: int, rng: random.Random, work: Path, refs: dict[str, Any]) -> dict:
    tally = _new_tally() | {"caught": 0, "harmless": 0, "resumed_equal": 0}
    for i in range(n):
        tally["runs"] += 1
        if i % 2 == 0:
            path = work / "c.nc"
            shutil.copy(refs["archive"], path)
            _damage(path, rng)
            seen = _open(path, [refs["single"]], tally)
        else:
            path = work / "cf"
            shutil.copytree(refs["base_folder"], path)
            parts = sorted(path.glob("part-*.nc"))
            _damage(rng.choice(parts), rng)
            seen = _open(path, [refs["base"]], tally)
            ds = xpersson.solve(BASE, output=path, chunk=CHUNK)
            if _same(ds, refs["base"]):
                tally["resumed_equal"] += 1
            else:
                tally["lost"] += 1
            shutil.rmtree(path)
        tally["caught"] += int(seen == "error")
        tally["harmless"] += int(seen.startswith("ref"))
    return tally


# -- hostile --------------------------------------------------------------------------------------
def _mutate(node: Any, rng: random.Random) -> Any:
    """One random change somewhere in a JSON tree."""
    if isinstance(node, dict) and node and rng.random() < 0.8:
        key = rng.choice(list(node))
        if rng.random() < 0.15:
            del node[key]
        else:
            node[key] = _mutate(node[key], rng)
        return node
    if isinstance(node, list) and node and rng.random() < 0.8:
        k = rng.randrange(len(node))
        node[k] = _mutate(node[k], rng)
        return node
    return rng.choice(
        [
            None,
            True,
            -1,
            0,
            10**12,
            1e308,
            "../../etc/passwd",
            "/etc/passwd",
            "part-99999.nc",
            "x" * 1000,
            [],
            {},
            [10**9] * 3,
            float("nan"),
        ]
    )


HOSTILE_SCENES = [
    ("material", "E", "1 MPa**9**9**9"),
    ("material", "E", "1 MPa^9^9^9^9"),
    ("material", "E", "9**9**9**9 Pa"),
    ("material", "E", "(" * 500 + "1 MPa" + ")" * 500),
    ("material", "E", "1" * 100_000 + " MPa"),
    ("material", "E", {"start": "1 MPa", "stop": "9 MPa", "num": 100_000}),
    ("spectrum", "H", {"start": 0.3, "stop": 0.9, "num": 100_000}),
    ("load", "p0", {"start": "1 kPa", "stop": "1 MPa", "num": 100_000}),
    ("output", "zeta_per_decade", 10**9),
]


def hostile_campaign(n: int, rng: random.Random, work: Path, refs: dict[str, Any]) -> dict:
    index = json.loads((refs["base_folder"] / INDEX).read_text(encoding="utf-8"))
    tally = _new_tally() | {"refused": 0, "untouched": 0}
    crafted = _new_tally() | {"refused": 0, "untouched": 0, "opened_as_crafted": 0}
    for i in range(2 * n):
        folder = work / "hx"
        shutil.copytree(refs["base_folder"], folder)
        mutated = _mutate(json.loads(json.dumps(index)), rng)
        forged = i % 2 == 1  # the checksum recomputed: a crafted index, not a damaged one
        if forged and isinstance(mutated, dict):
            mutated = seal_index(mutated)
        (folder / INDEX).write_text(json.dumps(mutated), encoding="utf-8")
        t = crafted if forged else tally
        t0 = time.perf_counter()
        seen = _open(folder, [refs["base"]], t)
        t["hang"] += int(time.perf_counter() - t0 > 60)
        t["runs"] += 1
        t["refused"] += int(seen == "error")
        t["untouched"] += int(seen.startswith("ref"))
        if forged and seen == "wrong":  # says what the forger wrote: not counted as silent
            t["silent_wrong"] -= 1
            t["opened_as_crafted"] += 1
        shutil.rmtree(folder)
    scenes = _new_tally() | {"refused_one_line": 0, "content_leaked": 0}
    for section, key, value in HOSTILE_SCENES:
        sc = json.loads(json.dumps(BASE))
        sc.setdefault(section, {})
        sc[section][key] = value
        f = work / "hostile.toml"
        f.write_text(_toml(sc), encoding="utf-8")
        scenes["runs"] += 1
        try:
            res = subprocess.run(
                ["xpersson", "validate", str(f)], capture_output=True, text=True, timeout=60
            )
        except subprocess.TimeoutExpired:
            scenes["hang"] += 1
            continue
        lines = res.stderr.strip().splitlines()
        if "Traceback" in res.stderr or res.returncode not in (0, 2):
            scenes["traceback"] += 1
        elif res.returncode == 2 and len(lines) == 1:
            scenes["refused_one_line"] += 1
    scenes["content_leaked"] = _reproduce_hostile(work, refs)
    return {"indexes": tally, "crafted_indexes": crafted, "scenes": scenes}


def _reproduce_hostile(work: Path, refs: dict[str, Any]) -> int:
    """``reproduce`` of an archive whose scene names a system file, with and without
    ``--read-files``: how many runs printed a line of that file."""
    secret = work / "secret.txt"
    secret.write_text("root:x:0:0:SECRET-LINE\n" * 3, encoding="utf-8")
    ds = xpersson.open_dataset(refs["archive"])
    scene = json.loads(ds.attrs["xpersson_scene"])
    scene["spectrum"] = {"model": "tabulated", "file": str(secret)}
    ds.attrs["xpersson_scene"] = json.dumps(scene)
    hostile = xpersson.to_netcdf(ds, work / "hostile.nc", overwrite=True)
    leaked = 0
    for extra in ([], ["--read-files"]):
        cmd = ["xpersson", "reproduce", str(hostile), "-o", str(work / "rep.nc"), *extra]
        res = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
        leaked += int("SECRET-LINE" in res.stderr or res.returncode != 2)
    return leaked


# -- hang -----------------------------------------------------------------------------------------
HANG_RUNNER = """
import json, sys, time
import xpersson
from xpersson.plugins import Analysis, VarSpec
from xpersson.testing import registry_with
from xpersson.cli import main
HANG = set(json.loads(sys.argv[1]))
def compute(self, ctx, ds):
    if round(float(ctx.E) / 1e6) in HANG:
        while True:
            pass
    return {"extra": (("p0", "zeta"), ds["area_fraction"].transpose("p0", "zeta").values.copy())}
cls = type("Hanging", (Analysis,), {"summary": "hangs", "requires": ("area_fraction",),
    "provides": ("extra",), "outputs": {"extra": VarSpec(("p0", "zeta"), "1", "copy")},
    "compute": compute})
with registry_with(analyses={"hanging": cls}):
    sys.exit(main(sys.argv[2:]))
"""


def hang_campaign(n: int, rng: random.Random, work: Path) -> dict[str, Any]:
    tally = _new_tally() | {"points": 0, "hung_points": 0, "named_failures": 0, "others_ok": 0}
    e_values = [5, 7, 10, 14, 20, 28]
    for i in range(n):
        hang = sorted(rng.sample(e_values, rng.randint(1, 3)))
        sc = json.loads(json.dumps(BASE))
        sc["spectrum"]["H"] = 0.8
        sc["solver"] = {"plugin_time_limit": "0.5 s"}
        sc["analyses"] = {"hanging": {}}
        f = work / "hang.toml"
        f.write_text(_toml(sc), encoding="utf-8")
        out = work / f"hang{i}.nc"
        scheduler = ["serial", "threads"][i % 2]
        args = [sys.executable, "-c", HANG_RUNNER, json.dumps(hang), "run", str(f), "-o", str(out)]
        args += ["--scheduler", scheduler, "--workers", "2", "--quiet"]
        tally["runs"] += 1
        try:
            res = subprocess.run(args, capture_output=True, text=True, timeout=120)
        except subprocess.TimeoutExpired:
            tally["hang"] += 1
            continue
        if "Traceback" in res.stderr or res.returncode != 3:
            tally["traceback"] += 1
            continue
        ds = xpersson.open_dataset(out)
        e_mpa = (ds["E"].values / 1e6).round().astype(int)
        status = dict(zip(e_mpa, ds["point_status"].values, strict=True))
        msgs = json.loads(ds.attrs["xpersson_point_messages"])
        tally["points"] += len(status)
        tally["hung_points"] += len(hang)
        tally["named_failures"] += sum(
            "analysis plugin 'hanging'" in m["message"] and "time limit" in m["message"]
            for m in msgs
        )
        tally["others_ok"] += sum(int(v == 0) for e, v in status.items() if e not in hang)
        if any(status[e] != 2 for e in hang):
            tally["silent_wrong"] += 1
        out.unlink()
    return tally


def _references(work: Path) -> dict[str, Any]:
    refs: dict[str, Any] = {}
    refs["base_folder"] = work / "ref-base"
    refs["other_folder"] = work / "ref-other"
    refs["base"] = xpersson.solve(BASE, output=refs["base_folder"], chunk=CHUNK).load()
    refs["other"] = xpersson.solve(OTHER, output=refs["other_folder"], chunk=CHUNK).load()
    single = json.loads(json.dumps(BASE))
    single["spectrum"]["H"], single["material"]["E"] = 0.8, "10 MPa"
    single["output"].update(pressure_pdf=True, p_points=64)
    refs["single"] = xpersson.solve(single)
    refs["archive"] = xpersson.to_netcdf(refs["single"], work / "single.nc")
    refs["single"] = xpersson.open_dataset(refs["archive"])
    return refs


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--kills", type=int, default=10, help="runs per mode (fresh/overwrite/resume)")
    ap.add_argument("--races", type=int, default=5)
    ap.add_argument("--corrupt", type=int, default=50)
    ap.add_argument("--hostile", type=int, default=50)
    ap.add_argument("--hangs", type=int, default=4)
    ap.add_argument("--issue37", type=int, default=200, help="faults per class of issue 37")
    ap.add_argument("--only", default=None, help="comma-separated campaigns to run")
    ap.add_argument("--seed", type=int, default=24)
    ap.add_argument("--out", default=None, help="write the figures as JSON here")
    args = ap.parse_args()
    rng = random.Random(args.seed)
    results: dict[str, Any] = {}
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="xpersson-faults-") as tmp:
        work = Path(tmp)
        refs = _references(work)
        import warnings

        warnings.simplefilter("ignore")
        sys.path.insert(0, str(Path(__file__).parent))
        from faults37 import campaigns as issue37

        campaigns = issue37(args.issue37, rng, work, refs) + [
            ("kill", lambda: kill_campaign(args.kills, rng, work, refs)),
            ("race", lambda: race_campaign(args.races, work)),
            ("corrupt", lambda: corrupt_campaign(args.corrupt, rng, work, refs)),
            ("hostile", lambda: hostile_campaign(args.hostile, rng, work, refs)),
            ("hang", lambda: hang_campaign(args.hangs, rng, work)),
        ]
        for name, fn in campaigns:
            if args.only and name not in args.only.split(","):
                continue
            t1 = time.perf_counter()
            try:
                results[name] = fn()
            except (SceneError, ArchiveError) as exc:  # a campaign that could not run
                results[name] = {"error": str(exc)}
            results[name]["seconds"] = round(time.perf_counter() - t1, 1)
            print(name, json.dumps(results[name]), flush=True)
    results["seconds"] = round(time.perf_counter() - t0, 1)
    if args.out:
        Path(args.out).write_text(json.dumps(results, indent=1), encoding="utf-8")


if __name__ == "__main__":
    main()
