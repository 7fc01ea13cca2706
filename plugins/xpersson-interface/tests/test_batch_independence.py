"""A load's direct-path values never depend on the other loads of its scene (bit for bit).

Sweeps run in chunks (dask) and promise the serial run's bits: each load's curve keeps every
dense magnification (no cut where the batch's lowest load leaves full contact), its crossing is
found by its own Newton steps, its ``Phi`` table is zero below its own first non-zero node,
its row sums are einsums (not BLAS products over the loads) and its difference quotient of
``u1`` reads ``Phi``'s spline (a load alone once took the shared-cut-off table path).
"""

from __future__ import annotations

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from interface_testlib import scene

import xpersson

#: Loads from near full contact to a few contact spots (p0/E* from 1e-4 to 0.5).
POOL = np.geomspace(1.5e3, 6e6, 20)
ANALYSES = {
    "gap_pdf": {"u_points": 32, "u_max": "30 um", "n_bins": 40},
    "leakage": {"viscosity": "1 mPa*s", "n_bins": 40},
    "mean_gap": {},
    "elastic_energy": {},
    "contact_stiffness": {},
}
NAMES = ("gap_pdf", "gap_mean", "gap_contact_weight", "leak_zeta_c", "leak_u1", "leak_rate",
         "leak_flow_factor_emt", "leak_rate_emt", "leak_sealed", "mean_gap", "elastic_energy",
         "contact_stiffness")  # fmt: skip
_ALONE: dict[int, dict[str, np.ndarray]] = {}


def _run(idx: list[int]) -> dict[str, np.ndarray]:
    ds = xpersson.solve(scene([float(POOL[i]) for i in idx], analyses=ANALYSES))
    return {n: np.asarray(ds[n].values, dtype=float) for n in NAMES}


def _alone(i: int) -> dict[str, np.ndarray]:
    if i not in _ALONE:
        _ALONE[i] = {n: v[0] for n, v in _run([i]).items()}
    return _ALONE[i]


@settings(max_examples=8, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    st.lists(st.integers(0, POOL.size - 1), min_size=2, max_size=7, unique=True),
    st.integers(0, 6),
)
def test_a_load_alone_and_in_any_batch_give_the_same_bits(batch, pick):
    """One load alone and the same load among random others (any order) on the direct path:
    leakage and gap distribution identical bit for bit."""
    batch = sorted(batch)
    target = batch[pick % len(batch)]
    together = _run(batch)
    alone = _alone(target)
    row = batch.index(target)
    assert np.isfinite(alone["gap_mean"])
    for name in NAMES:
        np.testing.assert_array_equal(together[name][row], alone[name], err_msg=name)
