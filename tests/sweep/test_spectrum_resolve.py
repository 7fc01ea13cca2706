"""A sweep over spectrum parameters re-resolves only the spectrum (``with_spectrum``): every
point equals its full resolve, and a bad point still fails before any work, named."""

from __future__ import annotations

import numpy as np
import pytest

import xpersson
from xpersson.plugins import get_registry
from xpersson.scene import SceneError, with_spectrum
from xpersson.sweep.batched import material_dims
from xpersson.sweep.execute import resolve_points
from xpersson.sweep.plan import expand

SPECTRUM = {
    "model": "self_affine",
    "H": [0.5, 0.7, 0.9],
    "q_L": "1e3 1/m",
    "q_r": "3e3 1/m",
    "q_1": "1e7 1/m",
    "h_rms": "1 um",
}


def _scene(**spectrum: object) -> dict:
    return {
        "spectrum": {**SPECTRUM, **spectrum},
        "material": {"E": ["1 MPa", "10 MPa"], "nu": 0.5},
        "load": {"p0": ["10 kPa", "100 kPa"]},
        "output": {"zeta_per_decade": 5},
    }


def test_each_point_equals_its_full_resolve() -> None:
    reg = get_registry()
    plan = expand(xpersson.Scene(_scene(q_1=["1e6 1/m", "1e7 1/m"])), reg)
    first = plan.point_scene((0, 0, 0)).resolve(reg)
    material = material_dims(plan.groups)
    for index in plan.indices():
        if any(i and m for i, m in zip(index, material, strict=True)):
            continue  # with_spectrum: points that differ from the first in the spectrum only
        scene = plan.point_scene(index)
        full, quick = scene.resolve(reg), with_spectrum(first, scene, reg)
        assert quick.resolved == full.resolved
        assert list(quick.resolved) == list(full.resolved)  # the archive's key order too
        assert {k: str(v) for k, v in quick.labels.items()} == {
            k: str(v) for k, v in full.labels.items()
        }
        assert quick.plugin_records == full.plugin_records
        assert quick.plugin_names == full.plugin_names
        np.testing.assert_array_equal(quick.zeta, full.zeta)
        assert quick.psd.cache_key() == full.psd.cache_key()
        assert quick.scene is scene


def test_sweep_points_match_full_resolves() -> None:
    reg = get_registry()
    plan = expand(xpersson.Scene(_scene()), reg)
    points = list(resolve_points(plan, reg))
    for index, rs in zip(plan.indices(), points, strict=True):
        full = plan.point_scene(index).resolve(reg)
        assert rs.resolved["spectrum"] == full.resolved["spectrum"]
        assert rs.psd.cache_key() == full.psd.cache_key()


def test_a_bad_spectrum_point_is_named() -> None:
    with pytest.raises(SceneError) as err:
        xpersson.solve(_scene(q_1=["1e7 1/m", "2e3 1/m"]))
    full = xpersson.Scene({**_scene(q_1="2e3 1/m", H=0.5), "material": {"E": "1 MPa", "nu": 0.5}})
    with pytest.raises(SceneError) as one:
        full.resolve()
    assert str(err.value).startswith("sweep point ")
    assert "q_1 = 2000" in str(err.value)
    assert str(err.value).endswith(str(one.value))
