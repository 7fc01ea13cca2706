"""A friction sweep's block template: the first point's Dataset assembled from the stacked run
(``StackedRun.point_dataset``) is that point's own run, friction included: the same variables,
dims, dtypes and attributes; the values the stacked run's (equal to the own run's to 1e-12:
with the S factor one element of ``mu_visc_cumulative`` differs in its last bit)."""

from __future__ import annotations

import copy
import tomllib
import warnings
from pathlib import Path

import numpy as np
import pytest

from xpersson.pipeline import run, stacked
from xpersson.scene import Scene

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "tread_on_asphalt.toml"
VOLATILE = {"history", "date_created", "xpersson_solver"}


def _point(data: dict, v: str, correction: str) -> object:
    d = copy.deepcopy(data)
    d["coefficient"]["velocity"] = v
    d["analyses"]["friction"]["correction"] = correction
    return Scene(d).resolve()


@pytest.mark.parametrize("correction", ["none", "s_factor"])
def test_the_first_friction_point_is_its_own_run(correction):
    data = tomllib.loads(EXAMPLE.read_text())
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        points = [_point(data, v, correction) for v in ("1e-4 m/s", "1 m/s", "30 m/s")]
        assert stacked.stack_reason(points) is None
        own = stacked.run_stacked(points).point_dataset()
        ref = run(points[0], squeeze=False)
    assert list(own.variables) == list(ref.variables)
    for name, var in ref.variables.items():
        got = own.variables[name]
        assert (got.dims, got.dtype) == (var.dims, var.dtype), name
        if var.dtype.kind == "f":
            np.testing.assert_allclose(got.values, var.values, rtol=1e-12, atol=0, err_msg=name)
        else:
            np.testing.assert_array_equal(got.values, var.values, name)
        assert repr(got.attrs) == repr(var.attrs), name
    assert {k: v for k, v in own.attrs.items() if k not in VOLATILE} == {
        k: v for k, v in ref.attrs.items() if k not in VOLATILE
    }
