"""Moving walls through ``cn``: cost per load of ``jkr`` and of ``plastic_scale_dependent`` with
its yield wall reached, against a bare O(N) step of the same grids (issue 25, item 5).

Scenes
------
* ``jkr``: the adhesion plugin's scene of ``jkr_vs_peer.py`` (PDMS-like elastomer on rough
  glass, loads -2, 1, 10 kPa), rtol 1e-6 (the default): the three loads in one call, and each
  load alone (the worst of the three is shown).
* ``plastic``: steel on the rough surface of ``pipeline_cost.py`` with
  ``plastic_scale_dependent`` (Y1 = 3 GPa, n = 0.1), loads 5, 20, 100 MPa in one call: the
  yield wall is reached (the solve takes ``cn``).

The limit
---------
The "bare step" is the floor of the scheme on this machine: for every grid level the engine
solved (same number of unknowns, loads concatenated, same number of time steps), one explicit
tridiagonal product in flux form (numpy) and one LAPACK ``dgtsv`` solve (the Thomas sweep in
compiled code) per step, on constant arrays prepared beforehand: no operator assembly, no wall
bookkeeping, no control.  ``ratio`` = the path's CPU time / the bare steps of its levels, both
measured in the same process.

CPU time (``time.process_time``), ``OPENBLAS_NUM_THREADS=1``, best of ``--rounds`` interleaved
rounds (every configuration once per round, after a warm-up).  With ``--before REV`` the same
measurements run for the tree of git revision ``REV`` (exported to a temporary folder) and for
this tree in alternating child processes, so that both see the same machine load; the table
then has both.

:func:`levels_of` (the levels the engine marched) and :func:`engine_call_of` (the engine's own
call on the problem the pipeline prepared) are also the spies of ``summary.py``'s C-march rows.

Usage: ``python benchmarks/cn_walls.py [--rounds 5] [--before REV]``; writes
``benchmarks/results/cn_walls.md``.
"""

from __future__ import annotations

import os

os.environ["OPENBLAS_NUM_THREADS"] = "1"

import argparse  # noqa: E402
import copy  # noqa: E402
import json  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
SPECTRUM = {
    "model": "self_affine",
    "H": 0.8,
    "q_L": "1e3 1/m",
    "q_r": "1e4 1/m",
    "q_1": "1e8 1/m",
    "h_rms": "1 um",
}
PLASTIC = {
    "spectrum": SPECTRUM,
    "material": {"E": "210 GPa", "nu": 0.3},
    "load": {"p0": ["5 MPa", "20 MPa", "100 MPa"]},
    "boundary": {"model": "plastic_scale_dependent", "Y1": "3 GPa", "n": 0.1},
    "output": {"zeta_per_decade": 10},
}
JKR = {
    "spectrum": {
        "model": "self_affine",
        "H": 0.8,
        "q_L": "1e4 1/m",
        "q_r": "1e5 1/m",
        "q_1": "1e9 1/m",
        "h_rms": "1 um",
    },
    "material": {"E": "1 MPa", "nu": 0.5},
    "load": {"p0": ["-2000 Pa", "1000 Pa", "10000 Pa"]},
    "boundary": {"model": "jkr", "work_of_adhesion": "0.05 J/m**2"},
    "output": {"zeta_per_decade": 4},
}


def _single(scene: dict, i: int) -> dict:
    sc = copy.deepcopy(scene)
    sc["load"]["p0"] = scene["load"]["p0"][i]
    return sc


def configs() -> dict[str, tuple[dict, int]]:
    """name -> (scene, number of loads)."""
    out = {"jkr, 3 loads in one call": (JKR, 3)}
    for i, p in enumerate(JKR["load"]["p0"]):
        out[f"jkr, {p} alone"] = (_single(JKR, i), 1)
    out["plastic_scale_dependent (wall reached), 3 loads in one call"] = (PLASTIC, 3)
    return out


def levels_of(scene: dict) -> list[tuple[int, int, int]]:
    """(loads, nodes, steps) of every grid level the engine marches for ``scene``."""
    import xpersson
    from xpersson.engine import _cn

    seen: list[tuple[int, int, int]] = []
    orig = _cn._march

    def spy(pbs, plan, n, *args):
        res = orig(pbs, plan, n, *args)
        # (a dict before issue 33's typed level result: --before may run an older tree)
        nsteps = res["nsteps"] if isinstance(res, dict) else res.nsteps
        seen.append((len(pbs), n + 1, int(nsteps)))
        return res

    _cn._march = spy
    try:
        xpersson.solve(scene)
    finally:
        _cn._march = orig
    return seen


def engine_args(scene: dict) -> tuple[tuple, dict]:
    """The arguments ``(args, kwargs)`` of the engine's one call for ``scene``
    (``xpersson.engine.solve_batch``: the walls, diffusion times, loads and tolerances the
    pipeline prepared); RuntimeError where the scene makes more or fewer calls than one."""
    import xpersson
    from xpersson import engine

    calls: list[tuple[tuple, dict]] = []
    orig = engine.solve_batch

    def spy(*args, **kwargs):
        calls.append((args, kwargs))
        return orig(*args, **kwargs)

    engine.solve_batch = spy
    try:
        xpersson.solve(scene)
    finally:
        engine.solve_batch = orig
    if len(calls) != 1:
        raise RuntimeError(f"the scene made {len(calls)} engine calls, not one")
    return calls[0]


def engine_call_of(scene: dict):
    """The engine's own call for ``scene`` (:func:`engine_args`) as a callable that repeats it
    (the march of :func:`levels_of` without the pipeline around it)."""
    from xpersson import engine

    args, kwargs = engine_args(scene)
    solve_batch = engine.solve_batch
    return lambda: solve_batch(*args, **kwargs)


