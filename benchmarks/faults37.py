"""Fault campaigns of issue 37 (the reader, the disk, the forger), run by ``benchmarks/faults.py``.

Each campaign injects at least ``n`` faults of one class and counts (next to ``runs``) silent
wrong results, tracebacks (an exception other than the documented one-line errors), hangs and
lost parts:

- ``snapshot``: a writer replaces a sweep folder's parts and index with another study's (one
  atomic replace at a time, as a run does) while a reader that opened the folder loads it, with
  the parts kept in memory or re-read: the reader gets the opened study or an ArchiveError.
- ``disk``: ENOSPC / EDQUOT / EFBIG / EROFS / EACCES injected at a random ``fsync`` or netCDF
  write of a sweep or of ``to_netcdf``, and real file-size limits (``RLIMIT_FSIZE``) on CLI
  runs: one line naming the path and the cause, nothing half-written, the study resumed equal.
- ``forge``: digests removed, format versions changed, values altered; sweep index fields
  changed with the index checksum recomputed: an error, ``unverified``, or the original values.
- ``coords``: analysis outputs on perturbed coordinates: a PluginFailure naming the plugin and
  the variable, or (coordinates identical) the right values.
- ``limits``: sleeping and looping calls under limits in threads and the main thread, a
  spectrum ``build()`` that sleeps under the default limit, non-regular files for ``reproduce
  --read-files``: interrupted in time, refused in one line.
- ``budgets``: unit texts of large powers, hostile environment values: a value or one line.
- ``texts``: control characters and surrogates in random attributes, duplicated index entries:
  refused naming the attribute (or both entries), or stored and given back identical.
"""

from __future__ import annotations

import contextlib
import errno
import json
import os
import random
import shutil
import subprocess
import sys
import threading
import time
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

import xpersson
from xpersson.errors import ArchiveError
from xpersson.sweep import INDEX
from xpersson.sweep.parts import seal_index

SMALL: dict[str, Any] = {
    "spectrum": {"model": "self_affine", "H": [0.7, 0.8], "q_L": "1e3 1/m", "q_r": "1e4 1/m",
                 "q_1": "1e6 1/m", "h_rms": "1 um"},
    "material": {"E": ["5 MPa", "10 MPa"], "nu": 0.5},
    "load": {"p0": "1e5 Pa"},
    "output": {"zeta_per_decade": 2},
}  # fmt: skip
ERRNOS = ("ENOSPC", "EDQUOT", "EFBIG", "EROFS", "EACCES")


def tally() -> dict[str, Any]:
    return {"runs": 0, "silent_wrong": 0, "traceback": 0, "hang": 0, "lost": 0}


def _values_equal(a: xr.Dataset, b: xr.Dataset) -> bool:
    """Same data and coordinates (attributes aside: forged attributes are admitted)."""
    a, b = a.load(), b.load()
    if set(a.variables) != set(b.variables):
        return False
    return all(a[n].variable.equals(b[n].variable) for n in a.variables)


def _one_line(exc: BaseException) -> bool:
    return "\n" not in str(exc) and bool(str(exc))


def _bad(t: dict[str, Any], exc: BaseException) -> None:
    t["traceback"] += 1
    t.setdefault("examples", []).append(f"{type(exc).__name__}: {exc}"[:240])


# -- 1. reader against writer ---------------------------------------------------------------------
def snapshot_campaign(n: int, rng: random.Random, work: Path, refs: dict[str, Any]) -> dict:
    from xpersson.sweep import parts

    t = tally() | {"kept": 0, "reread": 0, "error": 0, "opened_study": 0}
    base, other = refs["small_folder"], refs["small_other_folder"]
    for i in range(n):
        folder = work / f"snap{i}"
        shutil.copytree(base, folder)
        kept = rng.random() < 0.5
        t["kept" if kept else "reread"] += 1
        saved = parts.SNAPSHOT_BYTES
        parts.SNAPSHOT_BYTES = saved if kept else -1
        try:
            ds = xpersson.open_dataset(folder)
        finally:
            parts.SNAPSHOT_BYTES = saved
        names = sorted(p.name for p in other.iterdir() if p.name.startswith("part-"))
        rng.shuffle(names)
        writer = threading.Thread(target=_overwrite, args=(other, folder, names, rng.random()))
        writer.start()
        time.sleep(rng.uniform(0, 0.02))
        t["runs"] += 1
        try:
            got = ds.load()
        except ArchiveError as exc:
            t["error"] += 1
            if not _one_line(exc) or "part-" not in str(exc):
                _bad(t, exc)
        except Exception as exc:  # noqa: BLE001 - counted
            _bad(t, exc)
        else:
            if _values_equal(got, refs["small"]):
                t["opened_study"] += 1
            else:
                t["silent_wrong"] += 1
        writer.join(30)
        t["hang"] += int(writer.is_alive())
        shutil.rmtree(folder, ignore_errors=True)
    return t


