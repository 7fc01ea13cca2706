"""The paths of ``benchmarks/summary.py``: each against its kernel on the same curves.

A design path is ``fn(spec, rounds, quick) -> {"time", "kernel", "ratio", ...}`` (CPU seconds
per call, best of interleaved rounds of repeated calls: :func:`timed`) on one spectrum of the
design (:mod:`summary_design`).
"""

from __future__ import annotations

import copy
import ctypes
import os
import shutil
import subprocess
import sys
import tempfile
import warnings
from pathlib import Path

import numpy as np
from summary_cold import sweep_eh_cold
from summary_design import cpu, load_range, peak_mib, scene, timed
from summary_parallel import PLASTIC, STEEL, parallel_path

import xpersson

#: Target per path: ("x", ratio) or ("ms", milliseconds per load).
TARGETS = {
    "sweep E x H, 1 load": ("x", 5),
    "sweep E x H x 10 loads": ("x", 5),
    "sweep E x H, 1 load, cold": ("x", 5),
    "many loads (1e4) vs erf kernel": ("x", 10),
    "gap_pdf, 100 loads": ("x", 10),
    "gap_pdf, 1000 loads": ("x", 10),
    "gap_pdf, 1e4 loads": ("x", 10),
    "leakage, 100 loads": ("x", 10),
    "leakage, 1000 loads": ("x", 10),
    "leakage, 1e4 loads": ("x", 10),
    "1000 load strings vs range": ("x", 1.5),
    "jkr, one load vs C march": ("ms", 5),
    "plastic_scale_dependent vs C march": ("ms", 20),
    "jkr, one load: engine alone vs C march": ("ms", 5),
    "engine (jkr) vs C march, rtol 1e-6": ("x", 3),
    "engine alone (jkr) vs C march, rtol 1e-6": ("x", 3),
    "engine (jkr) vs C march, rtol 1e-8": ("x", 3),
    "engine alone (jkr) vs C march, rtol 1e-8": ("x", 3),
    "friction curve, 50 speeds vs kernel": ("x", 5),
    "LocalCluster(2) wall vs serial wall": ("x", 1),
    "LocalCluster(2) wall vs serial wall, above the threshold": ("x", 1),
    "E x H x p0 study: peak memory / result": ("x", 2),
}
JKR_MATERIAL = {"E": "1 MPa", "nu": 0.5}
JKR = {"model": "jkr", "work_of_adhesion": "0.05 J/m**2"}


def _ratio(t: float, k: float, **extra: object) -> dict:
    return {"time": t, "kernel": k, "ratio": t / k, **extra}


def _h_range(H: float, n: int) -> dict:
    lo, hi = max(0.3, H - 0.05), min(0.95, H + 0.05)
    return {"start": lo, "stop": hi, "num": n, "spacing": "linear"}


def _eh(spec: dict, n: int, loads: object) -> dict:
    sc = scene(spec, loads)
    sc["spectrum"]["H"] = _h_range(spec["H"], n)
    sc["material"]["E"] = {"start": "1 MPa", "stop": "100 MPa", "num": n}
    return sc


def sweep_eh(spec: dict, rounds: int, quick: bool) -> dict:
    """E x H sweep, one load per point, against the same number of plain loads (a range)."""
    n = 30 if quick else 100
    sweep, plain = _eh(spec, n, "100 kPa"), scene(spec, load_range(n * n))
    t = timed({"s": lambda: xpersson.solve(sweep), "k": lambda: xpersson.solve(plain)}, rounds)
    return _ratio(t["s"], t["k"], note=f"({n * n / t['s'] * 60:.2g} curves/min/core)")


def sweep_ehp(spec: dict, rounds: int, quick: bool) -> dict:
    """E x H x 10 loads against the same number of plain loads."""
    n = 10 if quick else 30
    sweep, plain = _eh(spec, n, load_range(10)), scene(spec, load_range(n * n * 10))
    t = timed({"s": lambda: xpersson.solve(sweep), "k": lambda: xpersson.solve(plain)}, rounds)
    return _ratio(t["s"], t["k"], note=f"({n * n * 10 / t['s'] * 60:.2g} curves/min/core)")


