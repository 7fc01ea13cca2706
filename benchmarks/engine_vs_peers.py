"""Engine error versus CPU time, side by side with its peers and its compiled limit.

Runs, in one process, on the peers' named scenes (``realistic``, ``extreme``, ``ultra``,
``lowH``: a fixed absorbing wall, the exact curve by images; ``moving``: a linearly moving wall,
its closed form) and on seeded scenes of the speed design (:mod:`summary_design`,
``design(12, --seed)[:--design]``; the load of each is set so that A/A0 = 0.1, 1e-2, 1e-3, 1e-4
in turn (:data:`AREA_DESIGN`) at
its largest magnification q_1/q_L, outputs at 4 per decade):

* the engine's paths: ``cn`` at several rtol (the compiled march built first, as the README's
  speed rows build it), ``sine`` (the semi-analytic series, fixed walls) and ``exact`` (closed
  form), each with its own error estimate next to its true error;
* the C march of ``../shared/peers/c_march`` (``$XPERSSON_PEERS`` overrides the folder; built
  with ``$CC``/``cc``, skipped without a compiler) on the very grid levels and steps each ``cn``
  run marched: the compiled floor of the same work (same node-steps, so the same error), not a
  solver of its own;
* the peers of ``peer_scipy_mol.py``: ``solve_ivp`` method of lines (BDF and LSODA in diffusion
  time, BDF in zeta on the named scenes; exact sparse/banded Jacobians) and the two-grid BDF
  peer (N and 2N-1 nodes, Richardson-extrapolated curve, as the README's row "BDF two-grid
  peer", here in diffusion time, which is faster than zeta at the same error); on the moving
  wall a Landau-transform BDF method of lines written here.

Error: max relative error of A/A0 over the output magnifications. Time: CPU time of this process
(``time.process_time``) per solve, best of ``--rounds`` rounds in which every run of a scene is
timed in turn (after a warm-up; calls of a few ms repeated to ~20 ms), ``OPENBLAS_NUM_THREADS=1``.

Writes ``benchmarks/results/engine_vs_peers.md`` (how to read it, speed-up at matched error,
every run) and ``benchmarks/results/work_precision.png``.

Usage: ``python benchmarks/engine_vs_peers.py [--quick] [--rounds 3] [--seed 2026]
[--design 4]`` (``--quick``: fewer scenes and runs, ~15 s; the full run ~5 minutes).
"""

from __future__ import annotations

import os

os.environ["OPENBLAS_NUM_THREADS"] = "1"  # ratios with one BLAS thread (said in the results)

import argparse  # noqa: E402
import math  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402
from collections.abc import Callable  # noqa: E402
from dataclasses import dataclass, field  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
import scipy.sparse as sp  # noqa: E402
from scipy.integrate import solve_ivp  # noqa: E402
from scipy.special import erf, erfinv  # noqa: E402

HERE = Path(__file__).resolve().parent
PEERS = Path(os.environ.get("XPERSSON_PEERS", HERE.parents[1] / "shared" / "peers"))
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(PEERS))
sys.path.insert(0, str(PEERS / "c_march"))

import peer_scipy_mol  # noqa: E402
import scene as S  # noqa: E402
from engine_vs_peers_report import plot, write_markdown  # noqa: E402
from summary_design import best, design, repeated  # noqa: E402

import xpersson  # noqa: E402
from xpersson.engine import Wall, exact, solve  # noqa: E402

NAMED = ("realistic", "extreme", "ultra", "lowH")
AREA_DESIGN = (0.1, 1e-2, 1e-3, 1e-4)
"""A/A0 at the largest magnification of the design scenes in turn (sets each one's load)."""


@dataclass
class Case:
    """One scene: output diffusion times ``tau`` [Pa^2], load ``p0`` [Pa], the exact A/A0 at
    ``tau``, the engine's walls, and the peers' scene (``peer_scipy_mol``'s duck type)."""

    name: str
    tau: np.ndarray
    p0: float
    area: np.ndarray
    peer: object = None
    zeta_peer: bool = False  # whether the peers may integrate in zeta (``peer.fhat`` exists)
    lower: Wall = field(default_factory=lambda: Wall.absorbing(0.0))
    closed: Callable[[], object] | None = None  # the engine's exact path, where it applies


