"""A LocalCluster whose workers are threads of this process (``processes=False``): the workers
write the sweep's large arrays into this process's own memory (no ``/dev/shm`` segment, no
copy), the result equals the serial one bit for bit, and the rule (``xpersson.sweep.schedule``)
uses its own threshold and no memory-bound rule for such workers."""

from __future__ import annotations

import math
import time
import warnings

import numpy as np
import pytest
import xarray as xr
from xpersson_sweep_testlib import scene

from xpersson.api import as_scene, expand
from xpersson.plugins import get_registry
from xpersson.sweep import _shm, filling, schedule
from xpersson.sweep.execute import solve_sweep

distributed = pytest.importorskip("distributed")

#: E x H, two loads: batched blocks, their rows written in place by the workers
STUDY = scene(
    material={"E": ["5 MPa", "10 MPa", "20 MPa", "40 MPa", "80 MPa"]},
    spectrum={"H": [0.6, 0.7, 0.8, 0.9]},
    load={"p0": ["1e4 Pa", "1e5 Pa"]},
)
#: H only, stacked blocks: rows copied into the arrays once by the worker
STACKED = scene(spectrum={"H": [0.6, 0.65, 0.7, 0.75, 0.8, 0.85]})


@pytest.fixture(scope="module")
def threads():
    """One LocalCluster of two single-thread workers in this process per module."""
    cluster = distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None, silence_logs=40
    )
    with distributed.Client(cluster) as c:
        yield c
    cluster.close()


def _plan(sc):
    return expand(as_scene(sc), get_registry())


def _equal(a: xr.Dataset, b: xr.Dataset) -> None:
    """Bitwise equal values and coordinates (attributes: timings differ)."""
    assert list(a.variables) == list(b.variables)
    for name in a.variables:
        assert a[name].dims == b[name].dims, name
        np.testing.assert_array_equal(a[name].values, b[name].values, err_msg=name, strict=True)


def test_in_process_is_told_from_the_workers_addresses(threads, client):
    assert _shm.in_process(threads)
    assert not _shm.in_process(client)  # worker processes (tests/sweep/conftest.py)
    assert not _shm.in_process("processes")
    assert schedule.threshold_s(threads) == schedule.IN_PROCESS_MIN_S
    assert schedule.threshold_s(client) == schedule.PARALLEL_MIN_S


@pytest.mark.parametrize(("sc", "chunk"), [(STUDY, 4), (STACKED, 2)])
def test_workers_write_into_this_process_arrays_and_equal_serial(threads, monkeypatch, sc, chunk):
    """No segment is created; the Dataset's large arrays are the ones the workers wrote into
    (the arrays :func:`_shm.share` handed out), released after the run."""

    def no_segment(size):
        raise AssertionError("a /dev/shm segment for workers in this process")

    handed: list[dict] = []
    share = _shm.share

    def record(*args, **kwargs):
        got = share(*args, **kwargs)
        handed.append(got)
        return got

    monkeypatch.setattr(_shm, "_create", no_segment)
    monkeypatch.setattr("xpersson.sweep.execute.share", record)
    plan = _plan(sc)
    serial = solve_sweep(plan, None)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        par = solve_sweep(plan, None, scheduler=threads, chunk=chunk, shm_bytes=2000)
    _equal(serial, par)
    assert "xpersson_scheduler" not in par.attrs  # it ran on the workers
    assert handed and handed[0] and "area_fraction" in handed[0]
    for name, arr in handed[0].items():  # no copy: the Dataset wraps the workers' arrays
        if par[name].dims[: len(plan.dims)] == tuple(plan.dims):  # (not reduced by finish)
            assert np.shares_memory(par[name].values, arr), name
    for _ in range(50):  # released without waiting: polled
        if not any(got[1] is handed[0] for got in _shm._ATTACHED.values()):
            break
        time.sleep(0.02)
    assert not any(got[1] is handed[0] for got in _shm._ATTACHED.values())


def test_the_rule_has_no_memory_bound_limit_for_workers_in_this_process(threads):
    plan = _plan(STUDY)
    est = 2 * schedule.IN_PROCESS_MIN_S
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no warning: it goes to the workers
        assert not schedule.too_small_for_a_cluster(plan, est, threads, nbytes=1e6 * est * 1e6)
    with pytest.warns(UserWarning, match="takes serially"):
        assert schedule.too_small_for_a_cluster(plan, 0.5 * schedule.IN_PROCESS_MIN_S, threads)


def test_a_probed_study_on_threads_reuses_the_probe_and_equals_serial(threads, monkeypatch):
    """Through the rule (its threshold lowered here): the probe's blocks are filled here, the
    workers' blocks arrive with their large variables written in place ("shm")."""
    monkeypatch.setattr(schedule, "IN_PROCESS_MIN_S", 0.0)
    monkeypatch.setattr(schedule, "BLOCK_CURVES", 8)  # blocks of 4 points x 2 loads
    monkeypatch.setattr(schedule, "SERIAL_BLOCK_POINTS", 8)
    moved, add = [], filling.Filling.add

    def record(self, res, written=()):
        if res.dataset is not None:
            moved.append((res.block.number, dict(written) if isinstance(written, dict) else {}))
        return add(self, res, written)

    monkeypatch.setattr(filling.Filling, "add", record)
    plan = _plan(STUDY)
    serial = solve_sweep(plan, None)
    moved.clear()
    par = solve_sweep(plan, None, scheduler=threads, shm_bytes=2000)
    _equal(serial, par)
    assert "xpersson_scheduler" not in par.attrs
    from_workers = [m for number, m in moved if number > 1]
    assert from_workers and all(m.get("area_fraction") == "shm" for m in from_workers)
    assert math.isfinite(par["area_fraction"].values.sum())
