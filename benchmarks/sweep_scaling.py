"""Throughput of a parameter study: 1e4 area curves (50 zeta each), serial vs 2 processes.

Run:  OPENBLAS_NUM_THREADS=1 python benchmarks/sweep_scaling.py [--points 200] [--loads 50]
One process measures, in the same run: (a) the serial scheduler, (b) a dask.distributed
LocalCluster with 2 single-threaded worker processes (started and warmed up before timing;
its start-up time is reported separately). The sweep is E (20 values) x H (10 values) x
p0 (50 loads) on the physics.md §1.4 surface, with the contact_area analysis. Each is timed
three times; the best time counts. The serial and parallel Datasets are checked to be equal.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np
import xarray as xr

import xpersson


def scene(n_e: int, n_h: int, loads: int) -> dict:
    return {
        "spectrum": {"model": "self_affine", "H": {"start": 0.5, "stop": 0.95, "num": n_h,
                                                   "spacing": "linear"},
                     "q_L": "1e3 1/m", "q_r": "1e4 1/m", "q_1": "1e8 1/m", "h_rms": "1 um"},
        "material": {"E": {"start": "1 MPa", "stop": "100 MPa", "num": n_e}, "nu": 0.5},
        "load": {"p0": {"start": "1 kPa", "stop": "1 MPa", "num": loads}},
        "output": {"zeta": [float(z) for z in np.geomspace(1.0, 1e5, 50)]},
        "analyses": {"contact_area": {}},
    }


def best(fn, repeats: int = 3) -> tuple[xr.Dataset, float]:
    out, times = None, []
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return out, min(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--n-e", type=int, default=20)
    ap.add_argument("--n-h", type=int, default=10)
    ap.add_argument("--loads", type=int, default=50)
    ap.add_argument("--chunk", type=int, default=None,
                    help="sweep points per task (default: the scheduler's choice)")
    args = ap.parse_args()
    sc = scene(args.n_e, args.n_h, args.loads)
    curves = args.n_e * args.n_h * args.loads
    from distributed import Client, LocalCluster

    serial, t_serial = best(lambda: xpersson.solve(sc))
    t0 = time.perf_counter()
    cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                           dashboard_address=None, silence_logs=40)
    client = Client(cluster)
    t_start = time.perf_counter() - t0
    xpersson.solve(scene(2, 2, 2), scheduler=client)  # warm up: imports on the workers
    par, t_par = best(lambda: xpersson.solve(sc, scheduler=client, chunk=args.chunk))
    client.close()
    cluster.close()
    same = all(serial[v].equals(par[v])
               for v in serial.data_vars)
    print(f"OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS')}, "
          f"{os.cpu_count()} cores; {curves} area curves x {serial.sizes['zeta']} zeta "
          f"({args.n_e * args.n_h} sweep points x {args.loads} loads; chunk {args.chunk})")
    print("| scheduler | time [s] | curves / minute | speed-up |")
    print("|---|---:|---:|---:|")
    print(f"| serial | {t_serial:.2f} | {curves / t_serial * 60:,.0f} | 1.00x |")
    print(f"| processes (LocalCluster, 2 workers) | {t_par:.2f} | {curves / t_par * 60:,.0f} | "
          f"{t_serial / t_par:.2f}x |")
    print(f"cluster start-up (not timed above): {t_start:.1f} s; serial == parallel bit for "
          f"bit: {same}")


if __name__ == "__main__":
    main()
