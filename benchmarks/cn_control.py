"""Does ``cn`` deliver the accuracy it is asked for, and at what cost?

For each scene of ``../shared/peers`` (realistic, extreme, ultra, lowH) and rtol in 1e-4, 1e-6,
1e-8: ``xpersson.engine.solve(method="cn")`` on the scene's output times, the actual error
(max relative error of A/A0 at 4 points per decade against the exact erf), error / rtol (the
target band is [0.05, 1]), the error estimate, the wall time and the peak memory of one load
(tracemalloc: numpy allocations).  Also a moving-wall case with a closed form (linear wall,
physics.md §2.2).

Run with one BLAS thread (the script sets OPENBLAS_NUM_THREADS=1 before numpy is imported):
``python benchmarks/cn_control.py [--quick]``; writes ``benchmarks/results/cn_control.md``.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
import tracemalloc  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

HERE = Path(__file__).resolve().parent
PEERS = HERE.parents[1] / "shared" / "peers"
sys.path.insert(0, str(PEERS))

import scene as S  # noqa: E402

from xpersson.engine import Wall, exact, solve  # noqa: E402

SCENES = ("realistic", "extreme", "ultra", "lowH")
RTOLS = (1e-4, 1e-6, 1e-8)


def measure(fn):
    """(result, CPU seconds, peak MB): process time of a second call (the machine is shared:
    CPU time, not wall time), peak of a traced third call."""
    fn()
    t0 = time.process_time()
    res = fn()
    t = time.process_time() - t0
    tracemalloc.start()
    fn()
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    return res, t, peak / 1e6


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="rtol 1e-4 and 1e-6 only")
    args = ap.parse_args(argv)
    rtols = RTOLS[:2] if args.quick else RTOLS
    rows = []
    for name in SCENES:
        sc = S.make_scene(name)
        tau = sc.tau(sc.zeta_out())
        for rtol in rtols:
            res, t, mb = measure(
                lambda tau=tau, sc=sc, rtol=rtol: solve(
                    tau, sc.p_bar, Wall.absorbing(0.0), None, method="cn", rtol=rtol
                )
            )
            err = S.curve_error(sc, res.area)
            est = float(np.max(res.error_estimate / np.maximum(res.area, 1e-300)))
            rows.append(
                (name, rtol, err, err / rtol, est, res.status, res.n_nodes, res.nsteps, t, mb)
            )
            print(
                f"{name:9s} rtol={rtol:.0e} err={err:.2e} err/rtol={err / rtol:7.3f} "
                f"est={est:.2e} {res.status} N={res.n_nodes} steps={res.nsteps} "
                f"cpu={t * 1e3:8.1f} ms peak={mb:7.1f} MB",
                flush=True,
            )
    p0, s0, c = 0.5, 0.2, 1.0
    tau = np.logspace(-3, 0, 13)
    ex = exact.linear_wall_area(tau, p0, s0, c)
    wall = Wall.absorbing(lambda t: -(s0 + c * t))  # a callable: no closed form for the engine
    for rtol in rtols:
        res, t, mb = measure(lambda rtol=rtol: solve(tau, p0, wall, method="cn", rtol=rtol))
        err = float(np.max(np.abs(res.area / ex - 1)))
        est = float(np.max(res.error_estimate / res.area))
        rows.append(
            ("moving", rtol, err, err / rtol, est, res.status, res.n_nodes, res.nsteps, t, mb)
        )
        print(
            f"moving    rtol={rtol:.0e} err={err:.2e} err/rtol={err / rtol:7.3f} est={est:.2e} "
            f"{res.status} N={res.n_nodes} steps={res.nsteps} cpu={t * 1e3:8.1f} ms "
            f"peak={mb:7.1f} MB",
            flush=True,
        )
    lines = [
        "# cn: accuracy delivered versus accuracy requested",
        "",
        "One load per row, `OPENBLAS_NUM_THREADS=1`, shared 2-core machine (CPU time of the "
        "process, as wall time varies with the other jobs). err: max relative error of A/A0 at "
        "4 points per decade; est: the engine's relative error estimate (max over zeta); "
        "steps: time steps over all grids; peak: tracemalloc peak of one solve.",
        "",
        "| scene | rtol | err | err/rtol | est | status | N | steps | CPU [ms] | peak [MB] |",
        "|---|---:|---:|---:|---:|---|---:|---:|---:|---:|",
    ]
    for r in rows:
        lines.append(
            f"| {r[0]} | {r[1]:.0e} | {r[2]:.2e} | {r[3]:.3f} | {r[4]:.2e} | {r[5]} | "
            f"{r[6]} | {r[7]} | {r[8] * 1e3:.1f} | {r[9]:.1f} |"
        )
    out = HERE / "results"
    out.mkdir(exist_ok=True)
    (out / "cn_control.md").write_text("\n".join(lines) + "\n")
    return rows


if __name__ == "__main__":
    main()
