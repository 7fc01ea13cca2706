"""Robustness campaign: random valid scenes over extreme ranges, every plugin installed.

Scenes span A/A0 from 1e-8 to 1 - 1e-12 (the load is set from the target area through the
Persson-01 closed form), magnifications zeta_max up to 1e9, Hurst exponents 0.05 .. 1, moduli
1e5 .. 1e12 Pa, every closure of the elastic coefficient, every installed boundary and a random
subset of every installed analysis (plugins the generator does not know get random parameters
inside their declared bounds). Each scene runs in a forked worker with a time limit; the counts:

* ``nan``: a non-finite value in a variable that does not declare ``NaN means`` (or any inf);
* ``out_of_range``: an area fraction outside [0, 1], negative P, or a value outside the
  variable's ``valid_min`` / ``valid_max``;
* ``dishonest``: status ``success`` although the result fails a check it should pass (the
  probability balance, the plastic force balance or the deviation from the exact two-wall
  series beyond 10x the requested tolerance, or the Persson-01 elastic area off the closed
  form ``erf(p0 / (2 sqrt(tau)))`` by more than 10x the requested tolerance);
* ``crash``: an exception other than a scene refusal (:class:`xpersson.SceneError`) or a caught
  plugin failure (:class:`xpersson.PluginFailure`, counted on its own);
* ``hang``: the time limit was exceeded (the worker is killed and replaced).

Run (not part of CI)::

    OPENBLAS_NUM_THREADS=1 python benchmarks/fuzz.py --scenes 10000 --workers 2 --out fuzz.json

Prints the counts and writes every finding (scene + message) to ``--out``.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import multiprocessing as mp
import os
import random
import sys
import tempfile
import time
import traceback
import warnings
from multiprocessing.connection import wait
from pathlib import Path
from typing import Any

CLOSURES = ("persson01", "yp08", "wm17", "xu24")
CATEGORIES = (
    "ok",
    "nan",
    "out_of_range",
    "dishonest",
    "crash",
    "hang",
    "plugin_failure",
    "refused",
    "not_success",
)


# -- scene generation --------------------------------------------------------------------------
def _logu(rng: random.Random, lo: float, hi: float) -> float:
    return 10 ** rng.uniform(math.log10(lo), math.log10(hi))


def _target_area(rng: random.Random) -> float:
    if rng.random() < 0.5:
        return _logu(rng, 1e-8, 0.5)
    return 1.0 - _logu(rng, 1e-12, 0.5)


def _random_param(rng: random.Random, spec: Any) -> Any:
    """A random value inside a ParamSpec's declaration, written as a scene value."""
    if spec.kind == "choice":
        return rng.choice(spec.choices)
    if spec.kind == "bool":
        return rng.random() < 0.5
    if spec.kind != "quantity":  # resolution settings (int) keep their defaults
        return None
    lo, hi = spec.bounds
    base = spec.sample
    if base is None or base is REQUIRED:
        base = 1.0 if lo is None else (lo + 1.0 if hi is None else 0.5 * (lo + hi))
    value = float(base)
    if lo is not None and hi is not None and lo > 0:
        value = _logu(rng, lo, hi) if hi / lo > 10 else rng.uniform(lo, hi)
    elif lo is not None and hi is not None:
        value = rng.uniform(lo, hi)
    elif value > 0:
        value = value * _logu(rng, 0.1, 10)
    if not spec.in_bounds(value):
        value = float(base)
    return value if spec.unit in ("1", "") else f"{value!r} {spec.unit}"


