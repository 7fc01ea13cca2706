"""Tests of the example plugin, written exactly as an outside plugin author would.

The ``xpersson_*`` fixtures come from xpersson's pytest plugin (the ``pytest11`` entry point
``xpersson``), active wherever xpersson is installed.
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

import xpersson
from xpersson.plugins import get_registry
from xpersson.testing import check_plugin, tiny_scene
from xpersson_example.offset_wall import OffsetWall

SCENE_S = 2e4  # Pa


def test_contract():
    """Metadata, cheap import, pickling, determinism, engine probability balance."""
    report = check_plugin(OffsetWall)
    assert report["engine"].startswith("ok (probability balance")


def test_listed_without_import():
    code = (
        "import sys\n"
        "from xpersson.plugins import get_registry\n"
        "info = get_registry().info('boundaries', 'offset_wall')\n"
        "assert info.dist == 'xpersson-example', info\n"
        "assert info.status == 'not loaded', info.status\n"
        "assert 'xpersson_example.offset_wall' not in sys.modules\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr


def test_cli_lists_the_plugin():
    proc = subprocess.run(
        [sys.executable, "-m", "xpersson.cli_plugins", "list", "--group", "boundaries"],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 0, proc.stderr
    row = next(line for line in proc.stdout.splitlines() if "offset_wall" in line)
    assert row.split()[:4] == ["boundaries", "offset_wall", "xpersson-example", "0.1.0"]


def test_scene_by_name_matches_the_exact_solution(xpersson_oracles):
    wall = {"boundary": {"model": "offset_wall", "s": f"{SCENE_S} Pa"}}
    ds = xpersson.solve(tiny_scene(scene=wall))
    p0 = ds["p0"].values[:, None]
    tau = ds["diffusion_time"].values[None, :]
    area = xpersson_oracles.constant_wall_area(p0, SCENE_S, tau)
    np.testing.assert_allclose(ds["area_fraction"].values, area, rtol=1e-6, atol=1e-12)
    np.testing.assert_allclose(ds["detached_fraction"].values, 1 - area, rtol=1e-5, atol=1e-9)
    excess = xpersson_oracles.constant_wall_load(p0, SCENE_S, tau) - p0
    np.testing.assert_allclose(ds["adhesive_load_excess"].values, excess, rtol=1e-5, atol=1e-6)
    if "load" in ds:
        np.testing.assert_allclose(ds["load"].values, p0 + excess, rtol=1e-6)
    # adhesion keeps more area in contact than the elastic wall
    elastic = xpersson.solve(tiny_scene())
    assert np.all(ds["area_fraction"].values[:, -1] > elastic["area_fraction"].values[:, -1])


def test_archive_records_the_plugin(xpersson_tiny_scene):
    import json

    sc = xpersson_tiny_scene
    sc["boundary"] = {"model": "offset_wall", "s": "1 kPa"}
    ds = xpersson.solve(sc)
    used = json.loads(ds.attrs["xpersson_plugins"])
    entry = next(p for p in used if p["group"] == "boundaries")
    assert entry["name"] == "offset_wall"
    assert entry["distribution"] == "xpersson-example"
    assert "10.1016/j.surfrep.2006.04.001" in entry["references"]


def test_out_of_range_parameter_is_refused(xpersson_tiny_scene):
    sc = xpersson_tiny_scene
    sc["boundary"] = {"model": "offset_wall", "s": "-1 kPa"}
    with pytest.raises(ValueError, match="boundary.s"):
        xpersson.solve(sc)


def test_registry_knows_version():
    info = get_registry().info("boundaries", "offset_wall")
    assert info.version == "0.1.0"
