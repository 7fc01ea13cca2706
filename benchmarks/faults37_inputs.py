"""Fault campaigns of issue 37, continued: plugin coordinates, time limits, budgets, texts
(see :mod:`faults37` for the counting; run by ``benchmarks/faults.py``)."""

from __future__ import annotations

import json
import os
import random
import shutil
import threading
import time
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr
from faults37 import _bad, _one_line, tally

import xpersson
from xpersson.errors import ArchiveError
from xpersson.sweep import INDEX
from xpersson.sweep.parts import seal_index

SINGLE: dict[str, Any] = {
    "spectrum": {"model": "self_affine", "H": 0.8, "q_L": "1e3 1/m", "q_r": "1e4 1/m",
                 "q_1": "1e6 1/m", "h_rms": "1 um"},
    "material": {"E": "5 MPa", "nu": 0.5},
    "load": {"p0": ["1e4 Pa", "1e5 Pa"]},
    "output": {"zeta_per_decade": 2},
}  # fmt: skip


# -- 4. plugin outputs on the solved coordinates --------------------------------------------------
def coords_campaign(n: int, rng: random.Random, work: Path, refs: dict[str, Any]) -> dict:
    from xpersson.checks import PluginFailure
    from xpersson.plugins import Analysis, VarSpec
    from xpersson.testing import registry_with

    how: dict[str, Any] = {}

    def compute(self: Any, ctx: Any, ds: xr.Dataset) -> dict[str, Any]:
        da = ds["area_fraction"].transpose("p0", "zeta").copy()
        return {"extra": how["change"](da)}

    cls = type("Shifting", (Analysis,), {
        "summary": "perturbed coordinates", "requires": ("area_fraction",),
        "provides": ("extra",), "outputs": {"extra": VarSpec(("p0", "zeta"), "1", "copy")},
        "compute": compute})  # fmt: skip
    scene = json.loads(json.dumps(SINGLE)) | {"analyses": {"shifting": {}}}
    t = tally() | {"named_failures": 0, "identical_ok": 0}
    with registry_with(analyses={"shifting": cls}):
        for _ in range(n):
            change, same = _perturbation(rng)
            how["change"] = change
            t["runs"] += 1
            try:
                ds = xpersson.solve(scene)
            except PluginFailure as exc:
                ok = "shifting" in str(exc) and "'extra'" in str(exc) and _one_line(exc)
                t["named_failures"] += int(ok)
                if same or not ok:
                    _bad(t, exc)
                continue
            except Exception as exc:  # noqa: BLE001 - counted
                _bad(t, exc)
                continue
            right = ds["area_fraction"].transpose("p0", "zeta")
            good = same and np.array_equal(ds["extra"].values, right.values, equal_nan=True)
            t["identical_ok"] += int(good)
            t["silent_wrong"] += int(not good)
    return t


def _perturbation(rng: random.Random) -> tuple[Any, bool]:
    kind = rng.choice(("scale", "ulp", "reverse", "p0", "roll", "same", "subset"))
    if kind == "same":
        return (lambda da: da), True
    if kind == "scale":
        f = rng.uniform(0.5, 2.0)
        return (lambda da: da.assign_coords(zeta=da["zeta"].values * f)), False
    if kind == "ulp":
        k = rng.randrange(5)
        return (lambda da: da.assign_coords(zeta=_nudge(da["zeta"].values, k))), False
    if kind == "reverse":
        return (lambda da: da.assign_coords(zeta=da["zeta"].values[::-1])), False
    if kind == "p0":
        return (lambda da: da.assign_coords(p0=da["p0"].values * 1.5)), False
    if kind == "roll":
        return (lambda da: da.assign_coords(zeta=np.roll(da["zeta"].values, 1))), False
    return (lambda da: da.isel(zeta=slice(1, None))), False


def _nudge(values: np.ndarray, k: int) -> np.ndarray:
    out = values.copy()
    out[k] = np.nextafter(out[k], np.inf)
    return out