def make_scene(
    index: int,
    seed: int,
    registry: Any,
    tmpdir: str,
    bodies: float = 0.0,
    sweeps: float = 0.0,
    methods: float = 0.0,
) -> dict[str, Any]:
    """The ``index``-th scene of a campaign (deterministic in ``seed``); with ``bodies`` > 0
    that fraction of the scenes a finite body (:func:`_as_body`), with ``sweeps`` > 0 that
    fraction a sweep (:func:`_as_sweep`), with ``methods`` > 0 that fraction asks for an
    engine method (:data:`METHODS`) and half of those an ``atol``, each drawn from a generator
    of its own: the other scenes are those of ``bodies = sweeps = methods = 0``."""
    from xpersson.builtin.spectra import SelfAffine
    from xpersson.physics import elastic

    rng = random.Random(seed * 1_000_003 + index)
    H = rng.uniform(0.05, 1.0)
    q_L = _logu(rng, 1e1, 1e6)
    zeta_max = _logu(rng, 2.0, 1e9)
    q_1 = q_L * zeta_max
    q_r = q_L if rng.random() < 0.5 else q_L * _logu(rng, 1.0, min(100.0, zeta_max**0.5))
    amp = (
        ("rms_slope", _logu(rng, 1e-2, 5.0))
        if rng.random() < 0.6
        else ("h_rms", _logu(rng, 1e-9, 1e-4))
    )
    E = _logu(rng, 1e5, 1e12)
    nu = rng.uniform(0.0, 0.5)
    spectrum = {
        "model": "self_affine",
        "H": H,
        "q_L": f"{q_L!r} 1/m",
        "q_r": f"{q_r!r} 1/m",
        "q_1": f"{q_1!r} 1/m",
        amp[0]: amp[1] if amp[0] == "rms_slope" else f"{amp[1]!r} m",
    }
    psd = SelfAffine(
        H=H,
        q_L=q_L,
        q_r=q_r,
        q_1=q_1,
        **{"h_rms": None, "rms_slope": None, "C_r": None, amp[0]: amp[1]},
    ).build()
    e_star = E / (1 - nu**2)
    tau = float(elastic.diffusion_time(psd, e_star, [zeta_max])[-1])
    n_loads = rng.choice((1, 1, 2, 3))
    areas = sorted(_target_area(rng) for _ in range(n_loads))
    from scipy.special import erfinv

    loads = sorted({min(2.0 * math.sqrt(tau) * float(erfinv(a)), 1e12) for a in areas})
    loads = [p for p in loads if p > 0] or [1e3]
    if rng.random() < 0.1:  # the same spectrum as a table file
        path = Path(tmpdir) / f"psd_{index}.txt"
        import numpy as np

        q = np.geomspace(q_L, q_1, rng.randint(3, 60))
        path.write_text("q C\n" + "".join(f"{float(a)!r} {float(psd.C(a))!r}\n" for a in q))
        spectrum = {"model": "tabulated", "file": str(path)}
    scene: dict[str, Any] = {
        "spectrum": spectrum,
        "material": {"E": f"{E!r} Pa", "nu": nu},
        "load": {"p0": [f"{p!r} Pa" for p in loads] if len(loads) > 1 else f"{loads[0]!r} Pa"},
        "output": {"zeta_per_decade": rng.randint(2, 20)},
        "solver": {"rtol": _logu(rng, 1e-8, 1e-3)},
    }
    if rng.random() < 0.1:
        scene["output"].update(pressure_pdf=True, p_points=rng.randint(16, 512))
    boundaries = registry.names("boundaries")
    boundary = rng.choice(boundaries)
    p_max = max(loads)
    others = [c for c in registry.names("coefficients") if c != "elastic"]
    if others and rng.random() < 0.25:
        scene["coefficient"] = _coefficient(rng, registry, rng.choice(others))
    if boundary == "elastic":
        if "coefficient" not in scene:
            closure = rng.choice(CLOSURES)
            scene["coefficient"] = {"model": "elastic", "closure": closure}
            if closure != "persson01" and rng.random() < 0.5:
                scene["coefficient"]["gamma"] = rng.uniform(0.05, 1.0)
        scene["boundary"] = {"model": "elastic"}
    elif boundary == "plastic":
        scene["boundary"] = {
            "model": "plastic",
            "sigma_Y": f"{min(p_max * _logu(rng, 1.01, 1e3), 1e13)!r} Pa",
        }
    elif boundary == "plastic_scale_dependent":
        scene["boundary"] = {
            "model": boundary,
            "Y1": f"{min(p_max * _logu(rng, 1.01, 1e3), 1e13)!r} Pa",
            "n": rng.uniform(0.0, 1.0),
        }
    else:
        cls = registry.load("boundaries", boundary)
        params = {k: _random_param(rng, s) for k, s in cls.parameters.items()}
        scene["boundary"] = {
            "model": boundary,
            **{k: v for k, v in params.items() if v is not None},
        }
    analyses = registry.names("analyses")
    if scene.get("coefficient", {}).get("model") != "viscoelastic":
        analyses = [a for a in analyses if a != "friction"]  # needs the viscoelastic loss
    chosen = rng.sample(analyses, rng.randint(0, min(3, len(analyses))))
    scene["analyses"] = {}
    for name in chosen:
        cls = registry.load("analyses", name)
        params = {
            k: _random_param(rng, s)
            for k, s in cls.parameters.items()
            if rng.random() < 0.3 and not s.required
        }
        scene["analyses"][name] = {k: v for k, v in params.items() if v is not None}
    method_rng = random.Random(seed * 11_000_027 + index + 3)
    if methods > 0.0 and method_rng.random() < methods:
        scene["solver"]["method"] = method_rng.choice(METHODS)
        if method_rng.random() < 0.5:
            scene["solver"]["atol"] = _logu(method_rng, 1e-14, 1e-6)
    body_rng = random.Random(seed * 7_000_003 + index + 1)
    if bodies > 0.0 and body_rng.random() < bodies:
        scene = _as_body(body_rng, scene, registry, loads)
    sweep_rng = random.Random(seed * 9_000_011 + index + 2)
    if sweeps > 0.0 and sweep_rng.random() < sweeps:
        scene = _as_sweep(sweep_rng, scene)
    return scene