def many_loads(spec: dict, rounds: int, quick: bool) -> dict:
    """1e4 loads through ``xpersson.solve`` against ``erf(p0 / (2 sqrt(tau)))`` on its grid."""
    from scipy.special import erf

    from xpersson.plugins import SceneContext

    sc = scene(spec, load_range(10_000))
    rs = xpersson.Scene(sc).resolve()
    ctx = SceneContext(
        psd=rs.psd, E=rs.E, nu=rs.nu, E_star=rs.E_star, p0=rs.p0, zeta=rs.zeta, rtol=rs.rtol,
        atol=rs.atol,
    )  # fmt: skip
    tau = np.asarray(rs.coefficient.tau(ctx, rs.zeta))
    p0 = rs.p0

    def kernel() -> None:
        with np.errstate(divide="ignore"):
            erf(p0[:, None] / (2.0 * np.sqrt(tau[None, :])))

    t = timed({"s": lambda: xpersson.solve(sc), "k": kernel}, rounds)
    return _ratio(t["s"], t["k"])


def _analysis(name: str, n: int):
    def path(spec: dict, rounds: int, quick: bool) -> dict:
        if quick and n > 1000:
            n_ = 3000
        else:
            n_ = n
        bare = scene(spec, load_range(n_))
        with_analysis = scene(spec, load_range(n_), analyses={name: {}})
        t = timed(
            {"s": lambda: xpersson.solve(with_analysis), "k": lambda: xpersson.solve(bare)},
            rounds,
        )
        return _ratio(t["s"], t["k"])

    return path


def load_strings(spec: dict, rounds: int, quick: bool) -> dict:
    """1000 loads as a list of strings against the same loads as a range table (each timed over
    ~20 ms of repeated solves). The headline is the list's first solve (the list cache cleared
    before each solve: what a user passing a fresh list pays); the note gives a repeated solve
    of the same list (its numbers read from the list cache)."""
    import xpersson.units  # noqa: F401 - the list cache is made on import
    from xpersson.cache import cache

    grid = np.geomspace(1e3, 1e6, 1000)
    listed = scene(spec, [f"{float(p)!r} Pa" for p in grid])
    ranged = scene(spec, load_range(1000))
    lists = cache("units.string_lists")

    def cold() -> None:
        lists.clear()
        xpersson.solve(listed)

    fns = {"s": lambda: xpersson.solve(listed), "k": lambda: xpersson.solve(ranged), "c": cold}
    t = timed(fns, rounds)  # ~3 ms calls: ~20 ms per timing
    return _ratio(t["c"], t["k"], note=f"(same list solved again: {t['s'] / t['k']:.2f}x)")


def one_load(spec: dict, rounds: int, quick: bool) -> dict:
    """One load (closed form: one absorbing wall) through ``xpersson.solve`` against its
    kernel on the same curve: ``tau(zeta)`` of the scene's coefficient and
    ``erf(p0 / (2 sqrt(tau)))`` (the pipeline's fixed cost per solve); the kernel runs with the
    caches off, so that a cached spectral integral does not make it look cheaper than the
    work a first solve does."""
    from scipy.special import erf

    from xpersson.plugins import SceneContext

    sc = scene(spec, "100 kPa")
    rs = xpersson.Scene(sc).resolve()
    ctx = SceneContext(
        psd=rs.psd, E=rs.E, nu=rs.nu, E_star=rs.E_star, p0=rs.p0, zeta=rs.zeta, rtol=rs.rtol,
        atol=rs.atol,
    )  # fmt: skip

    def kernel() -> None:  # caches off: the kernel computes tau's spectral integral each time
        with xpersson.set_options(cache=False):
            tau = np.asarray(rs.coefficient.tau(ctx, rs.zeta))
        with np.errstate(divide="ignore"):
            erf(rs.p0[:, None] / (2.0 * np.sqrt(tau[None, :])))

    t = timed({"s": lambda: xpersson.solve(sc), "k": kernel}, rounds)
    return _ratio(t["s"], t["k"], note=f"({t['s'] * 1e3:.2f} ms per solve)")


