"""A stacked sweep leaves Python's garbage collector as the user set it (issue 33: no
process-wide side effect from a library call)."""

from __future__ import annotations

import gc

import pytest
from xpersson_sweep_testlib import scene

import xpersson
from xpersson.pipeline import stacked

SPECTRUM_SCENE = scene(spectrum={"H": [0.6, 0.75, 0.9]}, analyses={"contact_area": {}})


@pytest.mark.fast_paths
@pytest.mark.parametrize("enabled", [True, False])
def test_stacked_block_runs_with_the_collector_as_set(monkeypatch, enabled):
    seen = []
    run = stacked.run_stacked
    monkeypatch.setattr(stacked, "run_stacked", lambda pts: seen.append(gc.isenabled()) or run(pts))
    was = gc.isenabled()
    (gc.enable if enabled else gc.disable)()
    try:
        xpersson.solve(SPECTRUM_SCENE)
        assert gc.isenabled() is enabled
    finally:
        (gc.enable if was else gc.disable)()
    assert seen and all(s is enabled for s in seen)  # the block ran stacked, collector untouched