#: The engine methods ``--methods`` asks for (``auto``'s choice overridden; ``markov``, the
#: slow referee, left out): a method that cannot treat a scene's walls is refused before work.
METHODS = ("cn", "sine", "exact")

#: The parameters :func:`_as_sweep` sweeps (section, name).
SWEPT = (("material", "E"), ("material", "nu"), ("spectrum", "H"))


def _as_sweep(rng: random.Random, scene: dict[str, Any]) -> dict[str, Any]:
    """``scene`` with one or two of :data:`SWEPT` given two values each (``E`` and 3 ``E``;
    ``nu`` and ``nu`` + 0.1; ``H`` and ``H`` + 0.1, inside their bounds), in an outer product
    or zipped: its loads stay, so a sweep point has 1-3 loads."""
    out = {k: (dict(v) if isinstance(v, dict) else v) for k, v in scene.items()}
    names = [(sec, key) for sec, key in SWEPT if key in out.get(sec, {})]
    picked = rng.sample(names, min(len(names), rng.choice((1, 1, 2))))
    for sec, key in picked:
        value = out[sec][key]
        if key == "E":
            number = float(str(value).split()[0])
            out[sec][key] = [value, f"{3.0 * number!r} Pa"]
        else:
            x = float(value)
            other = x + 0.1 if x + 0.1 <= (0.5 if key == "nu" else 1.0) else x - 0.1
            out[sec][key] = [x, other]
    if len(picked) == 2 and rng.random() < 0.3:
        out["sweep"] = {"mode": "zip"}
    return out


def swept(scene: dict[str, Any]) -> bool:
    """Whether ``scene`` sweeps one of :data:`SWEPT` (a list where one value stands)."""
    return any(isinstance(scene.get(sec, {}).get(key), list) for sec, key in SWEPT)


