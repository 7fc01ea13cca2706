"""Bitwise fingerprint of every output: the examples and a seeded set of generated scenes.

A refactoring that must leave results unchanged bit for bit (issue 33: the fast-path contract,
the one cache mechanism, the readable march) is checked by fingerprinting every data variable,
coordinate and (non-volatile) attribute of

* every example scene (``examples/*.toml`` and ``plugins/*/examples/*.toml``),
* ``--scenes`` (600) generated single scenes (``benchmarks/fuzz.py``'s generator, seed ``--seed``;
  refused scenes are recorded with their message, so a change of what is refused shows too),
* ``--sweeps`` (40) generated sweeps (E x H, E x nu x loads, H x loads, analyses on), which take the
  batched and stacked fast paths of :mod:`xpersson.sweep`,

before and after the change, and comparing the two files::

    OPENBLAS_NUM_THREADS=1 python benchmarks/bitwise.py record --out before.json
    # ... the change ...
    OPENBLAS_NUM_THREADS=1 python benchmarks/bitwise.py record --out after.json
    XPERSSON_CACHE=off OPENBLAS_NUM_THREADS=1 python benchmarks/bitwise.py record --out off.json
    python benchmarks/bitwise.py compare before.json after.json
    python benchmarks/bitwise.py compare before.json off.json

``compare`` prints every scene whose fingerprint differs (variable by variable) and exits 1 if
any does. Not part of CI (a few minutes).
"""

from __future__ import annotations

import argparse
import contextlib
import hashlib
import json
import math
import random
import shutil
import signal
import sys
import tempfile
import warnings
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))

#: global attributes that change from run to run (time stamps, environment, run ids)
VOLATILE = ("history", "date_created", "date_modified", "environment", "run_id", "provenance")


def _digest(values: Any) -> str:
    a = np.asarray(values)
    h = hashlib.sha256()
    h.update(f"{a.dtype.str}{a.shape}".encode())
    if a.dtype.kind == "O":
        h.update(repr(a.tolist()).encode())
    else:
        h.update(np.ascontiguousarray(a).tobytes())
    return h.hexdigest()[:24]


def _steady(value: Any) -> Any:
    """A JSON attribute without its timings (``wall_time_s``, ...)."""
    if isinstance(value, str) and value.startswith("{"):
        with contextlib.suppress(ValueError):
            return _drop_times(json.loads(value))
    return value


def _drop_times(obj: Any) -> Any:
    if isinstance(obj, dict):
        return {k: _drop_times(v) for k, v in obj.items() if "time" not in k}
    if isinstance(obj, list):
        return [_drop_times(v) for v in obj]
    return obj


#: Where the generated scenes' spectrum files are named in the records (attributes and
#: messages): the recording's private scratch directory is written as this one, so records
#: made at the same time in different directories (and older records) compare equal. A fixed
#: text, not under ``TMPDIR``: records made with different ``TMPDIR`` compare equal too.
STABLE_TMP = "<scratch>/xpersson-bitwise"
_SCRATCH: list[str] = []  # the private scratch directory of the recording under way


def _stable(text: str) -> str:
    """``text`` with the private scratch directory written as :data:`STABLE_TMP`."""
    for path in _SCRATCH:
        text = text.replace(path, STABLE_TMP)
    return text


def _attrs_digest(attrs: dict[str, Any]) -> str:
    keep = {k: _steady(v) for k, v in attrs.items() if not any(s in k for s in VOLATILE)}
    text = _stable(repr(sorted((k, repr(v)) for k, v in keep.items())))
    return _digest(np.array(text, dtype=object))


def fingerprint(ds: Any) -> dict[str, str]:
    """Digest of every variable's values and attributes, and of the global attributes."""
    out: dict[str, str] = {}
    for name in sorted(map(str, ds.variables)):
        var = ds.variables[name]
        out[name] = _digest(var.values) + "/" + "".join(var.dims)
        out[name + ".attrs"] = _attrs_digest(dict(var.attrs))
    out[".attrs"] = _attrs_digest(dict(ds.attrs))
    return out


def _solve(scene: Any) -> dict[str, str]:
    import xpersson

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            ds = xpersson.solve(scene)
        except (xpersson.SceneError, xpersson.PluginFailure) as exc:
            return {"refused": type(exc).__name__ + ": " + _stable(str(exc))[:400]}
    return fingerprint(ds)


def example_scenes() -> dict[str, Any]:
    paths = sorted(ROOT.glob("examples/*.toml")) + sorted(ROOT.glob("plugins/*/examples/*.toml"))
    return {str(p.relative_to(ROOT)): p for p in paths}


def generated_scenes(n: int, seed: int, tmpdir: str) -> dict[str, Any]:
    from fuzz import make_scene

    from xpersson.plugins import get_registry

    registry = get_registry()
    return {f"gen-{seed}-{i}": make_scene(i, seed, registry, tmpdir) for i in range(n)}


def _lin(rng: random.Random, lo: float, hi: float) -> float:
    return rng.uniform(lo, hi)


def _log(rng: random.Random, lo: float, hi: float) -> float:
    return 10 ** rng.uniform(math.log10(lo), math.log10(hi))


