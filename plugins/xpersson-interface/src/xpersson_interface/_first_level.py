"""The leakage load table's first level (private): loads predicted to be computed directly.

Near the junction's sealing (``zeta_c > NEAR_SEALING zeta_max``, each load a key of its own)
and where the junction is sealed but the effective medium is open (a stretch too short to
table), the load table computes every load directly, but only once refinement reaches them
(the second to fourth direct call). Predicted from the stored curve, they are computed in the
first call instead (:func:`._by_load.by_load`'s ``first``).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from xpersson import physics

from ._leakage import NEAR_SEALING, _contact_area

__all__ = ["MARGIN", "direct_anyway"]

#: Relative margin of the prediction on ``zeta_c / zeta_max`` (the stored curve's crossing is
#: within 6 % of the dense re-solve's on the speed design).
MARGIN = 0.1


def direct_anyway(
    ds: Any, boundary: Any, a_c: float, sealed: NDArray[np.bool_]
) -> NDArray[np.bool_]:
    """Per load (the Dataset's order): not sealed by both theories (``sealed``), and the
    stored curve's crossing of ``a_c`` above ``(1 - MARGIN) NEAR_SEALING zeta_max`` or none
    (the junction sealed)."""
    zeta = np.asarray(ds["zeta"].values, dtype=float)
    area = _contact_area(ds, boundary)
    zc = physics.critical_magnification(zeta, area, a_c)
    with np.errstate(invalid="ignore"):
        near = ~(zc <= (1.0 - MARGIN) * NEAR_SEALING * zeta[-1])
    return near & ~sealed
