"""One ``jkr`` load: the ``cn`` engine's reported error estimate bounds its true error on
the held-out scenes where the mesh's point speeds had hidden it (the detachment wall's PCHIP
knots inside steps), with the fewer levels of the chord speeds and of the sixth order after
a fourth-order miss (``engine/_cn_grading._chord_from``, ``engine/_cn_control.S_FIRST``;
``benchmarks/jkr_control.py`` measures all the design's and two held-out seeds' scenes).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import xpersson
from xpersson.engine import _cn_control

ZETA = np.geomspace(1.0, 1e3, 50).tolist()
SPECS = {  # held-out seed 4242 of benchmarks/summary_design.py
    "flat H=0.47 4dec": (0.4722, 6732.19374923703, 6732.19374923703, 67321937.49237029),
    "roll H=0.69 3dec": (0.6921, 4279.313504616741, 39078.54361964925, 4279313.504616741),
}


def _scene(H: float, q_L: float, q_r: float, q_1: float, rtol: float | None = None) -> dict:
    sc = {
        "spectrum": {"model": "self_affine", "H": H, "q_L": f"{q_L!r} 1/m",
                     "q_r": f"{q_r!r} 1/m", "q_1": f"{q_1!r} 1/m", "h_rms": "1 um"},
        "material": {"E": "1 MPa", "nu": 0.5},
        "load": {"p0": "1000 Pa"},
        "boundary": {"model": "jkr", "work_of_adhesion": "0.05 J/m**2"},
        "output": {"zeta": ZETA},
    }  # fmt: skip
    if rtol is not None:
        sc["solver"] = {"rtol": rtol, "method": "cn"}
    return sc


def _solve(sc: dict):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return xpersson.solve(sc)


@pytest.mark.parametrize("name", sorted(SPECS))
def test_estimate_bounds_the_error_of_one_jkr_load(name, monkeypatch):
    calls = []
    sixth = _cn_control._sixth
    monkeypatch.setattr(_cn_control, "_sixth", lambda *a, **k: calls.append(a[2]) or sixth(*a, **k))
    ds = _solve(_scene(*SPECS[name]))
    grids = list(calls)
    ref = _solve(_scene(*SPECS[name], rtol=1e-9))
    area, est = ds["area_fraction"].values, ds["error_estimate"].values
    err = np.abs(area - ref["area_fraction"].values)
    tol = 1e-6 * np.abs(area) + 1e-12
    assert np.all(err <= est)  # the reported estimate bounds the true error
    assert np.all(est <= tol)
    assert float(ref["error_estimate"].max()) < 1e-2 * float(tol.min())
    # the answer is the sixth order on the pilot grid (24 intervals): 4 levels, no more
    assert grids == [24]