def _as_body(
    rng: random.Random, scene: dict[str, Any], registry: Any, loads: list[float]
) -> dict[str, Any]:
    """``scene`` under a random installed geometry: radius 10 um - 1 m (other lengths 0.5-10
    radii), each generated pressure [Pa] made a force [N] over a contact 1e-4 - 0.3 radii
    wide; 80 % of them on the elastic boundary (a body couples to it alone: the others are
    refused)."""
    names = registry.names("geometries")
    if not names:
        return scene
    name = rng.choice(names)
    cls = registry.load("geometries", name)
    radius = _logu(rng, 1e-5, 1.0)
    geometry: dict[str, Any] = {"model": name}
    for key, spec in cls.parameters.items():
        if spec.unit == "m":
            size = radius if key == "radius" else radius * _logu(rng, 0.5, 10.0)
            geometry[key] = f"{size!r} m"
        elif (value := _random_param(rng, spec)) is not None:
            geometry[key] = value
    width = radius * _logu(rng, 1e-4, 0.3)
    forces = [f"{p * math.pi * width**2!r} N" for p in loads]
    load = {"force": forces if len(forces) > 1 else forces[0]}
    out = {**scene, "geometry": geometry, "load": load}
    if rng.random() < 0.8:
        out["boundary"] = {"model": "elastic"}
    return out


def _coefficient(rng: random.Random, registry: Any, name: str) -> dict[str, Any]:
    """Parameters of a coefficient other than the elastic one."""
    if name == "viscoelastic":
        E_r = _logu(rng, 1e5, 1e7)
        out: dict[str, Any] = {
            "model": name,
            "velocity": f"{_logu(rng, 1e-8, 1e2)!r} m/s",
            "temperature": f"{rng.uniform(250.0, 400.0)!r} K",
            "modulus": rng.choice(("sls", "prony")),
            "E_r": f"{E_r!r} Pa",
            "E_g": f"{E_r * _logu(rng, 10.0, 1e4)!r} Pa",
            "relaxation_time": f"{_logu(rng, 1e-6, 1.0)!r} s",
        }
        if rng.random() < 0.5:
            out.update(shift="wlf", T_ref=f"{rng.uniform(200.0, 300.0)!r} K")
        return out
    cls = registry.load("coefficients", name)
    params = {k: _random_param(rng, s) for k, s in cls.parameters.items()}
    return {"model": name, **{k: v for k, v in params.items() if v is not None}}


# -- checking one result -----------------------------------------------------------------------
def _variable_findings(ds: Any, findings: dict[str, list[str]]) -> None:
    """NaN/inf and out-of-range values of every float variable."""
    import numpy as np

    for name, var in ds.variables.items():
        if var.dtype.kind != "f":
            continue
        a = np.asarray(var.values)
        nan_ok = "NaN means" in str(var.attrs.get("comment", ""))
        if np.isinf(a).any() or (np.isnan(a).any() and not nan_ok):
            findings["nan"].append(f"{name}: {int((~np.isfinite(a)).sum())} non-finite")
        fin = a[np.isfinite(a)]
        lo, hi = var.attrs.get("valid_min"), var.attrs.get("valid_max")
        if lo is not None and (fin < lo).any():
            findings["out_of_range"].append(f"{name} < valid_min {lo}: {fin.min()!r}")
        if hi is not None and (fin > hi).any():
            findings["out_of_range"].append(f"{name} > valid_max {hi}: {fin.max()!r}")
        if (
            name.endswith("fraction")
            and var.attrs.get("units") == "1"
            and fin.size
            and (fin.min() < -1e-12 or fin.max() > 1 + 1e-12)
        ):
            findings["out_of_range"].append(
                f"{name} outside [0, 1]: {fin.min()!r} .. {fin.max()!r}"
            )
        if name == "P" and fin.size and fin.min() < -1e-12 * max(1.0, float(np.abs(fin).max())):
            findings["out_of_range"].append(f"P negative: {fin.min()!r}")


