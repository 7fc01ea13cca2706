"""A load's direct-path values do not depend on the other loads of its scene beyond round-off.

Sweeps run in chunks (dask): a load's crossing is found by its own Newton steps, its ``Phi``
table is zero below its own first non-zero node, its row sums are einsums (not BLAS products
over the loads) and its difference quotient of ``u1`` reads ``Phi``'s spline. The one batch
dependence left is the dense grid's full-contact cut, taken over the call's loads
(``xpersson.plugins.solved._past_full_contact``): measured on 60 random batches, only
``contact_stiffness`` moved (<= 4e-16 relative); the gap and leakage outputs kept their bits.
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
#: Integrals over the whole contact curve: the batch's cut may move them at round-off.
CURVE = ("mean_gap", "elastic_energy", "contact_stiffness")
#: Bound on their change with the batch, relative (measured: 4e-16).
RTOL = 1e-12
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
def test_a_load_alone_and_in_any_batch_agree(batch, pick):
    """One load alone and the same load among random others on the direct path: leakage and
    gap distribution identical bit for bit, the curve integrals within :data:`RTOL`."""
    batch = sorted(batch)
    target = batch[pick % len(batch)]
    together = _run(batch)
    alone = _alone(target)
    row = batch.index(target)
    assert np.isfinite(alone["gap_mean"])
    for name in NAMES:
        if name in CURVE:
            np.testing.assert_allclose(together[name][row], alone[name], rtol=RTOL, err_msg=name)
        else:
            np.testing.assert_array_equal(together[name][row], alone[name], err_msg=name)
