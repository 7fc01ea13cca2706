"""The measured-cost rule on every distributed scheduler, and the shared-memory return path."""

from __future__ import annotations

import math
import warnings

import pytest
import xarray as xr
from xpersson_sweep_testlib import scene

import xpersson
from xpersson.api import as_scene, expand
from xpersson.plugins import get_registry
from xpersson.sweep import schedule

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
