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


def test_the_probe_counts_the_first_block_once_and_the_rest_at_the_second_rate(monkeypatch):
    """Block 0 (with the first point's one-off costs) as it cost, the other points at the rate
    of block 1; a fake clock advances 5 s for block 0 and 1 s per point after it."""
    from xpersson.sweep import probe as probe_mod

    clock = [0.0]
    real = probe_mod.run_block

    def run_block(block, points, registry, **kw):
        clock[0] += 5.0 if block.number == 0 else float(block.size)
        return real(block, points, registry, **kw)

    monkeypatch.setattr(probe_mod.time, "process_time", lambda: clock[0])
    monkeypatch.setattr(probe_mod, "run_block", run_block)
    H = [0.6 + 0.02 * k for k in range(12)]
    plan = expand(as_scene(scene(spectrum={"H": H})), None)
    got = probe_mod.probe(plan, get_registry())
    assert [r.block.size for r in got.results] == [probe_mod.PROBE_POINTS] * 2
    assert got.estimate == 5.0 + (12 - 4) * 1.0  # not 12 * 5 / 4
    one = probe_mod.probe(plan, get_registry(), points=1)  # a layout probe: one block
    assert [r.block.size for r in one.results] == [1]


def test_a_study_that_falls_back_here_does_not_solve_the_probe_blocks_again(monkeypatch):
    """An E x H study given a client below the threshold: the probe's two blocks are the first
    two of the serial layout; each block of the sweep is solved once."""
    from xpersson.sweep import blocks as blocks_mod
    from xpersson.sweep import execute
    from xpersson.sweep import probe as probe_mod

    solved = []
    real = blocks_mod.run_block

    def counting(block, *args, **kwargs):
        solved.append((block.start, block.stop))
        return real(block, *args, **kwargs)

    monkeypatch.setattr(probe_mod, "run_block", counting)
    monkeypatch.setattr(execute, "run_block", counting)
    monkeypatch.setattr(schedule, "BLOCK_CURVES", 6)  # serial blocks of 3 points x 2 loads
    monkeypatch.setattr(schedule, "SERIAL_BLOCK_POINTS", 6)
    sc = scene(
        material={"E": ["5 MPa", "10 MPa", "20 MPa"]},
        spectrum={"H": [0.6, 0.7, 0.8]},
        load={"p0": ["1e4 Pa", "1e5 Pa"]},
    )
    with pytest.warns(xpersson.XperssonWarning, match="solving it in this process"):
        got = xpersson.solve(sc, scheduler=Client())
    assert sorted(solved) == sorted(set(solved)) and len(solved) == 3  # 3 blocks, once each
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        serial = xpersson.solve(sc)
    xr.testing.assert_identical(got.drop_attrs(), serial.drop_attrs())