DESIGN_PATHS = {
    "sweep E x H, 1 load": sweep_eh,
    "sweep E x H x 10 loads": sweep_ehp,
    "sweep E x H, 1 load, cold": sweep_eh_cold,
    "many loads (1e4) vs erf kernel": many_loads,
    **{
        f"{a}, {label} loads": _analysis(a, n)
        for a in ("gap_pdf", "leakage")
        for n, label in ((100, "100"), (1000, "1000"), (10_000, "1e4"))
    },
    "1000 load strings vs range": load_strings,
    "one closed-form load vs its kernel": one_load,
}


# --- the engine's limit and peer, friction, parallel -------------------------------------------


def c_march_lib(peers: Path):
    """The C march of ``peers/c_march/thomas.c`` built with ``$CC`` (``None``: no compiler)."""
    cc = os.environ.get("CC", "cc")
    if shutil.which(cc) is None or not (peers / "c_march" / "thomas.c").is_file():
        print(f"C march: skip (no compiler {cc!r} or no {peers}/c_march/thomas.c)")
        return None
    out = Path(tempfile.mkdtemp(prefix="c_march_")) / "libthomas.so"
    cmd = [cc, "-O2", "-shared", "-fPIC", str(peers / "c_march" / "thomas.c"), "-o", str(out)]
    if subprocess.run(cmd, capture_output=True, check=False).returncode != 0:
        print(f"C march: skip ({cc} failed)")
        return None
    sys.path.insert(0, str(peers / "c_march"))
    lib = ctypes.CDLL(str(out))
    dp = ctypes.POINTER(ctypes.c_double)
    lib.march.argtypes = [ctypes.c_int, ctypes.c_int, dp, dp]
    return lib


def _vs_march(lib, sc: dict, loads: int, rounds: int, how: str) -> tuple[dict, dict]:
    """``xpersson.solve(sc)`` and the engine's own call on the problem the pipeline prepared
    (:func:`cn_walls.engine_call_of`) against the C march over the grid levels the engine
    marched; ``how`` names the march in force (compiled or numpy). A scene on which the engine
    marches no level has no C counterpart: both entries then hold the times and why
    (:func:`_no_march`), and no ratio (the rows' worst and median are over marching scenes)."""
    from cn_walls import engine_call_of, levels_of  # the project's spies on the engine
    from march_vs_engine import c_march

    levels = levels_of(sc)
    engine = engine_call_of(sc)
    fns = {"s": lambda: xpersson.solve(sc), "e": engine}
    if levels:
        fns["k"] = lambda: c_march(lib, levels)
    t = timed(fns, rounds)
    if not levels:
        why = _no_march(engine())
        ms = {key: t[key] / loads * 1e3 for key in ("s", "e")}
        s, e = (
            {
                "no_march": why,
                "time": t[k],
                "per_load_ms": ms[k],
                "note": f"({ms[k]:.2f} ms/load; {why})",
            }
            for k in ("s", "e")
        )
        return s, e
    out = []
    steps = sum(a * b * c for a, b, c in levels)
    for key in ("s", "e"):
        ms = t[key] / loads * 1e3
        note = f"({ms:.1f} ms/load, {steps:.2g} node-steps, {how} march)"
        out.append(_ratio(t[key], t["k"], per_load_ms=ms, note=note))
    return out[0], out[1]


def _no_march(res) -> str:
    """Why the engine's result ``res`` (an ``EngineBatch``) marched no ``cn`` level."""
    method, message = str(res.method[0]), str(res.message[0])
    if method == "cn" and "analytic start covers every output" in message:
        # the wall never comes within k sqrt(2 tau) of the load up to the last output
        return "cn, no level: the wall stays outside the window, the analytic start is exact"
    return f"method {method!r}, no cn level: {message[:60]}"


def _march_cases(spec: dict) -> dict[str, tuple[dict, int, str | None]]:
    """name -> (scene, loads, name of its engine-alone row or None) on one design spectrum."""
    jkr = scene(spec, "1000 Pa", boundary=JKR)
    jkr["material"] = dict(JKR_MATERIAL)
    plastic = scene(spec, ["5 MPa", "20 MPa", "100 MPa"], boundary=PLASTIC)
    plastic["material"] = dict(STEEL)
    cases = {
        "jkr, one load vs C march": (jkr, 1, "jkr, one load: engine alone vs C march"),
        "plastic_scale_dependent vs C march": (plastic, 3, None),
    }
    for rtol in ("1e-6", "1e-8"):  # the engine's cn march (as the peer's jkr scene)
        tight = copy.deepcopy(jkr)
        tight["solver"] = {"rtol": float(rtol), "method": "cn"}
        tight["output"] = {"zeta_per_decade": 4}
        alone = f"engine alone (jkr) vs C march, rtol {rtol}"
        cases[f"engine (jkr) vs C march, rtol {rtol}"] = (tight, 1, alone)
    return cases