def _overwrite(src: Path, dst: Path, names: list[str], pause: float) -> None:
    for name in [*names, INDEX]:  # atomic replaces, as a run's writes
        tmp = dst / f".{name}.w"
        shutil.copyfile(src / name, tmp)
        os.replace(tmp, dst / name)
        time.sleep(pause * 0.004)


# -- 2. the disk ----------------------------------------------------------------------------------
def disk_campaign(n: int, rng: random.Random, work: Path, refs: dict[str, Any]) -> dict:
    t = tally() | {"one_line_errors": 0, "half_written": 0, "no_fault_hit": 0, "fsize_cli": 0}
    n_cli = max(n // 20, 4)
    for i in range(n - n_cli):
        code = getattr(errno, rng.choice(ERRNOS))
        sweep = i % 2 == 0
        folder = work / f"disk{i}"
        folder.mkdir()
        target = folder / ("s" if sweep else "a.nc")
        mode = rng.choice(("fsync", "hdf"))
        t["runs"] += 1
        try:
            calls = (6 if mode == "fsync" else 4) if sweep else 1  # index, 4 parts, index
            with _inject(mode, code, rng.randint(1, calls)):
                if sweep:
                    xpersson.solve(SMALL, output=target, chunk=1)
                else:
                    xpersson.to_netcdf(refs["single"], target)
            t["no_fault_hit"] += 1
        except OSError as exc:
            ok = _one_line(exc) and os.strerror(code) in str(exc) and str(folder) in str(exc)
            t["one_line_errors"] += int(ok)
            if not ok:
                _bad(t, exc)
        except Exception as exc:  # noqa: BLE001 - counted
            _bad(t, exc)
        left = [p.name for p in folder.rglob("*") if p.name.endswith((".part", ".tmp"))]
        t["half_written"] += int(bool(left))
        if sweep:  # resumed without faults: the whole study, bit for bit in values
            try:
                ds = xpersson.solve(SMALL, output=target, chunk=1)
                t["lost"] += int(not _values_equal(ds, refs["small"]))
            except Exception as exc:  # noqa: BLE001 - counted
                _bad(t, exc)
        shutil.rmtree(folder)
    for i in range(n_cli):
        t["runs"] += 1
        t["fsize_cli"] += 1
        _fsize_cli(work, i, rng, t)
    return t


@contextlib.contextmanager
def _inject(mode: str, code: int, k: int):
    """OSError ``code`` at the ``k``-th fsync, or the ``k``-th netCDF write failing as "HDF
    error" on a full disk (the probe write gets ``code``)."""
    calls = {"n": 0}
    real_fsync, real_write = os.fsync, os.write
    real_nc = xr.Dataset.to_netcdf

    def fail() -> None:
        raise OSError(code, os.strerror(code))

    def fsync(fd: int) -> None:
        calls["n"] += 1
        if calls["n"] == k:
            fail()
        real_fsync(fd)

    def to_netcdf(self: Any, *a: Any, **kw: Any) -> Any:
        calls["n"] += 1
        if calls["n"] == k and a:
            os.write = lambda fd, data: fail()  # the probe meets the full disk
            raise OSError(-101, "NetCDF: HDF error")
        return real_nc(self, *a, **kw)

    if mode == "fsync":
        os.fsync = fsync
    else:
        xr.Dataset.to_netcdf = to_netcdf
    try:
        yield
    finally:
        os.fsync, os.write = real_fsync, real_write
        xr.Dataset.to_netcdf = real_nc


_FSIZE = """
import resource, sys
resource.setrlimit(resource.RLIMIT_FSIZE, (int(sys.argv[1]), int(sys.argv[1])))
from xpersson.cli import main
sys.exit(main(sys.argv[2:]))
"""


def _fsize_cli(work: Path, i: int, rng: random.Random, t: dict[str, Any]) -> None:
    scene = work / f"fsize{i}.toml"
    sweep = i % 2 == 1
    data = json.loads(json.dumps(SMALL))
    if not sweep:
        data["spectrum"]["H"], data["material"]["E"] = 0.8, "5 MPa"
    lines = []
    for sec, table in data.items():
        lines += [f"[{sec}]"] + [f"{k} = {json.dumps(v)}" for k, v in table.items()]
    scene.write_text("\n".join(lines) + "\n")
    out = work / (f"fsize{i}/" if sweep else f"fsize{i}.nc")
    limit = rng.randint(2000, 60000)
    args = [sys.executable, "-c", _FSIZE, str(limit), "run", str(scene), "-o", str(out)]
    try:
        res = subprocess.run(args, capture_output=True, text=True, timeout=300)
    except subprocess.TimeoutExpired:
        t["hang"] += 1
        return
    lines = res.stderr.strip().splitlines()
    if res.returncode == 0:
        return  # the limit was large enough
    if res.returncode != 2 or len(lines) != 1 or "File too large" not in lines[0]:
        t["traceback"] += 1
        t.setdefault("examples", []).append(res.stderr[-240:])
    t["one_line_errors"] += int(res.returncode == 2)
    base = Path(str(out).rstrip("/"))
    left = [p for p in base.parent.rglob(f"*{base.name}*") if p.name.endswith((".part", ".tmp"))]
    t["half_written"] += int(bool(left))


# -- 3. the forger --------------------------------------------------------------------------------
def forge_campaign(n: int, rng: random.Random, work: Path, refs: dict[str, Any]) -> dict:
    import netCDF4

    t = tally() | {"error": 0, "unverified": 0, "unchanged": 0}
    src = refs["archive"]
    for i in range(n // 2):
        path = work / f"forge{i}.nc"
        shutil.copyfile(src, path)
        kind = rng.choice(("drop_digest", "drop_global", "format", "strip_all", "drop_some"))
        with netCDF4.Dataset(path, "a") as nc:
            names = list(nc.variables)
            victim = nc.variables[rng.choice([m for m in names if nc.variables[m].ndim])]
            if kind in ("drop_digest", "drop_some"):
                for m in rng.sample(names, 1 if kind == "drop_digest" else rng.randint(1, 5)):
                    nc.variables[m].delncattr("xpersson_sha256")
            elif kind == "drop_global":
                nc.delncattr("xpersson_attrs_sha256")
            elif kind == "format":
                nc.setncattr("xpersson_archive_format", np.int32(rng.choice((1, 4, 99, -3))))
            else:
                nc.delncattr("xpersson_attrs_sha256")
                nc.delncattr("xpersson_archive_format")
                for m in names:
                    nc.variables[m].delncattr("xpersson_sha256")
            victim[...] = np.asarray(victim[...]) + 1
        _classify_forged(path, refs["single"], t)
    for i in range(n - n // 2):
        folder = work / f"forge-s{i}"
        shutil.copytree(refs["small_folder"], folder)
        index = json.loads((folder / INDEX).read_text())
        _forge_index(index, rng)
        (folder / INDEX).write_text(json.dumps(seal_index(index)))
        _classify_forged(folder, refs["small"], t)
        shutil.rmtree(folder)
    return t


def _forge_index(index: dict[str, Any], rng: random.Random) -> None:
    field = rng.choice(("constant", "coords", "grid", "range", "dims", "attrs", "swap"))
    if field == "constant":
        var = rng.choice(["area_fraction", "G", "P", "mean_gap", "diffusion_time"])
        index["constant"][var] = rng.sample(index["dims"], rng.randint(1, len(index["dims"])))
    elif field == "coords":
        name = rng.choice(sorted(index["coords"]))
        values = index["coords"][name][1]
        values[rng.randrange(len(values))] *= rng.choice((1.0000001, 2.0, -1.0))
    elif field == "grid":
        entry = rng.choice(index["parts"])
        entry["grid_index"] = [g ^ 1 for g in entry["grid_index"]]
    elif field == "range":
        entry = rng.choice(index["parts"])
        entry["start"] = [max(s - 1, 0) for s in entry["start"]]
    elif field == "dims":
        index["dims"] = list(reversed(index["dims"]))
    elif field == "attrs":
        index["attrs"]["status"] = "success"
        index["attrs"]["title"] = "forged"
    else:
        a, b = rng.sample(range(len(index["parts"])), 2)
        pa, pb = index["parts"][a], index["parts"][b]
        pa["name"], pb["name"] = pb["name"], pa["name"]
        pa["sha256"], pb["sha256"] = pb["sha256"], pa["sha256"]


def _classify_forged(path: Path, ref: xr.Dataset, t: dict[str, Any]) -> None:
    t["runs"] += 1
    try:
        ds = xpersson.open_dataset(path).load()
    except ArchiveError as exc:
        t["error"] += 1
        if not _one_line(exc):
            _bad(t, exc)
        return
    except Exception as exc:  # noqa: BLE001 - counted
        _bad(t, exc)
        return
    if ds.attrs.get("status") == "unverified":
        t["unverified"] += 1
    elif _values_equal(ds, ref):
        t["unchanged"] += 1
    else:
        t["silent_wrong"] += 1


def campaigns(n: int, rng: random.Random, work: Path, refs: dict[str, Any]) -> list[Any]:
    """The campaigns of issue 37 (:mod:`faults37`, :mod:`faults37_inputs`)."""
    import faults37_inputs as b

    a = sys.modules[__name__]

    def small() -> None:
        if "small" not in refs:
            refs["small_folder"] = work / "ref-small"
            refs["small_other_folder"] = work / "ref-small-other"
            other = json.loads(json.dumps(a.SMALL))
            other["material"]["E"] = ["5 MPa", "11 MPa"]
            refs["small"] = xpersson.solve(a.SMALL, output=refs["small_folder"], chunk=1).load()
            xpersson.solve(other, output=refs["small_other_folder"], chunk=1)

    def run(fn: Any) -> Any:
        return lambda: (small(), fn(n, rng, work, refs))[1]

    return [
        ("snapshot", run(a.snapshot_campaign)),
        ("disk", run(a.disk_campaign)),
        ("forge", run(a.forge_campaign)),
        ("coords", run(b.coords_campaign)),
        ("limits", run(b.limits_campaign)),
        ("budgets", run(b.budgets_campaign)),
        ("texts", run(b.texts_campaign)),
    ]