def bare_steps(levels: list[tuple[int, int, int]]) -> None:
    """The floor: per level and step, a flux-form explicit product and one ``dgtsv``."""
    from scipy.linalg.lapack import dgtsv

    for nb, nn, steps in levels:
        m = nb * nn
        rng = np.random.default_rng(1)
        ga, gp = -rng.random(m - 1), rng.random(m - 1)
        w = 1.0 + rng.random(m)
        dl, du = -0.25 * rng.random(m - 1), -0.25 * rng.random(m - 1)
        dg = 1.0 + w
        r = rng.random(m)
        G, G2, rhs = np.empty(m - 1), np.empty(m - 1), np.empty(m)
        for _ in range(steps):
            np.multiply(ga, r[:-1], out=G)
            np.multiply(gp, r[1:], out=G2)
            G += G2
            np.multiply(w, r, out=rhs)
            rhs[1:-1] += G[1:] - G[:-1]
            r = dgtsv(dl, dg, du, rhs)[3]


def cpu(fn) -> float:
    t = time.process_time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fn()
    return time.process_time() - t


def measure(rounds: int) -> dict:
    """Best CPU time [s] per configuration and of its bare steps, this tree."""
    import xpersson

    cf = configs()
    levels = {k: levels_of(sc) for k, (sc, _) in cf.items()}
    best = {k: np.inf for k in cf}
    best_bare = {k: np.inf for k in cf}
    for rnd in range(rounds + 1):
        for k, (sc, _) in cf.items():
            t = cpu(lambda sc=sc: xpersson.solve(sc))
            tb = cpu(lambda k=k: bare_steps(levels[k]))
            if rnd:
                best[k], best_bare[k] = min(best[k], t), min(best_bare[k], tb)
    return {
        k: dict(
            loads=n,
            cpu=best[k],
            bare=best_bare[k],
            node_steps=sum(a * b * c for a, b, c in levels[k]),
            levels=len(levels[k]),
        )
        for k, (_, n) in cf.items()
    }


def areas() -> dict[str, list]:
    """A/A0 of both scenes (three loads each), for before/after comparisons."""
    import xpersson

    out = {}
    for name, sc in (("jkr", JKR), ("plastic", PLASTIC)):
        ds = xpersson.solve(sc)
        out[name] = np.asarray(ds["area_fraction"].values, float).tolist()
    return out


def _child(tree: Path, rounds: int) -> dict:
    env = dict(os.environ)
    srcs = [tree / "src"] + sorted((tree / "plugins").glob("*/src"))
    srcs += [tree / "examples" / "third_party_plugin" / "src"]
    env["PYTHONPATH"] = os.pathsep.join(str(s) for s in srcs)
    out = subprocess.run(
        [sys.executable, __file__, "--child", str(rounds)],
        env=env,
        capture_output=True,
        text=True,
        check=True,
        cwd=tree,
    )
    return json.loads(out.stdout.strip().splitlines()[-1])


def _merge(runs: list[dict]) -> dict:
    out = copy.deepcopy(runs[0])
    for run in runs[1:]:
        for k, v in run["cost"].items():
            out["cost"][k]["cpu"] = min(out["cost"][k]["cpu"], v["cpu"])
            out["cost"][k]["bare"] = min(out["cost"][k]["bare"], v["bare"])
    return out


def table(results: dict[str, dict]) -> str:
    lines = [
        "| tree | path | CPU per load [ms] | bare O(N) steps per load [ms] | ratio | "
        "node-steps per load |",
        "|---|---|---:|---:|---:|---:|",
    ]
    for tree, res in results.items():
        for k, v in res["cost"].items():
            n = v["loads"]
            lines.append(
                f"| {tree} | {k} | {v['cpu'] / n * 1e3:.1f} | {v['bare'] / n * 1e3:.1f} | "
                f"{v['cpu'] / v['bare']:.1f}x | {v['node_steps'] / n:.3g} |"
            )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--before", default=None, help="git revision to compare against")
    ap.add_argument("--child", type=int, default=None, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child is not None:
        print(json.dumps({"cost": measure(args.child), "areas": areas()}))
        return {}
    if args.before is None:
        results = {"this tree": {"cost": measure(args.rounds), "areas": areas()}}
    else:
        with tempfile.TemporaryDirectory() as tmp:
            old = Path(tmp)
            arc = subprocess.run(
                ["git", "archive", args.before, "src", "plugins", "examples"],
                cwd=ROOT,
                capture_output=True,
                check=True,
            ).stdout
            subprocess.run(["tar", "-x", "-C", str(old)], input=arc, check=True)
            runs: dict[str, list] = {f"before ({args.before})": [], "after": []}
            for _ in range(max(1, args.rounds // 2)):  # alternate the trees
                runs[f"before ({args.before})"].append(_child(old, 2))
                runs["after"].append(_child(ROOT, 2))
        results = {k: _merge(v) for k, v in runs.items()}
    text = table(results)
    if len(results) == 2:
        (a, ra), (b, rb) = results.items()
        for name in ra["areas"]:
            x, y = np.array(ra["areas"][name]), np.array(rb["areas"][name])
            d = float(np.max(np.abs(x / y - 1.0)))
            text += f"\n\nmax |A/A0 {a} / A/A0 {b} - 1|, {name}: {d:.2e}"
    print(text)
    out = HERE / "results"
    out.mkdir(exist_ok=True)
    (out / "cn_walls.md").write_text(
        "# Moving walls through `cn`: cost per load against bare O(N) steps\n\n"
        "CPU time, one process per tree and round, OPENBLAS_NUM_THREADS=1, best of "
        f"interleaved rounds ({args.rounds}); shared 2-core machine.\n\n" + text + "\n"
    )
    return results


if __name__ == "__main__":
    main()