def march_paths(lib, scenes, rounds: int, quick: bool) -> dict:
    """jkr (one load), plastic_scale_dependent (3 loads), jkr at rtol 1e-6 / 1e-8 vs C: through
    ``xpersson.solve`` and (jkr) the engine's own call alone, both with the compiled march in
    force (built here when numba is present: the rows measure the engine near its limit, not
    the numpy march a short process would run before the compiled one pays)."""
    from xpersson.engine import _compiled

    how = "compiled" if _compiled.build() else "numpy (no numba)"
    out: dict[str, dict] = {k: {} for k in TARGETS if "C march" in k}
    for label, spec in scenes[: 4 if quick else len(scenes)]:
        for name, (sc, loads, alone) in _march_cases(spec).items():
            try:
                res, res_alone = _vs_march(lib, sc, loads, rounds, how)
                out[name][label] = res
                if alone is not None:
                    out[alone][label] = res_alone
            except Exception as exc:  # noqa: BLE001 - reported in the table
                out[name][label] = {"error": f"{type(exc).__name__}: {str(exc)[:160]}"}
                if alone is not None:
                    out[alone][label] = out[name][label]
            print(f"{label:22s} {name:34s} {out[name][label].get('note', out[name][label])}")
            if alone is not None:
                print(f"{label:22s} {alone:34s} {out[alone][label].get('note', '')}", flush=True)
    return out


def friction_path(rounds: int) -> dict:
    """One friction curve (50 speeds, one temperature, one load) through ``xpersson.solve``
    against ``friction_curve`` on the same curve (the viscoelastic plugin's example): the
    kernel given the scene's output magnifications, so that it returns what the Dataset holds
    for friction (``mu_visc_cumulative`` on the output grid, not ``mu_visc`` at ``zeta_max``
    alone); the note gives the ratio to the curve-only kernel too."""
    from viscoelastic_friction import NU, SHIFT, V, _psd

    from xpersson_viscoelastic import friction_curve, synthetic_tread

    example = Path(__file__).resolve().parent.parent / "plugins/xpersson-viscoelastic/examples"
    kw = {
        "coefficient__velocity": [f"{float(x)!r} m/s" for x in V],
        "coefficient__temperature": "293.15 K",
        "load__p0": "300000.0 Pa",
    }
    psd, model, aT = _psd(), synthetic_tread(), SHIFT.aT(np.array([293.15]))
    path = str(example / "tread_on_asphalt.toml")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        zeta = np.asarray(xpersson.solve(path, **kw)["zeta"].values)  # the scene's output grid
    t = timed(
        {
            "s": lambda: xpersson.solve(path, **kw),
            "k": lambda: friction_curve(psd, model, NU, [3e5], V, aT, zeta=zeta),
            "c": lambda: friction_curve(psd, model, NU, [3e5], V, aT),
        },
        rounds,
    )
    note = f"(mu_visc_cumulative at {zeta.size} magnifications; curve-only kernel: "
    note += f"{t['s'] / t['c']:.1f}x)"
    return {
        "friction curve, 50 speeds vs kernel": {
            "tread_on_asphalt": _ratio(t["s"], t["k"], note=note)
        }
    }