class TauScene:
    """A design scene for ``peer_scipy_mol.solve(..., var="tau")``: scaled by
    ``s = sqrt(2 tau_max)`` as ``scene.Scene`` (domain ``[0, xbar + 8]``)."""

    def __init__(self, name: str, tau: np.ndarray, p0: float) -> None:
        s = math.sqrt(2.0 * tau[-1])
        self.name, self.xbar, self._th = name, p0 / s, tau / s**2
        self.L = self.xbar + 8.0

    def tauhat_out(self, per_decade: int = 4) -> np.ndarray:
        return self._th.copy()

    def area_curve_exact(self, per_decade: int = 4) -> np.ndarray:
        return erf(self.xbar / (2.0 * np.sqrt(self._th)))


def named_case(name: str) -> Case:
    sc = S.make_scene(name)
    tau = sc.tau(sc.zeta_out())
    case = Case(name, tau, sc.p_bar, sc.area_curve_exact(), sc, zeta_peer=True)
    case.closed = lambda: solve(tau, sc.p_bar, method="exact")
    return case


def design_cases(seed: int, n: int) -> list[Case]:
    """The first ``n`` scenes of ``design(12, seed)``: tau(zeta) from the pipeline's coefficient
    at 4 outputs per decade up to q_1/q_L, the load for A/A0 = :data:`AREA_DESIGN` there (in
    turn: with a fixed wall the scenes differ only in tau's spread over the outputs and in the
    load's distance to the wall on the scale sqrt(tau))."""
    from summary_design import scene

    from xpersson.plugins import SceneContext

    out = []
    for k, (name, spec) in enumerate(design(12, seed)[:n]):
        dec = math.log10(float(spec["q_1"].split()[0]) / float(spec["q_L"].split()[0]))
        zeta = np.logspace(0.0, dec, round(4 * dec) + 1)[1:]
        sc = scene(spec, "100 kPa", output={"zeta": [float(z) for z in zeta]})
        rs = xpersson.Scene(sc).resolve()
        ctx = SceneContext(
            psd=rs.psd, E=rs.E, nu=rs.nu, E_star=rs.E_star, p0=rs.p0, zeta=rs.zeta,
            rtol=rs.rtol, atol=rs.atol,
        )  # fmt: skip
        tau = np.asarray(rs.coefficient.tau(ctx, rs.zeta), float)
        p0 = 2.0 * math.sqrt(tau[-1]) * float(erfinv(AREA_DESIGN[k % 4]))
        label = f"seed {seed}: {name}, A/A0={AREA_DESIGN[k % 4]:g}"
        case = Case(label, tau, p0, erf(p0 / (2.0 * np.sqrt(tau))), TauScene(label, tau, p0))
        case.closed = lambda tau=tau, p0=p0: solve(tau, p0, method="exact")
        out.append(case)
    return out


# --- moving linear wall (physics: the wall p_w = -(S0 + C tau), closed form) --------------------
P0, S0, C = 0.5, 0.2, 1.0  # Pa, Pa, 1/Pa
TAU_MAX = 1.0


def moving_case() -> Case:
    tau = TAU_MAX * np.logspace(-3, 0, 13)
    case = Case("moving", tau, P0, exact.linear_wall_area(tau, P0, S0, C))
    case.lower = Wall.absorbing(lambda t: -(S0 + C * t))  # a callable: the numerical path
    case.closed = lambda: solve(tau, P0, Wall.linear(-S0, -C))
    return case


def landau_mol(n: int, rtol: float) -> np.ndarray:
    """The moving wall's peer: y = p - p_w(tau), Q_tau = Q_yy - c Q_y, BDF method of lines."""
    y0 = P0 + S0
    y = np.linspace(0.0, y0 + 12 * math.sqrt(2 * TAU_MAX), n)
    h, m = y[1] - y[0], n - 2
    lap = sp.diags([np.ones(m - 1), -2 * np.ones(m), np.ones(m - 1)], [-1, 0, 1]) / h**2
    der = sp.diags([-np.ones(m - 1), np.ones(m - 1)], [-1, 1]) / (2 * h)
    A = (lap - C * der).tocsr()
    t_eval = TAU_MAX * np.logspace(-3, 0, 13)
    sol = solve_ivp(
        lambda t, q: A @ q, (0.0, TAU_MAX), S.delta_hat(y, y0)[1:-1], method="BDF",
        t_eval=t_eval, jac=A, rtol=rtol, atol=1e-3 * rtol,
    )  # fmt: skip
    if not sol.success:
        raise RuntimeError(sol.message)
    return h * sol.y.sum(axis=0)