# -- 5. time limits -------------------------------------------------------------------------------
def limits_campaign(n: int, rng: random.Random, work: Path, refs: dict[str, Any]) -> dict:
    from xpersson.plugins import PluginTimeout, limited

    t = tally() | {"interrupted": 0, "completed": 0, "late": 0, "refused_files": 0, "builds": 0}
    n_calls = n - 20
    for _ in range(0, n_calls, 4):  # four threads at a time
        jobs = [(rng.uniform(0.05, 0.2), rng.choice(("sleep", "loop", "short"))) for _ in range(4)]
        results: list[Any] = [None] * 4

        def one(j: int, limit: float, kind: str, results: list[Any] = results) -> None:
            t0 = time.monotonic()
            try:
                with limited(limit):
                    if kind == "sleep":
                        time.sleep(30)
                    elif kind == "loop":
                        while time.monotonic() - t0 < 30:
                            pass
                    else:
                        time.sleep(limit / 4)
                results[j] = ("done", time.monotonic() - t0)
            except PluginTimeout:
                results[j] = ("timeout", time.monotonic() - t0)

        threads = [threading.Thread(target=one, args=(j, *job)) for j, job in enumerate(jobs)]
        for th in threads:
            th.start()
        for th in threads:
            th.join(20)
        for (limit, kind), th, res in zip(jobs, threads, results, strict=True):
            t["runs"] += 1
            if th.is_alive() or res is None:
                t["hang"] += 1
            elif kind == "short":
                t["completed"] += int(res[0] == "done")
                t["silent_wrong"] += int(res[0] != "done")
            else:
                t["interrupted"] += int(res[0] == "timeout")
                t["late"] += int(res[1] > limit + 2.0)
                t["hang"] += int(res[0] != "timeout")
    _builds(t, 6)
    _files(work, t, 14)
    return t


def _builds(t: dict[str, Any], n: int) -> None:
    """A spectrum ``build()`` that sleeps, under the default limit (set_options)."""
    from xpersson.scene import _resolve

    real = _resolve._build_spectrum

    def slow(spectrum: Any, who: Any) -> Any:
        with _resolve.calling(who, "build()"):
            time.sleep(60)

    _resolve._build_spectrum = slow
    try:
        for _ in range(n):
            t["runs"] += 1
            t0 = time.monotonic()
            try:
                with xpersson.set_options(plugin_time_limit=0.2):
                    xpersson.solve(SINGLE)
                t["silent_wrong"] += 1
            except TimeoutError as exc:
                t["builds"] += int("build()" in str(exc))
                t["hang"] += int(time.monotonic() - t0 > 5)
    finally:
        _resolve._build_spectrum = real


def _files(work: Path, t: dict[str, Any], n: int) -> None:
    """``reproduce --read-files`` of archives naming a FIFO, devices, a folder, a huge file."""
    from xpersson.cli import main

    fifo = work / "fifo"
    if not fifo.exists():
        os.mkfifo(fifo)
    huge = work / "huge.csv"
    with open(huge, "wb") as f:
        f.truncate(300 * 2**20)  # sparse
    names = [str(fifo), "/dev/zero", "/dev/urandom", str(work), str(huge), "/dev/stdin"]
    ds = refs_single = xpersson.solve(SINGLE)
    for i in range(n):
        target = names[i % len(names)]
        data = json.loads(ds.attrs["xpersson_scene"])
        data["spectrum"] = {"model": "tabulated", "file": target}
        arch = refs_single.copy()
        arch.attrs = {**ds.attrs, "xpersson_scene": json.dumps(data)}
        path = work / f"rf{i}.nc"
        xpersson.to_netcdf(arch, path, overwrite=True)
        t["runs"] += 1
        t0 = time.monotonic()
        code = main(["reproduce", str(path), "-o", str(work / f"rf{i}-o.nc"), "--read-files"])
        t["refused_files"] += int(code == 2)
        t["hang"] += int(time.monotonic() - t0 > 30)
        t["silent_wrong"] += int(code != 2)


# -- 6. budgets -----------------------------------------------------------------------------------
def budgets_campaign(n: int, rng: random.Random, work: Path, refs: dict[str, Any]) -> dict:
    from xpersson import memory, options
    from xpersson.units import to_si

    t = tally() | {"refused": 0, "accepted": 0}
    for i in range(n):
        t["runs"] += 1
        kind = i % 3
        try:
            if kind == 0:
                to_si(_power_text(rng), rng.choice(("Pa", "1", "m")), "load.p0")
            elif kind == 1:
                os.environ["XPERSSON_MEMORY_BUDGET"] = _number_text(rng)
                memory.budget()
            else:
                os.environ["XPERSSON_PLUGIN_TIME_LIMIT"] = _number_text(rng)
                options.set_options(plugin_time_limit=None)
                options.plugin_time_limit()
            t["accepted"] += 1
        except ValueError as exc:
            t["refused"] += 1
            named = ("load.p0", "XPERSSON_MEMORY_BUDGET", "XPERSSON_PLUGIN_TIME_LIMIT")[kind]
            if not _one_line(exc) or named not in str(exc):
                _bad(t, exc)
        except Exception as exc:  # noqa: BLE001 - counted
            _bad(t, exc)
        finally:
            os.environ.pop("XPERSSON_MEMORY_BUDGET", None)
            os.environ.pop("XPERSSON_PLUGIN_TIME_LIMIT", None)
            options.set_options(plugin_time_limit=None)
    return t