def generated_sweeps(n: int, seed: int) -> dict[str, Any]:
    """Sweeps that take the fast paths: material (E, nu), spectrum (H, h_rms) and loads."""
    out: dict[str, Any] = {}
    for i in range(n):
        rng = random.Random(seed * 7919 + i)
        q_L = _log(rng, 1e2, 1e5)
        zmax = _log(rng, 10.0, 1e5)
        spectrum: dict[str, Any] = {
            "model": "self_affine",
            "H": _lin(rng, 0.3, 0.95),
            "q_L": f"{q_L!r} 1/m",
            "q_r": f"{q_L * (1.0 if rng.random() < 0.5 else _log(rng, 1.0, 10.0))!r} 1/m",
            "q_1": f"{q_L * zmax!r} 1/m",
            "rms_slope": _log(rng, 0.03, 1.0),
        }
        E = _log(rng, 1e6, 1e11)
        material: dict[str, Any] = {"E": f"{E!r} Pa", "nu": _lin(rng, 0.0, 0.5)}
        kind = i % 4
        if kind in (0, 2):
            material["E"] = [f"{E * s!r} Pa" for s in (0.5, 1.0, 3.0)]
        if kind in (1, 2):
            spectrum["H"] = [round(_lin(rng, 0.3, 0.95), 3) for _ in range(3)]
        if kind == 3:
            material["nu"] = [0.0, 0.3, 0.5]
            spectrum["rms_slope"] = [0.05, 0.2]
        p_ref = E * spectrum_slope(spectrum) * _log(rng, 1e-4, 0.1)
        n_load = rng.choice((1, 1, 3, 10))
        loads = (
            f"{p_ref!r} Pa"
            if n_load == 1
            else {"start": f"{p_ref / 10!r} Pa", "stop": f"{p_ref!r} Pa", "num": n_load}
        )
        scene: dict[str, Any] = {
            "spectrum": spectrum,
            "material": material,
            "load": {"p0": loads},
            "output": {"zeta_per_decade": rng.choice((4, 8, 10))},
            "coefficient": {"model": "elastic", "closure": rng.choice(("persson01", "yp08"))},
        }
        analyses = ["contact_area", "mean_gap", "elastic_energy", "contact_stiffness"]
        scene["analyses"] = {a: {} for a in rng.sample(analyses, rng.randint(0, 3))}
        out[f"sweep-{seed}-{i}"] = scene
    return out


def spectrum_slope(spectrum: dict[str, Any]) -> float:
    s = spectrum["rms_slope"]
    return float(min(s) if isinstance(s, list) else s)


def record(args: argparse.Namespace) -> int:
    results: dict[str, Any] = {}

    def _alarm(*_: Any) -> None:
        raise TimeoutError("scene over its time limit")

    signal.signal(signal.SIGALRM, _alarm)
    tmp = tempfile.mkdtemp(prefix="xpersson-bitwise-")  # private: recordings run at once
    _SCRATCH[:] = [tmp]
    try:
        _record_into(args, results, tmp)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
        _SCRATCH.clear()
    Path(args.out).write_text(json.dumps(results, indent=0, sort_keys=True))
    solved = sum(1 for r in results.values() if not ({"refused", "crash", "timeout"} & set(r)))
    print(f"{len(results)} scenes, {solved} solved -> {args.out}")
    return 0


def _record_into(args: argparse.Namespace, results: dict[str, Any], tmp: str) -> None:
    """Solve every scene of the recording into ``results`` (generated spectra in ``tmp``)."""
    scenes: dict[str, Any] = {}
    if not args.no_examples:
        scenes.update(example_scenes())
    scenes.update(generated_scenes(args.scenes, args.seed, tmp))
    scenes.update(generated_sweeps(args.sweeps, args.seed))
    for k, (name, scene) in enumerate(scenes.items()):
        signal.alarm(args.time_limit)
        try:
            results[name] = _solve(scene)
        except TimeoutError as exc:
            results[name] = {"timeout": str(exc)}
        except Exception as exc:  # noqa: BLE001 - recorded, compared like any result
            results[name] = {"crash": _stable(f"{type(exc).__name__}: {exc}")[:400]}
        finally:
            signal.alarm(0)
        if args.verbose:
            print(k, name, next(iter(results[name]))[:40], flush=True)


def compare(args: argparse.Namespace) -> int:
    a = json.loads(Path(args.a).read_text())
    b = json.loads(Path(args.b).read_text())
    bad = 0
    for name in sorted(set(a) | set(b)):
        ra, rb = a.get(name), b.get(name)
        if ra == rb:
            continue
        bad += 1
        if ra is None or rb is None:
            print(f"{name}: only in {'b' if ra is None else 'a'}")
            continue
        diff = sorted(k for k in set(ra) | set(rb) if ra.get(k) != rb.get(k))
        print(f"{name}: {len(diff)} differ: {', '.join(diff[:12])}")
        for k in diff[:3]:
            with contextlib.suppress(Exception):
                print(f"    {k}: {str(ra.get(k))[:150]!s} | {str(rb.get(k))[:150]!s}")
    total = len(set(a) | set(b))
    print(f"{total} scenes compared, {bad} differ")
    return 1 if bad else 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="cmd", required=True)
    rec = sub.add_parser("record")
    rec.add_argument("--out", required=True)
    rec.add_argument("--scenes", type=int, default=600)
    rec.add_argument("--sweeps", type=int, default=40)
    rec.add_argument("--seed", type=int, default=33)
    rec.add_argument("--time-limit", type=int, default=120)
    rec.add_argument("--no-examples", action="store_true")
    rec.add_argument("-v", "--verbose", action="store_true")
    cmp_ = sub.add_parser("compare")
    cmp_.add_argument("a")
    cmp_.add_argument("b")
    args = parser.parse_args(argv)
    return record(args) if args.cmd == "record" else compare(args)


if __name__ == "__main__":
    raise SystemExit(main())
