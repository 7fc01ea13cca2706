"""The Markov-process solvers in the work-precision picture, beside the PDE paths.

Runs, in one process (``OPENBLAS_NUM_THREADS=1``), on the shared scene ``realistic``
(``../shared/peers``, A/A0 = 0.1 at zeta = 1e4) and on the linearly moving wall of physics.md
§2.2 (p0 = 0.5, s0 = 0.2, c = 1, tau in [1e-3, 1]):

* ``markov`` (Monte Carlo walkers) with N = 1e3 ... 1e6; the error of each N is the rms over
  several seeds (one seed at 1e6), so that the N^-1/2 law is visible and not one draw;
* ``markov_ck`` (Chapman-Kolmogorov integral on a grid), several node counts;
* the PDE paths ``sine`` (fixed walls), ``cn`` (any wall) and the closed form ``exact``.

Metric: ``curve_err`` = max relative error of A/A0 at the output magnifications (4 per decade,
``scene.zeta_out()``), as in ``engine_vs_peers.py``; time: median of ``scene.timed``.  Also
reports walkers per second and the fitted slope of log(error) against log(N).  Writes
``results/markov_work_precision.md`` and ``results/markov_work_precision.png``.

Usage: ``python benchmarks/markov_work_precision.py [--quick]``.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import math  # noqa: E402
import sys  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

HERE = Path(__file__).resolve().parent
PEERS = HERE.parents[1] / "shared" / "peers"
sys.path.insert(0, str(PEERS))
sys.path.insert(0, str(HERE.parent / "src"))

import scene as S  # noqa: E402

from xpersson.engine import Wall, exact, solve  # noqa: E402

MOVING = dict(p0=0.5, s0=0.2, c=1.0)


def _cases(quick: bool) -> dict:
    sc = S.make_scene("realistic")
    tau_r = sc.tau(sc.zeta_out())
    tau_m = np.geomspace(1e-3, 1.0, 13)
    m = MOVING
    return {
        "realistic": dict(
            tau=tau_r,
            p0=sc.p_bar,
            lower=Wall.absorbing(0.0),
            exact=sc.area_curve_exact(),
            pde=("sine", "cn"),
        ),
        "moving wall": dict(
            tau=tau_m,
            p0=m["p0"],
            lower=Wall.linear(-m["s0"], -m["c"]),
            exact=exact.linear_wall_area(tau_m, m["p0"], m["s0"], m["c"]),
            pde=("cn",),
        ),
    }


def _err(area, ref):
    return float(np.max(np.abs(np.asarray(area) - ref) / ref))


def run(quick: bool) -> list[dict]:
    rows = []
    walkers = (
        (1_000, 10_000, 100_000)
        if quick
        else (1_000, 3_000, 10_000, 30_000, 100_000, 300_000, 1_000_000)
    )
    for name, c in _cases(quick).items():
        tau, p0, lower, ref = c["tau"], c["p0"], c["lower"], c["exact"]

        def one(method, rtol=1e-6, options=None, tau=tau, p0=p0, lower=lower):
            return solve(tau, p0, lower, None, method=method, rtol=rtol, options=options)

        res, t, _ = S.timed(lambda: one("exact"), budget=1.0)
        rows.append(
            dict(
                scene=name, method="exact", setting="closed form", time_s=t, err=_err(res.area, ref)
            )
        )
        for method in c["pde"]:
            for rtol in (1e-3, 1e-5) if quick else (1e-3, 1e-4, 1e-5, 1e-6, 1e-8):
                if method == "cn" and rtol < 1e-6:
                    continue
                res, t, _ = S.timed(lambda m=method, r=rtol: one(m, r), budget=2.0)
                rows.append(
                    dict(
                        scene=name,
                        method=method,
                        setting=f"rtol={rtol:g}",
                        time_s=t,
                        err=_err(res.area, ref),
                    )
                )
        for nodes in (50, 200) if quick else (25, 50, 100, 200, 400):
            res, t, _ = S.timed(lambda n=nodes: one("markov_ck", 1e-3, {"nodes": n}), budget=2.0)
            rows.append(
                dict(
                    scene=name,
                    method="markov_ck",
                    setting=f"nodes={nodes}",
                    time_s=t,
                    err=_err(res.area, ref),
                )
            )
        for n in walkers:
            seeds = 1 if n >= 1_000_000 else (4 if quick else 8)
            errs, times, steps = [], [], 0
            for seed in range(seeds):
                res, t, _ = S.timed(
                    lambda n=n, s=seed: one("markov", 0.09, {"walkers": n, "seed": s}),
                    budget=0.0,
                    max_repeats=1,
                )
                errs.append(_err(res.area, ref))
                times.append(t)
                steps = res.nsteps
            rows.append(
                dict(
                    scene=name,
                    method="markov",
                    setting=f"N={n}",
                    time_s=float(np.median(times)),
                    err=float(math.sqrt(np.mean(np.square(errs)))),
                    walkers=n,
                    steps=steps,
                    walkers_per_s=n / float(np.median(times)),
                )
            )
            print(rows[-1], flush=True)
    return rows


def slope(rows: list[dict], scene: str) -> float:
    mc = [r for r in rows if r["scene"] == scene and r["method"] == "markov"]
    n = np.log([r["walkers"] for r in mc])
    e = np.log([r["err"] for r in mc])
    return float(np.polyfit(n, e, 1)[0])


def write(rows: list[dict], out: Path) -> None:
    lines = [
        "# Markov-process solvers beside the PDE paths (`markov_work_precision.py`)",
        "",
        "One process, `OPENBLAS_NUM_THREADS=1`, shared 2-core machine. `err` = max relative "
        "error of A/A0 at the output magnifications; for `markov` the rms over seeds.",
        "",
        "| scene | method | setting | time [s] | err | walkers/s |",
        "|---|---|---|---:|---:|---:|",
    ]
    for r in rows:
        wps = f"{r['walkers_per_s']:.3g}" if "walkers_per_s" in r else ""
        lines.append(
            f"| {r['scene']} | {r['method']} | {r['setting']} | {r['time_s']:.3g} | "
            f"{r['err']:.2e} | {wps} |"
        )
    lines.append("")
    for scene in sorted({r["scene"] for r in rows}):
        lines.append(
            f"- {scene}: fitted slope of log(err) vs log(N) for `markov`: "
            f"{slope(rows, scene):.3f} (N^-1/2: -0.5)"
        )
    out.with_suffix(".md").write_text("\n".join(lines) + "\n")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    scenes = sorted({r["scene"] for r in rows}, reverse=True)
    fig, axes = plt.subplots(1, len(scenes), figsize=(11, 4.2), constrained_layout=True)
    style = {"exact": "*", "sine": "s-", "cn": "^-", "markov_ck": "d-", "markov": "o-"}
    color = {
        "exact": "k",
        "sine": "tab:blue",
        "cn": "tab:orange",
        "markov_ck": "tab:green",
        "markov": "tab:red",
    }
    for ax, scene in zip(np.atleast_1d(axes), scenes, strict=True):
        for method, fmt in style.items():
            rs = sorted(
                (r for r in rows if r["scene"] == scene and r["method"] == method),
                key=lambda r: r["time_s"],
            )
            if rs:
                ax.loglog(
                    [r["time_s"] for r in rs],
                    [max(r["err"], 1e-16) for r in rs],
                    fmt,
                    color=color[method],
                    ms=4,
                    label=method,
                )
        mc = [r for r in rows if r["scene"] == scene and r["method"] == "markov"]
        t = np.array([r["time_s"] for r in mc])
        ax.loglog(t, mc[0]["err"] * (t / t[0]) ** -0.5, "k:", lw=0.8, label="slope -1/2")
        ax.set_title(scene)
        ax.set_xlabel("run time [s]")
        ax.set_ylabel("max relative error of A/A0")
        ax.legend(fontsize=8)
    fig.savefig(out.with_suffix(".png"), dpi=110)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args(argv)
    rows = run(args.quick)
    out = HERE / "results" / "markov_work_precision"
    write(rows, out)
    print(out.with_suffix(".md").read_text())


if __name__ == "__main__":
    main()