def _power_text(rng: random.Random) -> str:
    prefixes = ["", "k", "M", "G", "T", "P", "E", "Y", "m", "u", "n", "y"]
    terms = []
    for _ in range(rng.randint(1, 6)):
        p = rng.choice(prefixes) + rng.choice(["m", "Pa", "s", "g"])
        e = rng.choice(["", f"**{rng.randint(-64, 64)}", f"^{rng.randint(1, 64)}"])
        terms.append(p + e)
    ops = [rng.choice(("*", "/", " ")) for _ in terms[1:]]
    body = terms[0] + "".join(o + x for o, x in zip(ops, terms[1:], strict=True))
    if rng.random() < 0.3:
        body = f"({body})"
    return f"{rng.choice(('1', '1e300', '3.5', '-2e-300'))} {body}"


def _number_text(rng: random.Random) -> str:
    return rng.choice(
        [
            "1e999",
            "-1",
            "0",
            "nan",
            "inf",
            "1.2.3",
            "",
            "9" * 400,
            "2 GB",
            "1e30 GB",
            "abc",
            "1e-999",
        ]
        + [f"{rng.uniform(-10, 1e20):g}", f"{rng.randint(1, 10**30)}"]
    )


# -- 7. texts -------------------------------------------------------------------------------------
def texts_campaign(n: int, rng: random.Random, work: Path, refs: dict[str, Any]) -> dict:
    t = tally() | {"refused": 0, "round_trip": 0, "duplicates_named": 0}
    src = refs["single"]
    n_dup = max(n // 10, 20)
    for i in range(n - n_dup):
        ds = src.copy(deep=False)
        ds.attrs = dict(src.attrs)
        text = _hostile_text(rng)
        on_var = rng.random() < 0.5
        key = rng.choice(("title", "comment", "history", "xpersson_note", text[:8] or "k"))
        target = ds[rng.choice(list(ds.data_vars))] if on_var else ds
        if on_var:
            target.attrs = dict(target.attrs)
        target.attrs[key] = text
        path = work / f"text{i}.nc"
        t["runs"] += 1
        try:
            xpersson.to_netcdf(ds, path)
        except ValueError as exc:
            t["refused"] += 1
            if not _one_line(exc) or "attribute" not in str(exc):
                _bad(t, exc)
            continue
        except Exception as exc:  # noqa: BLE001 - counted
            _bad(t, exc)
            continue
        try:
            back = xpersson.open_dataset(path)
            got = (back[target.name] if on_var else back).attrs.get(key)
            ok = got == text
        except Exception:  # noqa: BLE001 - written but not readable: silent wrong
            ok = False
        t["round_trip"] += int(ok)
        t["silent_wrong"] += int(not ok)
        path.unlink()
    for i in range(n_dup):
        folder = work / f"dup{i}"
        shutil.copytree(refs["small_folder"], folder)
        index = json.loads((folder / INDEX).read_text())
        a, b = sorted(rng.sample(range(len(index["parts"])), 2))
        index["parts"][b]["name"] = index["parts"][a]["name"]
        (folder / INDEX).write_text(json.dumps(seal_index(index)))
        t["runs"] += 1
        try:
            xpersson.open_dataset(folder)
            t["silent_wrong"] += 1
        except ArchiveError as exc:
            t["duplicates_named"] += int(f"parts[{a}]" in str(exc) and f"parts[{b}]" in str(exc))
        shutil.rmtree(folder)
    return t


def _hostile_text(rng: random.Random) -> str:
    pool = ["a", "é", " ", "\t", "\n", "\x00", "\x01", "\x1b", "\x7f", "\ud800", "\udfff", "€"]
    pool += ["\u2028", "\ufeff", "\U0001f600", "%", "\\", '"']
    return "".join(rng.choice(pool) for _ in range(rng.randint(1, 12)))