def _balance_findings(ds: Any, rtol: float, atol: float, findings: dict[str, list[str]]) -> None:
    """A success whose own balances exceed ten times the tolerance is dishonest.

    The engine meets ``|error of A| <= rtol A + atol``: the plastic force balance, relative to
    ``p0`` and carried by the contact area ``A`` (``total_contact_fraction``), may then be off
    by ``(rtol A + atol) / A`` (at ``A = 1.5e-7`` and the default ``atol = 1e-12``: 7e-6, far
    above ``rtol``), so its tolerance is ten times that.
    """
    import numpy as np

    pb = np.abs(np.asarray(ds["probability_balance"].values)) if "probability_balance" in ds else 0
    if np.nanmax(pb) > 10 * (rtol + atol) + 1e-9:  # (the engine's own check: atol counts)
        findings["dishonest"].append(
            f"probability_balance {np.nanmax(pb):.3g} with status success (rtol {rtol:g})"
        )
    for name in ("plastic_force_balance_residual", "exact_series_deviation"):
        if name in ds:
            res = abs(ds[name])
            allow = 10 * rtol + 1e-9
            if name == "plastic_force_balance_residual" and "total_contact_fraction" in ds:
                area = ds["total_contact_fraction"]  # (broadcast by dimension name)
                allow = allow + 10 * atol / area.where(area > 1e-300, 1e-300)
            dev = float(np.nanmax(np.asarray(res.values)))
            if bool((res > allow).any()):
                findings["dishonest"].append(
                    f"{name} {dev:.3g} with status success (rtol {rtol:g})"
                )


def _closed_form_findings(
    ds: Any, scene: dict[str, Any], rtol: float, findings: dict[str, list[str]]
) -> None:
    """Elastic Persson-01 scenes: A/A0 against erf(p0 / 2 sqrt(tau)) within ten times rtol."""
    import numpy as np
    from scipy.special import erf, erfc

    tau = np.asarray(ds["diffusion_time"].values)
    area = ds["area_fraction"].transpose(..., "zeta").values.reshape(-1, tau.size)
    non = ds["non_contact_fraction"].transpose(..., "zeta").values.reshape(-1, tau.size)
    p0 = np.atleast_1d(ds["p0"].values)[:, None]
    with np.errstate(divide="ignore"):
        x = np.where(tau > 0, p0 / (2 * np.sqrt(np.maximum(tau, 1e-300))), np.inf)
    exact_a, exact_n = erf(x), erfc(x)
    tol = 10 * (rtol * exact_a + float(scene["solver"].get("atol", 1e-12))) + 1e-12
    err = np.minimum(np.abs(area - exact_a), np.abs(non - exact_n))
    # relative error of the small one of (A, 1 - A) where it matters
    bad = (np.abs(area - exact_a) > tol) & (np.abs(non - exact_n) > 10 * rtol * exact_n + 1e-300)
    if bad.any():
        findings["dishonest"].append(
            f"A/A0 off the Persson-01 closed form by up to "
            f"{float(err.max()):.3g} with status success"
        )


def check(ds: Any, scene: dict[str, Any]) -> tuple[str, str]:
    """Classify a solved Dataset: (category, message)."""
    findings: dict[str, list[str]] = {"nan": [], "out_of_range": [], "dishonest": []}
    _variable_findings(ds, findings)
    status = ds.attrs.get("status")
    rtol = float(scene["solver"]["rtol"])
    if status == "success":
        _balance_findings(ds, rtol, float(scene["solver"].get("atol", 1e-12)), findings)
        coef = scene.get("coefficient", {})
        # (a body's p0 is the grid of pressures it samples; a sweep's tau has its dimensions)
        plain = "geometry" not in scene and not swept(scene)
        if plain and scene["boundary"]["model"] == "elastic" and coef.get("closure") == "persson01":
            _closed_form_findings(ds, scene, rtol, findings)
    for cat in ("nan", "out_of_range", "dishonest"):
        if findings[cat]:
            return cat, "; ".join(findings[cat][:3])
    if status != "success":
        return "not_success", f"{status}: {str(ds.attrs.get('status_message'))[:200]}"
    return "ok", ""


