"""A body whose Newton iteration stalls: the result with its residual and an honest status, never
an exception from inside (found by the fuzz campaign with bodies, 2026-12-01: every stall it
found was at the round-off of the approach solved, under forces of 1e-16 - 1e-8 N)."""

from __future__ import annotations

import warnings

import numpy as np
import xarray as xr

import xpersson
from xpersson.errors import XperssonWarning
from xpersson.physics.body import BodySolution
from xpersson.pipeline import body
from xpersson.pipeline.body import ITERATION_SHARE


def _cylinder() -> dict:
    """Seed 5, scene 275 of ``fuzz.py --bodies 1``: a 2.2e-15 N line load on a 1.1 mm cylinder,
    whose nominal pressure stalls at a gap residual of ~4e-4 of the Hertz approach."""
    return {
        "spectrum": {"model": "self_affine", "H": 0.29427409014922445,
                     "q_L": "1083.6551701537587 1/m", "q_r": "1083.6551701537587 1/m",
                     "q_1": "10772856.224034475 1/m", "h_rms": "1.8204500057153633e-08 m"},
        "material": {"E": "10868804.768399667 Pa", "nu": 0.45802462450603626},
        "load": {"force": ["2.2171559552609925e-15 N", "1.606242239179023e-08 N"]},
        "output": {"zeta_per_decade": 5},
        "solver": {"rtol": 2.0587076442827103e-05},
        "geometry": {"model": "cylinder", "radius": "0.0010993928687585254 m",
                     "length": "0.010800592140894924 m"},
    }  # fmt: skip


def _sphere() -> dict:
    """Seed 5, scene 224: stalls at 1.7e-9 of the approach, far below its grid error."""
    return {
        "spectrum": {"model": "self_affine", "H": 0.8120971834487897,
                     "q_L": "42.03512924603995 1/m", "q_r": "42.03512924603995 1/m",
                     "q_1": "940.7239624882483 1/m", "rms_slope": 0.44639192153776974},
        "material": {"E": "511116833.1901797 Pa", "nu": 0.33697404166926975},
        "load": {"force": "3.706900359104954e-05 N"},
        "output": {"zeta_per_decade": 15},
        "solver": {"rtol": 2.393574723106331e-06},
        "geometry": {"model": "sphere", "radius": "0.033336160262789606 m"},
    }  # fmt: skip


def test_a_stall_at_the_round_off_of_the_approach_is_a_success():
    """The iteration stalls at 4e-4 of the Hertz approach (2e-19 m), which is 1e-16 of the
    approach it solved (3e-7 m): converged to the gaps' round-off, not a failure."""
    ds = xpersson.solve(_cylinder())
    res, hertz, approach = (ds[n].values for n in ("body_residual", "hertz_approach", "approach"))
    assert res[0] > 1e-5  # stalled far above Newton's tolerance (1e-10) in Hertz units
    assert np.all(res * hertz / np.maximum(np.abs(approach), hertz) < 1e-14)
    assert ds.attrs["status"] == "success"
    assert np.all(np.isfinite(ds["real_contact_area"].values))
    assert np.all(ds["real_contact_area"].values > 0)


def test_a_stall_far_below_the_grid_error_is_a_success():
    ds = xpersson.solve(_sphere())
    res, err = float(ds["body_residual"]), float(ds["body_grid_error"])
    assert 1e-10 < res < ITERATION_SHARE * err  # stalled above the Newton tolerance 1e-10
    assert ds.attrs["status"] == "success"


def test_a_stall_above_the_grid_error_is_flagged_and_named():
    """The rule itself (no scene found that stalls there): a stalled solution whose residual,
    per the approach it solved, exceeds 1 % of its grid error names its force, sets
    tolerance_not_met and warns; a converged one, or one at round-off, does not."""
    r = np.zeros(2)

    def sol(residual: float, delta: float, converged: bool) -> BodySolution:
        return BodySolution(r, r, r, r, delta, 1.0, residual, 200, converged)

    forces, hertz, errs = np.array([1e-3, 2e-3]), np.array([1e-9, 1e-9]), np.array([1e-3, 1e-3])
    ok = [sol(1e-12, 1e-9, True), sol(1e-12, 1e-9, True)]
    stalled = [sol(1e-3, 1e-9, False), sol(1e-3, 1e-2, False)]  # 1e-3 and 1e-10 of delta
    assert body._stalled(forces, ok, ok, errs, hertz) == []
    lines = body._stalled(forces, stalled, ok, errs, hertz)
    assert len(lines) == 1 and lines[0].startswith("force = 0.001 N")
    ds = xr.Dataset(attrs={"status": "success", "status_message": "all loads met"})
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        body._not_met(ds, lines)
    assert ds.attrs["status"] == "tolerance_not_met" and ds.attrs["status_message"] == lines[0]
    assert any(issubclass(w.category, XperssonWarning) for w in caught)
