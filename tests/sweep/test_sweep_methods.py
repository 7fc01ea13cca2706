"""A sweep that asks for a numerical engine method by name gives what its points give alone.

The contact-similarity path (material sweeps solved at equivalent loads) and the stacked path
(one run for points that differ in a stacked parameter) are exact for the closed forms; ``cn``
steers its error control by discrete decisions (grid levels, one time schedule for the loads
sharing their walls) that neither reproduces, and ``sine`` by series terms a scaled load does
not reproduce: ``benchmarks/fuzz.py --methods 1 --sweeps 1 --seed 197`` found the fast paths
up to 3.5e-6 of the area off the plain path. Such sweeps now take neither path.
"""

from __future__ import annotations

import numpy as np
import pytest

import xpersson
from xpersson.pipeline.stacked import LOAD_WISE_METHODS
from xpersson.sweep import batched, plain_paths


def scene(method: str, **swept) -> dict:
    sc = {
        "spectrum": {
            "model": "self_affine",
            "H": 0.8,
            "q_L": "1e3 1/m",
            "q_1": "1e6 1/m",
            "h_rms": "1 um",
        },  # fmt: skip
        "material": {"E": "10 MPa", "nu": 0.5},
        "load": {"p0": ["10 kPa", "100 kPa"]},
        "output": {"zeta_per_decade": 6},
        "solver": {"method": method, "rtol": 1e-4},
    }
    for path, values in swept.items():
        section, key = path.split("__")
        sc[section][key] = values
    return sc


@pytest.mark.parametrize(
    "swept",
    [{"material__E": ["5 MPa", "10 MPa", "20 MPa"]}, {"spectrum__H": [0.6, 0.7, 0.8]}],
    ids=["E (similarity)", "H (stacked)"],
)
@pytest.mark.parametrize("method", ["cn", "sine"])
def test_a_method_sweep_equals_its_plain_path(method, swept):
    sc = scene(method, **swept)
    fast = xpersson.solve(sc)
    with plain_paths():
        plain = xpersson.solve(sc)
    for name in ("area_fraction", "non_contact_fraction", "load_balance"):
        np.testing.assert_array_equal(fast[name].values, plain[name].values, err_msg=name)


def test_the_paths_name_the_methods_they_take():
    assert batched.SIMILAR_METHODS == ("auto", "exact")
    assert "cn" not in LOAD_WISE_METHODS and "sine" in LOAD_WISE_METHODS
