"""Safe-write campaign (not in CI): SIGKILL at random moments during large writes, and rounds
of parallel writers racing for one new path.

    python benchmarks/kill_writes.py --kills 100 --races 50

Prints the counts: kills that landed mid-write, targets left partial (must be 0), temporaries
left after the next write (must be 0), races with other than exactly one winner (must be 0).
"""

from __future__ import annotations

import argparse
import json
import multiprocessing as mp
import os
import random
import signal
import tempfile
import time
from pathlib import Path

import numpy as np
import xarray as xr

from xpersson import io

_FORK = mp.get_context("fork")


def _child(target: str, overwrite: bool, rows: int, conn) -> None:  # pragma: no cover
    ds = xr.Dataset({"x": (("a", "b"), np.arange(rows * 1000, dtype=float).reshape(rows, 1000))})
    ds.attrs["checksum"] = float(ds["x"].sum())
    conn.send("ready")
    conn.recv()
    try:
        io.to_netcdf(ds, target, overwrite=overwrite)
    except FileExistsError:
        os._exit(17)
    os._exit(0)


def _writer(target: Path, overwrite: bool, rows: int):
    conn, child = _FORK.Pipe()
    proc = _FORK.Process(target=_child, args=(str(target), overwrite, rows, child))
    proc.start()
    assert conn.recv() == "ready"
    return proc, conn


def _whole(path: Path, rows: int) -> bool:
    ds = io.open_dataset(path)
    return float(ds["x"].sum()) == ds.attrs["checksum"] and ds["x"].shape == (rows, 1000)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--kills", type=int, default=100)
    ap.add_argument("--races", type=int, default=50)
    ap.add_argument("--rows", type=int, default=4000, help="1000-double rows (4000: 32 MB)")
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    rng = random.Random(args.seed)
    out = {
        "kills_attempted": args.kills,
        "killed_mid_write": 0,
        "partial_targets": 0,
        "temporaries_left_by_kills": 0,
        "temporaries_after_next_write": 0,
        "races": args.races,
        "races_not_exactly_one_winner": 0,
        "temporaries_after_races": 0,
    }
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        proc, conn = _writer(folder / "probe.nc", False, args.rows)
        t0 = time.perf_counter()
        conn.send("go")
        proc.join()
        duration = time.perf_counter() - t0
        out["write_duration_s"] = round(duration, 3)
        for i in range(args.kills):
            target = folder / f"k{i % 5}.nc"
            proc, conn = _writer(target, True, args.rows)
            conn.send("go")
            time.sleep(rng.uniform(0.0, duration))
            if proc.exitcode is None:
                os.kill(proc.pid, signal.SIGKILL)
                out["killed_mid_write"] += 1
            proc.join()
            if target.exists() and not _whole(target, args.rows):
                out["partial_targets"] += 1
        out["temporaries_left_by_kills"] = len(list(folder.glob(".*.part")))
        small = xr.Dataset({"x": ("a", np.zeros(3))})
        for i in range(5):
            io.to_netcdf(small, folder / f"k{i}.nc", overwrite=True)
        out["temporaries_after_next_write"] = len(list(folder.glob(".*.part")))
        for r in range(args.races):
            target = folder / f"race{r}.nc"
            writers = [_writer(target, False, 200) for _ in range(4)]
            for _, c in writers:
                c.send("go")
            codes = []
            for p, _ in writers:
                p.join()
                codes.append(p.exitcode)
            if codes.count(0) != 1 or codes.count(17) != 3:
                out["races_not_exactly_one_winner"] += 1
        out["temporaries_after_races"] = len(list(folder.glob(".*.part")))
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