# --- the runs of one scene ------------------------------------------------------------------------
@dataclass
class Run:
    """One point of the figure: ``fn`` solves, ``curve(result)`` gives its A/A0 curve."""

    solver: str
    resolution: str
    kind: str  # "engine", "limit" (the C march) or "peer"
    fn: Callable[[], object]
    curve: Callable[[object], np.ndarray] = lambda r: np.asarray(r.area)
    row: dict = field(default_factory=dict)


def _levels(fn: Callable[[], object]) -> tuple[object, list[tuple[int, int, int]]]:
    """``fn()`` and the (loads, nodes, steps) of every ``cn`` grid level it marched (the spy of
    ``cn_walls.levels_of``, around an engine call)."""
    from xpersson.engine import _cn

    seen: list[tuple[int, int, int]] = []
    orig = _cn._march

    def spy(pbs, plan, n, *args):
        res = orig(pbs, plan, n, *args)
        seen.append((len(pbs), n + 1, int(res.nsteps)))
        return res

    _cn._march = spy
    try:
        return fn(), seen
    finally:
        _cn._march = orig


def engine_runs(case: Case, lib, quick: bool) -> list[Run]:
    """cn at several rtol (and the C march on each one's levels), sine, exact."""
    from march_vs_engine import c_march

    runs = []
    rtols = (1e-4, 1e-6, 1e-8) if quick else (1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8)
    for rtol in rtols:

        def fn(rtol=rtol):
            return solve(case.tau, case.p0, case.lower, None, method="cn", rtol=rtol)

        res, levels = _levels(fn)
        steps = sum(a * b * c for a, b, c in levels)
        runs.append(Run("xpersson cn", f"rtol={rtol:g}, n={res.n_nodes}", "engine", fn))
        runs[-1].row["node_steps"] = steps
        if lib is not None and levels:
            march = Run(
                "C march",
                f"levels of cn rtol={rtol:g}",
                "limit",
                lambda lv=levels: c_march(lib, lv),
            )
            runs.append(march)
            runs[-1].row.update(node_steps=steps, same_as=len(runs) - 2)
    if case.name != "moving":
        for rtol in (1e-6,) if quick else (1e-4, 1e-8):

            def sine(rtol=rtol):
                return solve(case.tau, case.p0, case.lower, None, method="sine", rtol=rtol)

            runs.append(Run("xpersson sine", f"rtol={rtol:g}", "engine", sine))
    runs.append(Run("xpersson exact", "closed form", "engine", case.closed))
    return runs


def _two_grid(peer: object, n: int) -> np.ndarray:
    coarse = peer_scipy_mol.solve(peer, n, "BDF", 1e-7, var="tau")[3]
    fine = peer_scipy_mol.solve(peer, 2 * n - 1, "BDF", 1e-7, var="tau")[3]
    return (4.0 * fine - coarse) / 3.0


def peer_runs(case: Case, quick: bool) -> list[Run]:
    """The ``solve_ivp`` method of lines (a reduced set) and the two-grid BDF peer."""
    if case.name == "moving":
        sizes = ((1025, 1e-5), (4097, 1e-7)) + (() if quick else ((16385, 1e-8),))
        return [
            Run("scipy BDF MoL (Landau)", f"N={n}, rtol={r:g}", "peer",
                lambda n=n, r=r: landau_mol(n, r), curve=lambda c: c)
            for n, r in sizes
        ]  # fmt: skip
    configs = [("BDF", "tau", 1025, 1e-5), ("BDF", "tau", 4097, 1e-7)]
    if not quick:
        configs += [("BDF", "tau", 16385, 1e-7), ("LSODA", "tau", 4097, 1e-7)]
        configs += [("BDF", "zeta", 4097, 1e-7)] if case.zeta_peer else []
    runs = [
        Run(f"scipy {m} MoL ({var})", f"N={n}, rtol={r:g}", "peer",
            lambda m=m, var=var, n=n, r=r: peer_scipy_mol.solve(case.peer, n, m, r, var=var),
            curve=lambda out: out[3])
        for m, var, n, r in configs
    ]  # fmt: skip
    for n in (513,) if quick else (513, 2049, 8193):
        runs.append(Run("scipy BDF two-grid (tau)", f"N={n}+{2 * n - 1}, rtol=1e-07", "peer",
                        lambda n=n: _two_grid(case.peer, n), curve=lambda c: c))  # fmt: skip
    return runs


