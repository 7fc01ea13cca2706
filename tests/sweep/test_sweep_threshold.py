"""The measured-cost rule on every distributed scheduler, and the shared-memory return path."""

from __future__ import annotations

import math
import os
import warnings

import numpy as np
import pytest
import xarray as xr
from xpersson_sweep_testlib import scene

import xpersson
from xpersson.api import as_scene, expand
from xpersson.plugins import get_registry
from xpersson.sweep import _shm, schedule
from xpersson.sweep.stacking import Block, BlockResult

SMALL = scene(material={"E": ["5 MPa", "20 MPa"]}, load={"p0": "3e4 Pa"})
SMALL_PLAN = expand(as_scene(SMALL), get_registry())


class _Scheduler:
    address = "tcp://10.0.0.9:8786"


class Client:  # named as distributed's: accepted as a scheduler, never contacted below
    scheduler = _Scheduler()

    def submit(self, *args, **kwargs):
        raise AssertionError("a study below the threshold was sent to the workers")


def test_threshold_is_the_stated_constants():
    assert schedule.threshold_s(Client()) == schedule.PARALLEL_MIN_S
    assert schedule.threshold_s("tcp://h:8786") == schedule.PARALLEL_MIN_S
    assert schedule.threshold_s("processes") == (
        schedule.PARALLEL_MIN_S + schedule.CLUSTER_STARTUP_S
    )


def test_a_small_study_given_a_client_runs_here_and_says_so():
    with pytest.warns(xpersson.XperssonWarning, match=r"tcp://10\.0\.0\.9:8786: sending the work"):
        got = xpersson.solve(SMALL, scheduler=Client())
    assert got.attrs["xpersson_scheduler"] == (
        "serial (asked: tcp://10.0.0.9:8786; the workers would not pay for this study)"
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        serial = xpersson.solve(SMALL)
    xr.testing.assert_identical(got.drop_attrs(), serial.drop_attrs())


def test_a_memory_bound_study_runs_here_at_any_size():
    with pytest.warns(xpersson.XperssonWarning, match="memory-bound"):
        assert schedule.too_small_for_a_cluster(SMALL_PLAN, 100.0, Client(), nbytes=2e10)
    assert not schedule.too_small_for_a_cluster(SMALL_PLAN, 100.0, Client(), nbytes=1e9)


def test_above_the_threshold_the_client_is_used(monkeypatch):
    from xpersson.sweep import execute

    def used(scheduler, workers):
        raise AssertionError(f"sent to the workers of {scheduler.scheduler.address}")

    monkeypatch.setattr(schedule, "PARALLEL_MIN_S", 0.0)
    monkeypatch.setattr(schedule, "MEMORY_BOUND_RATE", math.inf)
    monkeypatch.setattr(execute, "client_for", used)
    with pytest.raises(AssertionError, match="sent to the workers of tcp://10.0.0.9:8786"):
        xpersson.solve(SMALL, scheduler=Client())


def _block(n: int) -> BlockResult:
    rng = np.random.default_rng(1)
    ds = xr.Dataset(
        {
            "small": ("E", np.arange(n, dtype=float), {"units": "1"}),
            "big": (("E", "zeta"), rng.random((n, 1100)), {"units": "Pa"}),
            "last": (("E", "zeta"), rng.random((n, 1100)).astype(np.float32)),
        },
        coords={"E": ("E", np.linspace(1e6, 1e7, n), {"units": "Pa"}), "zeta": np.arange(1100)},
        attrs={"title": "block"},
    )
    block = Block(0, (0,), (0,), (n,), ("E",), {})
    return BlockResult(block, ds, None, np.zeros(n, np.int8), {})


@pytest.mark.skipif(not os.access(_shm.SHM, os.W_OK), reason="no POSIX shared memory")
def test_shared_memory_round_trip_is_identical_and_leaves_nothing():
    res = _block(130)  # "big": 1.1 MiB, through shared memory; "small", "last": through dask
    want = res.dataset.copy(deep=True)
    packed, moved = _shm.pack(res)
    assert list(moved) == ["big"] and "big" not in packed.dataset
    assert all(os.path.exists(m[0]) for m in moved.values())
    got = _shm.unpack(packed, moved).dataset
    xr.testing.assert_identical(got, want)
    assert list(got.data_vars) == list(want.data_vars)
    assert not any(os.path.exists(m[0]) for m in moved.values())