def peer_path(peers: Path, scenes, rounds: int, quick: bool) -> dict:
    """The engine (cn, rtol 1e-6) against a two-grid scipy BDF method of lines (sparse exact
    Jacobian, N and 2N-1 nodes, Richardson-extrapolated curve) on the peers' scene at the
    design's H values; ratio = peer time / engine time (higher: the engine faster)."""
    if not (peers / "peer_scipy_mol.py").is_file():
        return {}
    sys.path.insert(0, str(peers))
    import peer_scipy_mol
    import scene as S

    from xpersson.engine import Wall, solve

    out = {}
    hs = sorted({round(s["H"], 2) for _, s in scenes})[:: 3 if quick else 1]
    for H in hs:
        sc = S.make_scene("realistic", H=H)
        tau = sc.tau(sc.zeta_out())

        def engine(sc=sc, tau=tau):
            return solve(tau, sc.p_bar, Wall.absorbing(0.0), None, method="cn", rtol=1e-6)

        def peer(sc=sc):
            coarse = peer_scipy_mol.solve(sc, 513, "BDF", 1e-7)[3]
            fine = peer_scipy_mol.solve(sc, 1025, "BDF", 1e-7)[3]
            return (4 * fine - coarse) / 3

        t = timed({"e": engine, "p": peer}, max(1, rounds - 1))
        err_e, err_p = S.curve_error(sc, engine().area), S.curve_error(sc, peer())
        out[f"H={H:.2f}"] = {
            "time": t["p"],
            "kernel": t["e"],
            "ratio": t["p"] / t["e"],
            "note": f"(curve error: engine {err_e:.1e}, peer {err_p:.1e})",
        }
        print(f"BDF peer H={H:.2f}: {out[f'H={H:.2f}']}", flush=True)
    return {"BDF two-grid peer / engine (cn, rtol 1e-6)": out}


def study_memory(scenes, quick: bool) -> dict:
    """The issue's E x H x p0 study (20 E x 100 H x 50 loads = 1e5 curves; --quick: 2e4) on
    the worst sweep scene: peak traced memory over the result's size (ratio), CPU time."""
    out = {}
    for label, spec in scenes[:2]:
        sc = _eh(spec, 1, load_range(50))
        sc["material"]["E"] = {"start": "1 MPa", "stop": "100 MPa", "num": 20}
        sc["spectrum"]["H"] = _h_range(spec["H"], 20 if quick else 100)
        t = cpu(lambda sc=sc: xpersson.solve(sc))
        size = xpersson.solve(sc).nbytes / 2**20
        peak = peak_mib(lambda sc=sc: xpersson.solve(sc))
        curves = 20 * (20 if quick else 100) * 50
        note = f"({peak:.0f} MiB peak for {size:.0f} MiB; {curves / t * 60:.2g} curves/min/core)"
        out[label] = {"time": peak, "kernel": size, "ratio": peak / size, "note": note}
        out[label]["unit"] = "MiB"
        print(f"{label:22s} study memory {note}", flush=True)
    return {"E x H x p0 study: peak memory / result": out}


def single_paths(peers: Path, scenes, rounds: int, quick: bool) -> dict:
    out: dict[str, dict] = study_memory(scenes, quick)
    lib = c_march_lib(peers)
    if lib is not None:
        out.update(march_paths(lib, scenes, rounds, quick))
    try:
        out.update(friction_path(rounds))
    except ImportError as exc:
        out["friction curve, 50 speeds vs kernel"] = {"-": {"error": f"skip: {exc}"}}
    out.update(peer_path(peers, scenes, rounds, quick))
    return out


def memory(raw: dict, scenes, quick: bool) -> dict:
    """Peak traced memory [MiB] of the sweep paths on their worst scene, and the result size."""
    specs = dict(scenes)
    out = {}
    for name, build in (
        ("sweep E x H, 1 load", lambda s: _eh(s, 30 if quick else 100, "100 kPa")),
        ("sweep E x H x 10 loads", lambda s: _eh(s, 10 if quick else 30, load_range(10))),
    ):
        ok = {k: v for k, v in raw.get(name, {}).items() if "ratio" in v}
        if not ok:
            continue
        sc = build(specs[max(ok, key=lambda k: ok[k]["ratio"])])
        out[name] = peak_mib(lambda sc=sc: xpersson.solve(sc))
    return out


#: Rows outside the design that ``--paths`` may measure again: name -> fn(rounds).
AGAIN = {
    "friction curve, 50 speeds vs kernel": friction_path,
    "LocalCluster(2) wall vs serial wall": parallel_path,  # both LocalCluster rows
}

__all__ = ["AGAIN", "DESIGN_PATHS", "TARGETS", "cpu", "memory", "parallel_path", "single_paths"]