def run_one(scene: dict[str, Any]) -> tuple[str, str, float, list[str]]:
    import xpersson

    t0 = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            ds = xpersson.solve(scene)
        except xpersson.SceneError as exc:
            return "refused", str(exc)[:300], time.perf_counter() - t0, []
        except xpersson.PluginFailure as exc:
            return "plugin_failure", str(exc)[:300], time.perf_counter() - t0, []
        except Exception as exc:
            tb = traceback.format_exc().strip().splitlines()[-3:]
            return (
                "crash",
                f"{type(exc).__name__}: {exc}"[:300] + " | " + " / ".join(tb),
                time.perf_counter() - t0,
                [],
            )
    cat, msg = check(ds, scene)
    if cat in ("ok", "not_success") and swept(scene):
        cat, msg = _fast_path_check(ds, scene) or (cat, msg)
    if cat in ("ok", "not_success") and swept(scene) and PARALLEL["scheduler"]:
        cat, msg = _parallel_check(ds, scene, PARALLEL["scheduler"]) or (cat, msg)
    notes = sorted(
        {str(w.message)[:80] for w in caught if type(w.message).__name__ == "XperssonWarning"}
    )
    return cat, msg, time.perf_counter() - t0, notes


def _fast_path_check(ds: Any, scene: dict[str, Any]) -> tuple[str, str] | None:
    """A sweep solved again with ``fast_paths=False`` (every point on its own): every data
    variable within 1e-12 relative of the fast paths' (the README's claim), NaN where they
    have NaN; else ``("dishonest", message)``."""

    import xpersson

    with warnings.catch_warnings(), xpersson.set_options(fast_paths=False):
        warnings.simplefilter("ignore")
        plain = xpersson.solve(scene)
    bad = _differences(ds, plain, "the plain path", rtol=1e-12)
    if bad:
        return "dishonest", "fast path vs plain: " + "; ".join(bad[:3])
    return None


#: ``--parallel``: the scheduler a sweep is solved on again (None: not), set before forking.
PARALLEL: dict[str, str | None] = {"scheduler": None}


def _parallel_check(ds: Any, scene: dict[str, Any], scheduler: str) -> tuple[str, str] | None:
    """A sweep solved again on ``scheduler`` (one point a block: every block a task) and into
    a sweep folder: both equal to the serial Dataset bit for bit (the README's claim), else
    ``("dishonest", message)``."""

    import xpersson

    with warnings.catch_warnings(), tempfile.TemporaryDirectory() as tmp:
        warnings.simplefilter("ignore")
        runs = {
            scheduler: xpersson.solve(scene, scheduler=scheduler, chunk=1, workers=2),
            "folder": xpersson.solve(scene, output=Path(tmp) / "study"),
        }
        bad = [m for how, other in runs.items() for m in _differences(ds, other, how, rtol=0.0)]
    if bad:
        return "dishonest", "serial vs " + "; ".join(bad[:3])
    return None


def _differences(ds: Any, other: Any, how: str, rtol: float) -> list[str]:
    """One line per data variable of ``ds`` that ``other`` lacks or holds otherwise: floats
    within ``rtol`` relative (0: bit for bit), NaN where NaN; the others equal."""
    import numpy as np

    bad = []
    for name in ds.data_vars:
        if name not in other.data_vars:
            bad.append(f"{name}: not on {how}")
            continue
        x, y = np.asarray(ds[name].values), np.asarray(other[name].transpose(*ds[name].dims).values)
        if x.shape != y.shape:
            bad.append(f"{name}: shape {x.shape} vs {y.shape} on {how}")
        elif x.dtype.kind == "f":
            with np.errstate(invalid="ignore"):
                off = ~((x == y) | (np.isnan(x) & np.isnan(y)))
                off &= ~(np.abs(x - y) <= rtol * np.maximum(np.abs(x), np.abs(y)))
            if off.any():
                rel = np.abs(x - y)[off] / np.maximum(np.abs(x), np.abs(y))[off]
                bad.append(
                    f"{name}: {int(off.sum())} values off on {how}, up to {np.nanmax(rel):.3g} rel"
                )
        elif not np.array_equal(x, y):
            bad.append(f"{name}: differs on {how}")
    return bad


