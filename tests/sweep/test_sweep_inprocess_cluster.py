"""A LocalCluster whose workers are threads of this process (``processes=False``): the workers
write the sweep's large arrays into this process's own memory (no ``/dev/shm`` segment, no
copy), the result equals the serial one bit for bit; and a memory-bound study given workers on
this machine runs on their number of threads in this process (``xpersson.sweep.schedule``)."""

from __future__ import annotations

import threading
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


def test_threads_here_are_the_local_workers_threads(threads, client):
    class Remote:  # a client of a scheduler elsewhere: this machine's cores are not its workers'
        def scheduler_info(self):
            return {"workers": {"tcp://10.0.0.9:1": {"nthreads": 8}}}

    assert schedule.here_threads(threads) == 2
    assert schedule.here_threads(client) == 2  # a LocalCluster of 2 processes
    assert schedule.here_threads("processes", 3) == 3
    assert schedule.here_threads(Remote()) == 1
    assert schedule.here_threads("tcp://10.0.0.9:8786") == 1


def test_run_here_uses_threads_only_for_a_long_enough_memory_bound_study(client):
    rate, least = schedule.MEMORY_BOUND_RATE, schedule.THREADS_MIN_S
    bound = 2 * rate * 2 * least  # bytes of a memory-bound study of 2 * least seconds
    assert schedule.run_here(client, 2 * least, bound) == ("threads", 2)
    assert schedule.run_here(client, 0.5 * least, bound * 0.25) == (None, 1)  # too short
    assert schedule.run_here(client, 2 * least, 0.5 * rate * 2 * least) == (None, 1)  # CPU-bound
    assert schedule.run_here("tcp://10.0.0.9:8786", 2 * least, bound) == (None, 1)


@pytest.mark.fast_paths
def test_a_memory_bound_study_given_local_workers_runs_on_threads_here(client, monkeypatch):
    """Through the rule (the small study made memory-bound here): solved on 2 threads of this
    process, its batched rows written in place into the sweep's arrays from those threads,
    bitwise the serial result; the attribute says where it ran."""
    from xpersson.sweep import execute

    def no_workers(*args, **kwargs):
        raise AssertionError("a memory-bound study was sent to the workers")

    monkeypatch.setattr(execute, "run_on_workers", no_workers)
    monkeypatch.setattr(schedule, "MEMORY_BOUND_RATE", 1.0)
    monkeypatch.setattr(schedule, "THREADS_MIN_S", 0.0)
    monkeypatch.setattr(schedule, "BLOCK_CURVES", 8)  # blocks of 4 points x 2 loads
    monkeypatch.setattr(schedule, "SERIAL_BLOCK_POINTS", 8)
    in_place, rows = [], filling.Filling.rows
    main = threading.get_ident()

    def record(self, name, block, point_shape, dtype):
        got = rows(self, name, block, point_shape, dtype)
        if threading.get_ident() != main and name == "area_fraction":
            in_place.append(got is not None)
        return got

    monkeypatch.setattr(filling.Filling, "rows", record)
    plan = _plan(STUDY)
    serial = solve_sweep(plan, None)
    with pytest.warns(UserWarning, match="memory-bound.*solving it in this process on 2 threads"):
        par = solve_sweep(plan, None, scheduler=client)
    _equal(serial, par)
    assert par.attrs["xpersson_scheduler"].startswith("threads (2) (asked: tcp://")
    assert in_place and all(in_place)  # every block after the probe's, from a pool thread


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


def test_a_cpu_bound_study_is_not_sent_to_workers_that_are_threads_of_this_process(threads, client):
    """Above the threshold and not memory-bound, the study goes to worker processes but not to
    dask's threads of this process (its Python holds the GIL there), said in the warning."""
    plan = _plan(STUDY)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no warning: to the workers
        assert not schedule.too_small_for_a_cluster(plan, 100.0, client, nbytes=1e3)
    with pytest.warns(UserWarning, match="threads of this process.*GIL.*in this process\\."):
        assert schedule.too_small_for_a_cluster(plan, 100.0, threads, nbytes=1e3)
