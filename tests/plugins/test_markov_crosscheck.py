"""check_plugin's referee: every first-party boundary against the Markov process."""

from __future__ import annotations

import numpy as np
import pytest

import xpersson
from xpersson.builtin.elastic import ElasticBoundary
from xpersson.engine import EngineMethod, exact, register_method
from xpersson.engine._methods import METHODS
from xpersson.engine._result import Raw
from xpersson.testing import check_plugin, markov_cross_check, tiny_scene


def test_check_plugin_runs_the_markov_cross_check_on_the_elastic_wall():
    report = check_plugin(ElasticBoundary, cheap_import=False)
    assert report["markov"].startswith("ok (markov, 40000 walkers: within")


class _HalfArea(EngineMethod):
    """A broken method: the right walls, the wrong area (1 - A absorbed twice as fast)."""

    name = "half_area_test"

    def run(self) -> Raw:
        pb = self.problem
        a = 1.0 - 1.02 * (1.0 - exact.one_wall_area(pb.tau, pb.p0, 0.0))
        z = np.zeros_like(a)
        return Raw(a, 1 - a, 1 - a, z, pb.p0 + z, z, 1e-12 + z)


def test_cross_check_fails_a_wrong_engine_solution():
    register_method("half_area_test", _HalfArea)
    try:
        with pytest.raises(AssertionError, match="standard errors"):
            markov_cross_check(ElasticBoundary, scene={"solver": {"method": "half_area_test"}})
    finally:
        METHODS.pop("half_area_test", None)


def test_scene_selects_markov_with_walkers_and_seed():
    sc = tiny_scene()
    sc["solver"] = {"method": "markov", "walkers": 20_000, "seed": 2, "rtol": 0.05}
    ds1 = xpersson.solve(sc)
    ds2 = xpersson.solve(sc)
    ref = xpersson.solve(tiny_scene())
    np.testing.assert_array_equal(ds1.area_fraction.values, ds2.area_fraction.values)
    z = np.abs(ds1.area_fraction - ref.area_fraction) / np.maximum(ds1.error_estimate, 1e-300)
    assert float(z.max()) <= 5.0
    assert ds1.attrs["status"] == "success"
    assert '"walkers": 20000' in ds1.attrs["xpersson_scene"]


def test_scene_rejects_bad_walkers():
    sc = tiny_scene()
    sc["solver"] = {"method": "markov", "walkers": 0}
    with pytest.raises(ValueError, match="solver.walkers"):
        xpersson.solve(sc)