def _worker(conn: Any) -> None:
    import xpersson  # noqa: F401  - imported once per worker

    while True:
        item = conn.recv()
        if item is None:
            return
        conn.send(run_one(item))


def _preload(registry: Any) -> None:
    """Import everything before forking: every worker (also a replaced one) runs the same code."""
    import importlib

    for mod in (
        "xpersson.api",
        "xpersson.pipeline",
        "xpersson.scene",
        "xpersson.io",
        "xpersson.engine",
        "xpersson.checks",
        "xpersson.pipeline",
        "xpersson.plugins._analyses",
    ):
        with contextlib.suppress(ImportError):
            importlib.import_module(mod)
    for group in ("spectra", "coefficients", "boundaries", "analyses"):
        for name in registry.names(group):
            with contextlib.suppress(Exception):
                registry.load(group, name)


# -- the campaign ------------------------------------------------------------------------------
class _Slot:
    def __init__(self, ctx: Any) -> None:
        self.ctx = ctx
        self.start()

    def start(self) -> None:
        self.conn, child = self.ctx.Pipe()
        self.proc = self.ctx.Process(target=_worker, args=(child,), daemon=True)
        self.proc.start()
        self.job: tuple[int, dict[str, Any]] | None = None
        self.t0 = 0.0

    def submit(self, index: int, scene: dict[str, Any]) -> None:
        self.job = (index, scene)
        self.t0 = time.perf_counter()
        self.conn.send(scene)

    def kill(self) -> None:
        self.proc.kill()
        self.proc.join()
        self.start()


def _count_coverage(coverage: dict[str, int], scene: dict[str, Any]) -> None:
    """Count the plugins, closure and analyses a generated scene exercises."""
    tags = [
        f"{key}:{scene.get(key, {}).get('model', 'elastic')}" for key in ("boundary", "coefficient")
    ]
    tags.append(f"closure:{scene.get('coefficient', {}).get('closure', '-')}")
    tags += [f"analysis:{a}" for a in scene["analyses"]]
    if "geometry" in scene:
        tags.append(f"geometry:{scene['geometry']['model']}")
    tags += [f"swept:{sec}.{key}" for sec, key in SWEPT if isinstance(scene[sec].get(key), list)]
    for tag in tags:
        coverage[tag] = coverage.get(tag, 0) + 1


def _collect(slot: Any, ready: bool, limit: float, record: Any, notes: dict[str, int]) -> int:
    """Record a busy slot's result (or its hang past ``limit`` seconds); 1 if it finished."""
    assert slot.job is not None
    index, scene = slot.job
    if ready:
        try:
            cat, msg, dt, warn = slot.conn.recv()
        except EOFError:  # the worker died (e.g. out of memory)
            cat, msg, dt, warn = "crash", "worker died", 0.0, []
            slot.kill()
        for w in warn:
            key = w.split(":")[1].strip()[:40] if ":" in w else w[:40]
            notes[key] = notes.get(key, 0) + 1
        record(index, scene, cat, msg, dt)
        slot.job = None
        return 1
    if time.perf_counter() - slot.t0 > limit:
        record(index, scene, "hang", f"exceeded {limit:g} s", limit)
        slot.kill()
        return 1
    return 0


