"""The leakage load table's first level (private): loads it would compute directly anyway.

Measured on the speed design at 1000 loads (``benchmarks/leakage_loads.py``): the loads near the
junction's sealing (``zeta_c > NEAR_SEALING zeta_max``: each a key of its own, so computed
directly by design) and, where fewer than :data:`SHORT`, the loads the junction alone seals
(the effective medium still open: too few to table) are all computed directly, but only once
refinement reaches them, in the table's third or fourth direct call (each call ~2.5 ms fixed).
Predicted from the stored curve's crossing of ``a_c``, they are nodes of the first level
instead (:func:`._by_load.by_load`'s ``free``): computed in the first call, with the grid.
A load predicted wrongly costs one direct evaluation (its values are then exact); one missed
is found by the table's refinement, as before: the prediction changes which loads are
computed, never the accuracy claim.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from xpersson import physics

from ._by_load import LEAK_ORDERS
from ._leakage import NEAR_SEALING, _contact_area

__all__ = ["MARGIN", "SHORT", "direct_anyway", "predicted"]

#: Relative margin of the prediction on ``zeta_c / zeta_max`` (the stored curve's crossing
#: lies within 6 % of the dense re-solve's on the speed design).
MARGIN = 0.1
#: Loads sealed by the junction alone (the medium open) fewer than this: too few to table (a
#: segment of the table needs twice its ``2 m`` check nodes), each computed directly.
SHORT = 4 * max(LEAK_ORDERS)


def direct_anyway(
    ds: Any, boundary: Any, a_c: float, sealed: NDArray[np.bool_]
) -> NDArray[np.bool_]:
    """:func:`predicted` of the loads of the solved Dataset ``ds`` (the Dataset's order), from
    its stored contact area (the ``boundary``'s ``contact_area`` variables)."""
    zeta = np.asarray(ds["zeta"].values, dtype=float)
    return predicted(zeta, _contact_area(ds, boundary), a_c, sealed)


def predicted(
    zeta: NDArray[np.float64],
    area: NDArray[np.float64],
    a_c: float,
    sealed: NDArray[np.bool_],
) -> NDArray[np.bool_]:
    """Per load (its row of the contact area ``area`` (n_load, n_zeta) [1] on the
    magnifications ``zeta``, increasing from 1): not ``sealed`` by both theories, and the
    curve's crossing of ``a_c`` above ``(1 - MARGIN) NEAR_SEALING zeta_max`` or, where fewer
    than :data:`SHORT` loads have none (the junction sealed), none."""
    zc = physics.critical_magnification(zeta, area, a_c)
    shut = ~np.isfinite(zc) & ~sealed
    with np.errstate(invalid="ignore"):
        out = zc > (1.0 - MARGIN) * NEAR_SEALING * float(zeta[-1])
    if np.count_nonzero(shut) < SHORT:
        out |= shut
    return out & ~sealed
