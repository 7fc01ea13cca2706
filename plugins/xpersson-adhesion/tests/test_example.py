"""The bundled example scene (PDMS-like elastomer on rough glass) and its comparison script."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def test_example_scene_adhesion_raises_the_area_at_every_load(solve):
    ds = solve(EXAMPLES / "pdms_on_glass.toml", output__zeta_per_decade=2)
    assert ds.attrs["status"] == "success"
    area = ds["area_fraction"].isel(zeta=-1).values
    p0 = ds["p0"].values
    assert p0[0] < 0 < p0[-1]  # tensile to compressive
    assert np.all(np.diff(area) > 0)
    assert -p0[0] < ds["sigma_a"].values[0]  # every tensile load is above -sigma_a(1)
    # the contact carries p0 plus the tensile stress of the detached patches
    np.testing.assert_allclose(
        ds["contact_stress"] - ds["p0"],
        ds["detached_stress"],
        atol=1e-9 * float(ds["sigma_a"].max()),
    )


def test_comparison_script_builds_three_consistent_scenes():
    spec = importlib.util.spec_from_file_location("plot_example", EXAMPLES / "plot_area_vs_load.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)  # matplotlib is imported only inside main()
    scenes = mod.scenes()
    assert set(scenes) == {"jkr", "dmt", "non-adhesive"}
    work = {s["boundary"].get("work_of_adhesion") for s in (scenes["jkr"], scenes["dmt"])}
    assert len(work) == 1  # the same work of adhesion for both adhesive limits
    assert scenes["non-adhesive"]["boundary"] == {"model": "elastic"}
