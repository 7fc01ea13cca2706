"""Local dask workers write the sweep's large output arrays in place, in shared memory
(``xpersson.sweep._shm``): the result equals the serial one bit for bit, the arrays are the
shared mapping itself, and no segment is ever left in ``/dev/shm`` (a failed run included)."""

from __future__ import annotations

import mmap
import os
import subprocess
import sys
import time
import warnings

import numpy as np
import pytest
import xarray as xr
from xpersson_sweep_testlib import scene

from xpersson.api import as_scene, expand
from xpersson.plugins import get_registry
from xpersson.sweep import _shm, filling
from xpersson.sweep.execute import solve_sweep

distributed = pytest.importorskip("distributed")
pytestmark = pytest.mark.skipif(not os.access(_shm.SHM, os.W_OK), reason="no POSIX shared memory")

#: E x H, two loads: batched blocks (rows written in place) on two worker processes
STUDY = scene(
    material={"E": ["5 MPa", "10 MPa", "20 MPa", "40 MPa", "80 MPa"]},
    spectrum={"H": [0.6, 0.7, 0.8, 0.9]},
    load={"p0": ["1e4 Pa", "1e5 Pa"]},
)
#: H only, stacked blocks: rows copied into the arrays once by the worker
STACKED = scene(spectrum={"H": [0.6, 0.65, 0.7, 0.75, 0.8, 0.85]})


def _plan(sc):
    return expand(as_scene(sc), get_registry())


def _segments() -> list[str]:
    return [n for n in os.listdir(_shm.SHM) if n.startswith(_shm._PREFIX)]


def _in_shared_memory(a: np.ndarray) -> bool:
    """Whether the array's memory is a mapping (of the run's shared segment)."""
    while isinstance(a, np.ndarray):
        a = a.base
    return isinstance(getattr(a, "obj", a), mmap.mmap)


def _dropped(client) -> bool:
    """Whether every worker dropped its mappings (released without waiting: polled)."""
    for _ in range(50):
        if sum(client.run(lambda: len(_shm._ATTACHED)).values()) == 0:
            return True
        time.sleep(0.02)
    return False


def _equal(a: xr.Dataset, b: xr.Dataset) -> None:
    """Bitwise equal values and coordinates (attributes: timings differ)."""
    assert list(a.variables) == list(b.variables)
    for name in a.variables:
        assert a[name].dims == b[name].dims, name
        np.testing.assert_array_equal(a[name].values, b[name].values, err_msg=name, strict=True)


@pytest.mark.parametrize(("sc", "chunk"), [(STUDY, 4), (STACKED, 2)])
def test_large_variables_come_through_shared_memory_and_equal_serial(client, sc, chunk):
    plan = _plan(sc)
    serial = solve_sweep(plan, None)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        par = solve_sweep(plan, None, scheduler=client, chunk=chunk, shm_bytes=2000)
    _equal(serial, par)
    big = [n for n, v in serial.data_vars.items() if v.nbytes >= 2000 and v.dims[:1] == ("H",)]
    assert "area_fraction" in big
    for name in big:  # the client's arrays are the shared mapping the workers wrote into
        assert _in_shared_memory(par[name].values), name
    assert not _in_shared_memory(par["point_status"].values)  # below the threshold
    assert _segments() == []
    assert _dropped(client)  # the workers' mappings


def test_probed_study_reuses_the_probe_and_sends_no_rows_every_point_shares(client, monkeypatch):
    """On the workers (the threshold rule switched off here) the probe's two blocks are the
    layout's first two (filled here, not solved again); load_balance, the same row at every
    point of the probe, is not shared: the workers' blocks, whose points hold that row again,
    send nothing of it."""
    from xpersson.sweep import schedule

    monkeypatch.setattr(schedule, "PARALLEL_MIN_S", 0.0)
    monkeypatch.setattr(schedule, "MEMORY_BOUND_RATE", float("inf"))
    monkeypatch.setattr(schedule, "BLOCK_CURVES", 8)  # blocks of 4 points x 2 loads
    monkeypatch.setattr(schedule, "SERIAL_BLOCK_POINTS", 8)
    moved, add = [], filling.Filling.add

    def record(self, res, written=()):
        if res.dataset is not None:  # (finish adds every result again: nothing to fill)
            moved.append((res.block.number, dict(written) if isinstance(written, dict) else {}))
        return add(self, res, written)

    monkeypatch.setattr(filling.Filling, "add", record)
    plan = _plan(STUDY)
    serial = solve_sweep(plan, None)
    moved.clear()
    par = solve_sweep(plan, None, scheduler=client, shm_bytes=2000)
    _equal(serial, par)
    assert "xpersson_scheduler" not in par.attrs  # it ran on the workers
    assert _in_shared_memory(par["area_fraction"].values)
    from_workers = [m for number, m in moved if number > 1]  # blocks 0, 1: the probe's
    assert from_workers and sorted(number for number, _ in moved)[:2] == [0, 1]
    assert all(m["area_fraction"] == "shm" and m["load_balance"] == "same" for m in from_workers)
    assert par["load_balance"].dims == ("p0", "zeta")  # the same at every point: reduced
    assert _segments() == []
    assert _dropped(client)


def test_a_failed_run_leaves_no_segment_and_no_mapping(client, monkeypatch):
    seen = []

    def fail(self, res, written=()):
        seen.append((list(written), _segments()))  # mid-run: the segment has no name already
        raise RuntimeError("the client failed while reading the blocks")

    monkeypatch.setattr(filling.Filling, "add", fail)
    with pytest.raises(RuntimeError, match="the client failed"):
        solve_sweep(_plan(STUDY), None, scheduler=client, chunk=4, shm_bytes=2000)
    assert seen and "area_fraction" in seen[0][0] and seen[0][1] == []
    assert _segments() == []
    assert _dropped(client)


def test_a_segment_of_a_killed_client_is_removed_by_the_next_run():
    gone = subprocess.run(
        [sys.executable, "-c", "import os; print(os.getpid())"],
        capture_output=True,
        text=True,
        check=True,
    )
    path = os.path.join(_shm.SHM, f"{_shm._PREFIX}{int(gone.stdout)}-leftover")
    mine = os.path.join(_shm.SHM, f"{_shm._PREFIX}{os.getpid()}-alive")
    for p in (path, mine):
        with open(p, "wb") as f:
            f.write(b"x")
    try:
        _shm._remove_orphans()
        assert not os.path.exists(path) and os.path.exists(mine)
        # a worker drops the mappings of runs whose client is gone when it maps a new one
        _shm._ATTACHED["stale"] = (None, {}, {"client": int(gone.stdout)})
        assert _shm._attach("new", mine, {}, {}, _shm.machine(), {})
        assert "stale" not in _shm._ATTACHED and "new" in _shm._ATTACHED
    finally:
        _shm._ATTACHED.pop("new", None)
        for p in (path, mine):
            if os.path.exists(p):
                os.unlink(p)
