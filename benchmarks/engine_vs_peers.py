"""Engine error versus run time, side by side with the scipy method-of-lines peers.

Runs, in one process, xpersson's engine (numerical paths "sine" and "cn" at several rtol, and the
exact path) and the peers of ``../shared/peers`` (``scipy.integrate.solve_ivp`` BDF / LSODA /
Radau, in zeta and in tau, a few N and rtol) on the scenes realistic, extreme, ultra, lowH, plus
a linearly moving wall (engine "cn" vs a Landau-transform method of lines with BDF written here).

Metric: ``curve_err`` = max relative error of A/A0(zeta) at ``scene.zeta_out()`` (4 per decade);
time: median of ``scene.timed``.  Writes ``benchmarks/results/engine_vs_peers.md`` and
``benchmarks/results/work_precision.png``.

Usage: ``python benchmarks/engine_vs_peers.py [--quick]``  (``--quick`` < 2 minutes).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # ratios with one BLAS thread (said so)

import argparse  # noqa: E402
import math  # noqa: E402
import sys  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
import scipy.sparse as sp  # noqa: E402
from scipy.integrate import solve_ivp  # noqa: E402

HERE = Path(__file__).resolve().parent
PEERS = HERE.parents[1] / "shared" / "peers"
sys.path.insert(0, str(PEERS))
sys.path.insert(0, str(HERE.parent / "src"))

import peer_scipy_mol  # noqa: E402
import scene as S  # noqa: E402

from xpersson.engine import Wall, exact, solve  # noqa: E402

SCENES = ("realistic", "extreme", "ultra", "lowH")
TARGET = 1e-5


def _row(scene, method, resolution, t, err, kind):
    return dict(
        scene=scene, method=method, resolution=resolution, time_s=t, curve_err=err, kind=kind
    )


def engine_rows(sc, quick):
    tau = sc.tau(sc.zeta_out())
    rows = []
    cases = [("exact", None)]
    cases += [("sine", r) for r in (1e-4, 1e-6, 1e-8)]
    cases += [("cn", r) for r in ((1e-3, 1e-5) if quick else (1e-3, 1e-4, 1e-5, 1e-6))]
    for method, rtol in cases:

        def fn(method=method, rtol=rtol):
            return solve(tau, sc.p_bar, Wall.absorbing(0.0), None, method=method, rtol=rtol or 1e-8)

        res, t, _ = S.timed(fn, budget=2.0 if quick else 5.0)
        err = S.curve_error(sc, res.area)
        label = f"xpersson {method}" + ("" if method == "exact" else f" ({res.status})")
        resol = "closed form" if method == "exact" else f"rtol={rtol:g}, n={res.n_nodes}"
        rows.append(_row(sc.name, label, resol, t, err, "engine"))
        print(f"{sc.name:9s} {label:32s} {resol:24s} t={t:9.5f}s err={err:9.2e}", flush=True)
    return rows


def peer_rows(sc, quick):
    rows = []
    if quick:
        configs = [("BDF", "zeta", n, r) for n in (1025, 4097) for r in (1e-5, 1e-7)]
        configs += [("LSODA", "zeta", 4097, 1e-7), ("BDF", "tau", 4097, 1e-7)]
    else:
        configs = [("BDF", "zeta", n, r) for n in (257, 1025, 4097, 16385) for r in (1e-5, 1e-7)]
        configs += [(m, "zeta", n, 1e-7) for m in ("LSODA", "Radau") for n in (1025, 4097)]
        configs += [("BDF", "tau", n, r) for n in (1025, 4097) for r in (1e-5, 1e-7)]
        configs += [("LSODA", "tau", 4097, 1e-7)]
    for method, var, n, rtol in configs:

        def fn(method=method, var=var, n=n, rtol=rtol):
            return peer_scipy_mol.solve(sc, n, method, rtol, var=var)

        try:
            (x, P, A, curve, info), t, _ = S.timed(fn, budget=2.0 if quick else 6.0, max_repeats=3)
            err = S.curve_error(sc, curve)
        except Exception as exc:  # report failures in the table
            t, err = float("nan"), float("nan")
            print(f"{sc.name} scipy {method} failed: {exc}")
        label = f"scipy {method} MoL ({var})"
        resol = f"N={n},rtol={rtol:g}"
        rows.append(_row(sc.name, label, resol, t, err, "peer"))
        print(f"{sc.name:9s} {label:32s} {resol:24s} t={t:9.5f}s err={err:9.2e}", flush=True)
    return rows


# --- moving linear wall ------------------------------------------------------------------------
P0, S0, C = 0.5, 0.2, 1.0  # Pa, Pa, 1/Pa (physics.md §2.2 check case)
TAU_MAX = 1.0


def _moving_tau():
    return TAU_MAX * np.logspace(-3, 0, 13)


def landau_mol(n, rtol):
    """Peer for the moving wall: y = p - p_w(tau), Q_tau = Q_yy - c Q_y, BDF method of lines."""
    y0 = P0 + S0
    length = y0 + 12 * math.sqrt(2 * TAU_MAX)
    y = np.linspace(0.0, length, n)
    h = y[1] - y[0]
    m = n - 2
    lap = sp.diags([np.ones(m - 1), -2 * np.ones(m), np.ones(m - 1)], [-1, 0, 1]) / h**2
    der = sp.diags([-np.ones(m - 1), np.ones(m - 1)], [-1, 1]) / (2 * h)
    A = (lap - C * der).tocsr()
    q0 = S.delta_hat(y, y0)[1:-1]
    t_eval = _moving_tau()
    sol = solve_ivp(
        lambda t, q: A @ q,
        (0.0, TAU_MAX),
        q0,
        method="BDF",
        t_eval=t_eval,
        jac=A,
        rtol=rtol,
        atol=1e-3 * rtol,
    )
    if not sol.success:
        raise RuntimeError(sol.message)
    return h * sol.y.sum(axis=0)


def moving_rows(quick):
    tau = _moving_tau()
    ex = exact.linear_wall_area(tau, P0, S0, C)
    rows = []
    wall = Wall.absorbing(lambda t: -(S0 + C * t))  # a callable: forces the numerical path
    for rtol in (1e-3, 1e-4, 1e-5, 1e-6) if not quick else (1e-3, 1e-5):

        def fn(rtol=rtol):
            return solve(tau, P0, wall, method="cn", rtol=rtol)

        res, t, _ = S.timed(fn, budget=2.0)
        err = float(np.max(np.abs(res.area / ex - 1)))
        resol = f"rtol={rtol:g}, n={res.n_nodes}"
        rows.append(_row("moving", f"xpersson cn ({res.status})", resol, t, err, "engine"))
        print(f"moving    xpersson cn {resol:24s} t={t:9.5f}s err={err:9.2e}", flush=True)
    res, t, _ = S.timed(lambda: solve(tau, P0, Wall.linear(-S0, -C)), budget=1.0)
    rows.append(
        _row(
            "moving",
            "xpersson exact",
            "closed form",
            t,
            float(np.max(np.abs(res.area / ex - 1))),
            "engine",
        )
    )
    for n, rtol in (
        ((1025, 1e-5), (4097, 1e-7)) if quick else ((1025, 1e-5), (4097, 1e-7), (16385, 1e-8))
    ):
        try:
            curve, t, _ = S.timed(
                lambda n=n, rtol=rtol: landau_mol(n, rtol), budget=3.0, max_repeats=3
            )
            err = float(np.max(np.abs(curve / ex - 1)))
        except Exception as exc:
            t, err = float("nan"), float("nan")
            print(f"moving peer failed: {exc}")
        resol = f"N={n},rtol={rtol:g}"
        rows.append(_row("moving", "scipy BDF MoL (Landau)", resol, t, err, "peer"))
        print(f"moving    scipy BDF MoL (Landau) {resol:24s} t={t:9.5f}s err={err:9.2e}")
    return rows


# --- report ------------------------------------------------------------------------------------
def speedups(rows, engine_method=None):
    """Per scene: (fastest engine run at <= TARGET, fastest peer at <= TARGET, ratio).

    ``engine_method``: "cn" (grid to grid: a numerical grid method against the peers' grids),
    "sine" (the semi-analytic series), or None (any numerical engine run).
    """
    out = {}
    for name in sorted({r["scene"] for r in rows}):

        def best(kind, name=name):
            ok = [
                r
                for r in rows
                if r["scene"] == name
                and r["kind"] == kind
                and "exact" not in r["method"]
                and r["curve_err"] <= TARGET
                and (
                    kind == "peer"
                    or engine_method is None
                    or f"xpersson {engine_method}" in r["method"]
                )
            ]
            return min(ok, key=lambda r: r["time_s"]) if ok else None

        e, p = best("engine"), best("peer")
        if e and not p:  # no peer reached 1e-5: compare with its most accurate run (a bound)
            peers = [
                r
                for r in rows
                if r["scene"] == name and r["kind"] == "peer" and math.isfinite(r["curve_err"])
            ]
            if peers:
                p = dict(min(peers, key=lambda r: (r["curve_err"], r["time_s"])), bound=True)
        out[name] = (e, p, p["time_s"] / e["time_s"] if e and p else float("nan"))
    return out


def _speedup_table(rows, engine_method, title):
    lines = [
        "",
        f"## {title}",
        "",
        "| scene | engine (fastest at 1e-5) | peer (fastest at 1e-5) | speed-up |",
        "|---|---|---|---:|",
    ]
    for name, (e, p, ratio) in speedups(rows, engine_method).items():
        es = f"{e['method']} {e['resolution']}: {e['time_s']:.2e} s" if e else "none"
        ps = f"{p['method']} {p['resolution']}: {p['time_s']:.2e} s" if p else "none"
        bound = ""
        if p and p.get("bound"):
            ps += f" (none reached 1e-5; best curve_err {p['curve_err']:.1e})"
            bound = ">"
        lines.append(
            f"| {name} | {es} | {ps} | {bound}{ratio:.0f}x |"
            if math.isfinite(ratio)
            else f"| {name} | {es} | {ps} | - |"
        )
    return lines


def write_markdown(rows, path):
    sp_ = speedups(rows)
    lines = [
        "# Engine vs scipy method-of-lines peers",
        "",
        "`curve_err`: max relative error of A/A0(zeta) at 4 points per decade (scene.zeta_out()); "
        "time: median wall time (scene.timed). Speed-up: fastest peer with curve_err <= 1e-5 "
        "divided by the fastest numerical engine run with curve_err <= 1e-5 (exact path "
        "excluded).",
        "",
        "`OPENBLAS_NUM_THREADS=1`; all runs in one process on a shared 2-core machine.",
        "",
        "| scene | method | resolution | time [s] | curve_err | speed-up at 1e-5 |",
        "|---|---|---|---:|---:|---:|",
    ]
    for r in rows:
        e, p, ratio = sp_[r["scene"]]
        bound = ">" if p and p.get("bound") else ""
        mark = f"{bound}{ratio:.0f}x" if (r is e and math.isfinite(ratio)) else ""
        lines.append(
            f"| {r['scene']} | {r['method']} | {r['resolution']} | {r['time_s']:.2e} | "
            f"{r['curve_err']:.2e} | {mark} |"
        )
    lines += _speedup_table(
        rows,
        "cn",
        "Grid to grid at equal accuracy (curve_err <= 1e-5): cn against the scipy method of lines",
    )
    lines += _speedup_table(
        rows,
        "sine",
        "Semi-analytic sine series against the scipy method "
        "of lines (curve_err <= 1e-5; not a grid method)",
    )
    path.write_text("\n".join(lines) + "\n")


def plot(rows, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    def label_of(method: str) -> str:
        parts = method.split(" (")
        return parts[0] + (" (" + parts[1] if "MoL" in method else "")

    names = [n for n in (*SCENES, "moving") if any(r["scene"] == n for r in rows)]
    # one colour per method across every panel (a panel without some method keeps the others')
    labels = list(dict.fromkeys(label_of(r["method"]) for r in rows))
    colour = {lab: plt.get_cmap("tab10")(i % 10) for i, lab in enumerate(labels)}
    fig, axes = plt.subplots(1, len(names), figsize=(4 * len(names), 3.6), squeeze=False)
    for ax, name in zip(axes[0], names, strict=True):
        groups = {}
        for r in rows:
            if r["scene"] == name and math.isfinite(r["time_s"]) and math.isfinite(r["curve_err"]):
                groups.setdefault(label_of(r["method"]), []).append(r)
        for label, rs in groups.items():
            rs.sort(key=lambda r: r["time_s"])
            ax.loglog(
                [r["time_s"] for r in rs],
                [max(r["curve_err"], 1e-16) for r in rs],
                "o-" if "xpersson" in label else "s--",
                color=colour[label],
                label=label,
                ms=4,
            )
        ax.axhline(TARGET, color="grey", lw=0.8, ls=":")
        ax.set_title(f"{name} (sine: semi-analytic; cn vs scipy: grid to grid)", fontsize=7)
        ax.set_xlabel("time [s]")
        ax.set_ylabel("max rel. error of A/A0")
        if ax is axes[0][0] or name == "moving":  # the moving wall has its own peer
            ax.legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer configurations (< 2 minutes)")
    args = ap.parse_args(argv)
    out = HERE / "results"
    out.mkdir(exist_ok=True)
    rows = []
    for name in SCENES:
        sc = S.make_scene(name)
        rows += engine_rows(sc, args.quick)
        rows += peer_rows(sc, args.quick)
    rows += moving_rows(args.quick)
    write_markdown(rows, out / "engine_vs_peers.md")
    plot(rows, out / "work_precision.png")
    for method in ("cn", "sine"):
        for name, (_e, p, ratio) in speedups(rows, method).items():
            bound = ">" if p and p.get("bound") else ""
            print(f"speed-up at 1e-5 [{name}, {method}]: {bound}{ratio:.1f}x")
    return rows


if __name__ == "__main__":
    main()
