"""Safe archive writes: SIGKILL at random moments, parallel writers, stale temporaries, umask."""

from __future__ import annotations

import multiprocessing as mp
import os
import random
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from xpersson import archive, io

pytestmark = pytest.mark.skipif(os.name != "posix", reason="POSIX signals and file modes")

ROWS = 2000  # 2000 x 1000 doubles = 16 MB
_FORK = mp.get_context("fork")  # children start at once (xarray already imported)


def _child(target: str, overwrite: bool, rows: int, conn) -> None:
    ds = xr.Dataset({"x": (("a", "b"), np.arange(rows * 1000, dtype=float).reshape(rows, 1000))})
    ds.attrs["checksum"] = float(ds["x"].sum())
    conn.send("ready")
    conn.recv()  # go
    try:
        io.to_netcdf(ds, target, overwrite=overwrite)
    except FileExistsError:
        os._exit(17)
    os._exit(0)


class _Writer:
    """A forked writer process: built its Dataset, waits for ``go()``."""

    def __init__(self, target: Path, overwrite: bool, rows: int = ROWS) -> None:
        self.conn, child_conn = _FORK.Pipe()
        self.proc = _FORK.Process(target=_child, args=(str(target), overwrite, rows, child_conn))
        self.proc.start()
        assert self.conn.recv() == "ready"

    def go(self) -> None:
        self.conn.send("go")

    def wait(self) -> int:
        self.proc.join(timeout=60)
        return self.proc.exitcode


def _whole(path: Path) -> bool:
    ds = io.open_dataset(path)
    return float(ds["x"].sum()) == ds.attrs["checksum"] and ds["x"].shape == (ROWS, 1000)


def _temporaries(folder: Path) -> list[Path]:
    return sorted(folder.glob(".*.part"))


def test_sigkill_at_random_moments_leaves_target_absent_or_whole(tmp_path):
    rng = random.Random(20261123)
    # time one uninterrupted write to spread the kills over it
    probe = _Writer(tmp_path / "probe.nc", False)
    t0 = time.perf_counter()
    probe.go()
    assert probe.wait() == 0
    duration = time.perf_counter() - t0
    assert _whole(tmp_path / "probe.nc")

    targets = [tmp_path / f"k{i}.nc" for i in range(6)]
    for t in targets[::2]:  # an overwrite of a whole archive must keep it whole
        os.link(tmp_path / "probe.nc", t)
    killed = attempts = 0
    while killed < len(targets) and attempts < 3 * len(targets):
        t = targets[attempts % len(targets)]
        attempts += 1
        writer = _Writer(t, True)
        writer.go()
        time.sleep(rng.uniform(0.0, 0.9 * duration))
        if writer.proc.exitcode is None:
            os.kill(writer.proc.pid, signal.SIGKILL)
            killed += 1
        writer.wait()
        assert not t.exists() or _whole(t), f"{t.name} is partial"
    assert killed >= 3, f"only {killed} of {attempts} writers were killed mid-write"
    assert _temporaries(tmp_path), "the killed writers left no temporary (kills too late?)"
    # the next write to each target removes what the killed writers left behind
    small = xr.Dataset({"x": (("a", "b"), np.zeros((2, 1000)))}, attrs={"checksum": 0.0})
    for t in targets:
        io.to_netcdf(small, t, overwrite=True)
    assert _temporaries(tmp_path) == []


def test_parallel_writers_without_overwrite_exactly_one_succeeds(tmp_path):
    target = tmp_path / "race.nc"
    writers = [_Writer(target, False, rows=200) for _ in range(4)]
    for w in writers:
        w.go()
    codes = sorted(w.wait() for w in writers)
    assert codes.count(0) == 1, codes
    assert codes.count(17) == 3, codes  # the others: FileExistsError, nothing replaced
    ds = io.open_dataset(target)
    assert float(ds["x"].sum()) == ds.attrs["checksum"]
    assert _temporaries(tmp_path) == []


def _small() -> xr.Dataset:
    return xr.Dataset({"x": ("a", np.arange(3.0))})


def test_existing_target_is_refused_and_kept(tmp_path):
    target = tmp_path / "a.nc"
    io.to_netcdf(_small(), target)
    before = target.read_bytes()
    with pytest.raises(FileExistsError, match="overwrite"):
        io.to_netcdf(_small() * 2, target)
    assert target.read_bytes() == before
    assert _temporaries(tmp_path) == []


@pytest.mark.parametrize("umask", [0o022, 0o027, 0o077, 0o002])
def test_file_mode_follows_the_umask(tmp_path, umask):
    old = os.umask(umask)
    try:
        path = io.to_netcdf(_small(), tmp_path / "m.nc")
    finally:
        os.umask(old)
    assert path.stat().st_mode & 0o777 == 0o666 & ~umask


def _dead_pid() -> int:
    proc = subprocess.Popen([sys.executable, "-c", "pass"])
    proc.wait()
    return proc.pid


def test_stale_temporary_of_a_dead_writer_is_removed(tmp_path):
    host = archive.socket.gethostname().replace(".", "_")
    stale = tmp_path / f".t.nc.{host}.{_dead_pid()}.0badc0de.part"
    stale.write_bytes(b"\0" * 1000)
    other = tmp_path / f".other.nc.{host}.{_dead_pid()}.0badc0de.part"  # another target's
    other.write_bytes(b"")
    io.to_netcdf(_small(), tmp_path / "t.nc")
    assert not stale.exists()
    assert other.exists()


def test_live_writers_temporary_is_never_removed(tmp_path):
    """A temporary whose writer still runs (this process) and holds its lock stays."""
    target = tmp_path / "t.nc"
    tmp, fd = archive._create_temporary(target)
    try:
        assert io.stale_temporaries(target) == []
        io.to_netcdf(_small(), target)  # a second writer, same target
        assert tmp.exists()
        # even when old: the lock shows the writer is alive
        os.utime(tmp, (time.time() - 7200, time.time() - 7200))
        assert io.stale_temporaries(target) == []
    finally:
        os.close(fd)
        tmp.unlink()