def _errors(case: Case, run: Run, res: object) -> dict:
    """True error (max relative over the outputs) and, for the engine, its own estimate."""
    area = run.curve(res)
    true = np.abs(np.asarray(area, float) - case.area)
    out = {"err": float(np.max(true / case.area))}
    est = getattr(res, "error_estimate", None)
    if est is not None:
        est = np.asarray(est, float)
        out["est"] = float(np.max(est / case.area))
        judged = true > 1e-15  # rounding-level errors are not judged (as verify_core.py)
        ratio = true[judged] / np.maximum(est[judged], 1e-300)
        out["err/est"] = float(ratio.max()) if judged.any() else 0.0
    return out


def measure(case: Case, lib, rounds: int, quick: bool) -> list[dict]:
    """Every run of ``case`` once (its errors), then best CPU times over interleaved rounds."""
    runs = engine_runs(case, lib, quick) + peer_runs(case, quick)
    fns, counts = {}, {}
    for i, run in enumerate(runs):
        t = time.process_time()
        try:
            res = run.fn()
        except Exception as exc:  # noqa: BLE001 - a failing peer is a row of the table
            run.row.update(err=math.nan, error=f"{type(exc).__name__}: {str(exc)[:80]}")
            continue
        once = time.process_time() - t
        if run.kind == "limit":
            run.row["err"] = runs[run.row["same_as"]].row.get("err", math.nan)
        else:
            run.row.update(_errors(case, run, res))
        fns[i], counts[i] = repeated(run.fn, once=once) if run.kind != "peer" else (run.fn, 1)
    t = best(fns, rounds)
    rows = []
    for i, run in enumerate(runs):
        row = {k: v for k, v in run.row.items() if k != "same_as"}
        row.update(scene=case.name, solver=run.solver, resolution=run.resolution, kind=run.kind)
        row["time_s"] = t[i] / counts[i] if i in t else math.nan
        rows.append(row)
        err = row.get("err", math.nan)
        print(
            f"{case.name:40s} {run.solver:26s} {run.resolution:26s} "
            f"t={row['time_s'] * 1e3:9.3f} ms err={err:9.2e}",
            flush=True,
        )
    return rows


def machine() -> dict:
    """Facts of the run (no paths): date, CPU, cores, versions, compiler."""
    import platform
    import shutil
    import subprocess

    import scipy

    model = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as fh:
            model = next(ln.split(":", 1)[1].strip() for ln in fh if ln.startswith("model name"))
    except (OSError, StopIteration):
        pass
    cc = os.environ.get("CC", "cc")
    ver = "none"
    if shutil.which(cc):
        out = subprocess.run([cc, "--version"], capture_output=True, text=True, check=False)
        ver = out.stdout.splitlines()[0] if out.stdout else cc
    try:
        import numba

        nb = numba.__version__
    except ImportError:
        nb = "absent (numpy march)"
    return {
        "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
        "cpu": f"{model}, {os.cpu_count()} cores (shared)",
        "versions": f"Python {platform.python_version()}, numpy {np.__version__}, "
        f"scipy {scipy.__version__}, numba {nb}, xpersson {xpersson.__version__}",
        "compiler": ver,
    }


def main(argv: list[str] | None = None) -> list[dict]:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer scenes and runs (< 2 minutes)")
    ap.add_argument("--rounds", type=int, default=None, help="timing rounds (3; --quick 2)")
    ap.add_argument("--seed", type=int, default=2026, help="seed of the design scenes")
    ap.add_argument("--design", type=int, default=None, help="design scenes (4; --quick 2)")
    ap.add_argument("--out", type=Path, default=HERE / "results")
    args = ap.parse_args(argv)
    rounds = args.rounds or (2 if args.quick else 3)
    n_design = args.design if args.design is not None else (2 if args.quick else 4)
    from summary_paths import c_march_lib

    from xpersson.engine import _compiled

    xpersson.set_options(compiled=True)
    compiled = _compiled.build()
    lib = c_march_lib(PEERS)
    warnings.simplefilter("ignore")
    cases = [named_case(n) for n in (NAMED[:1] if args.quick else NAMED)] + [moving_case()]
    cases += design_cases(args.seed, n_design)
    rows = []
    for case in cases:
        rows += measure(case, lib, rounds, args.quick)
    meta = machine()
    meta["march"] = "compiled (numba)" if compiled else "numpy (numba absent)"
    flags = " --quick" if args.quick else ""
    meta["command"] = (
        f"python benchmarks/engine_vs_peers.py{flags} --rounds {rounds} --seed {args.seed} "
        f"--design {n_design}"
    )
    meta["rounds"] = rounds
    args.out.mkdir(exist_ok=True)
    write_markdown(rows, meta, args.out / "engine_vs_peers.md")
    plot(rows, args.out / "work_precision.png")
    return rows


if __name__ == "__main__":
    main()