def campaign(
    n: int,
    seed: int,
    workers: int,
    limit: float,
    out: Path | None,
    budget: float | None,
    bodies: float = 0.0,
    sweeps: float = 0.0,
    methods: float = 0.0,
) -> dict[str, Any]:
    from xpersson.plugins import get_registry

    registry = get_registry()
    _preload(registry)
    ctx = mp.get_context("fork")
    counts = dict.fromkeys(CATEGORIES, 0)
    examples: dict[str, list[dict[str, Any]]] = {c: [] for c in CATEGORIES if c != "ok"}
    notes: dict[str, int] = {}
    times: list[float] = []
    coverage: dict[str, int] = {}
    t_start = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmpdir:
        slots = [_Slot(ctx) for _ in range(workers)]
        next_index = 0
        done = 0

        def record(index: int, scene: dict[str, Any], cat: str, msg: str, dt: float) -> None:
            counts[cat] += 1
            times.append(dt)
            if cat != "ok" and len(examples[cat]) < 20:
                examples[cat].append({"index": index, "message": msg, "scene": scene})

        while done < next_index or next_index < n:
            stop = budget is not None and time.perf_counter() - t_start > budget
            for slot in slots:
                if slot.job is None and next_index < n and not stop:
                    scene = make_scene(next_index, seed, registry, tmpdir, bodies, sweeps, methods)
                    _count_coverage(coverage, scene)
                    slot.submit(next_index, scene)
                    next_index += 1
            busy = [s for s in slots if s.job is not None]
            if not busy:
                break
            ready = wait([s.conn for s in busy], timeout=0.5)
            for slot in busy:
                done += _collect(slot, slot.conn in ready, limit, record, notes)
            if done and done % 500 == 0 and done != getattr(campaign, "_last", -1):
                campaign._last = done  # type: ignore[attr-defined]
                print(
                    f"  {done} scenes, {time.perf_counter() - t_start:.0f} s: {counts}",
                    file=sys.stderr,
                    flush=True,
                )
        for slot in slots:
            if slot.job is None:
                slot.conn.send(None)
            slot.proc.kill()
    summary = {
        "scenes_run": done,
        "scenes_requested": n,
        "seed": seed,
        "workers": workers,
        "time_limit_s": limit,
        "wall_time_s": round(time.perf_counter() - t_start, 1),
        "counts": counts,
        "median_scene_s": round(sorted(times)[len(times) // 2], 4) if times else None,
        "max_scene_s": round(max(times), 2) if times else None,
        "coverage": dict(sorted(coverage.items())),
        "warnings": dict(sorted(notes.items(), key=lambda kv: -kv[1])[:12]),
    }
    if out is not None:
        out.write_text(
            json.dumps({"summary": summary, "examples": examples}, indent=1, default=str)
        )
    return summary


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scenes", type=int, default=10_000)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--workers", type=int, default=max(1, (os.cpu_count() or 2) // 2))
    parser.add_argument("--time-limit", type=float, default=10.0, help="per scene [s]")
    parser.add_argument(
        "--budget",
        type=float,
        default=None,
        help="stop submitting new scenes after this many seconds",
    )
    parser.add_argument("--out", type=Path, default=None, help="JSON file for the findings")
    parser.add_argument(
        "--bodies",
        type=float,
        default=0.0,
        help="fraction of the scenes under a finite body (installed geometries; default 0: "
        "the scenes of the documented campaigns)",
    )
    parser.add_argument(
        "--parallel",
        default=None,
        help="a scheduler (e.g. threads) each sweep is solved on again, and into a folder: "
        "both must equal the serial Dataset bit for bit",
    )
    parser.add_argument(
        "--sweeps",
        type=float,
        default=0.0,
        help="fraction of the scenes made sweeps of E, nu or H (solved again with "
        "fast_paths=False and compared: the fast paths' claim)",
    )
    parser.add_argument(
        "--methods",
        type=float,
        default=0.0,
        help="fraction of the scenes that ask for an engine method (cn, sine, exact) instead "
        "of auto, half of them with an atol (1e-14 - 1e-6): the Persson-01 scenes are then "
        "the march's closed-form check",
    )
    args = parser.parse_args(argv)
    PARALLEL["scheduler"] = args.parallel
    summary = campaign(
        args.scenes,
        args.seed,
        args.workers,
        args.time_limit,
        args.out,
        args.budget,
        args.bodies,
        args.sweeps,
        args.methods,
    )
    print(json.dumps(summary, indent=1))
    bad = sum(summary["counts"][c] for c in ("nan", "out_of_range", "dishonest", "crash", "hang"))
    return 1 if bad else 0


REQUIRED: Any = None
if __name__ == "__main__":
    from xpersson.plugins import REQUIRED  # noqa: F811

    sys.exit(main())
