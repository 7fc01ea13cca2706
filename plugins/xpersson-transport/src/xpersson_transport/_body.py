"""Local quantities a finite body integrates (:class:`xpersson.plugins.BodyQuantity`).

The contact conductance per nominal area at the local pressure is in series with the spreading
(constriction) resistance of the two bodies over the nominal contact; the core solves the flux
over the nominal pressure with the elastic solve's half-space Green's function and the bulk
factor ``b`` here (Barber 2003's analogy; a smooth body gives Holm's ``4 a / (rho_1 +
rho_2)``).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from xpersson.plugins import BodyQuantity

__all__ = ["ELECTRICAL", "THERMAL"]


def _electrical_bulk(p: Mapping[str, Any]) -> float:
    """``(rho_1 + rho_2) / 2`` [ohm m]."""
    return 0.5 * (float(p["resistivity_1"]) + float(p["resistivity_2"]))


def _thermal_bulk(p: Mapping[str, Any]) -> float:
    """``(1/kappa_1 + 1/kappa_2) / 2`` [m K/W]."""
    return 0.5 * (1.0 / float(p["conductivity_1"]) + 1.0 / float(p["conductivity_2"]))


_WHAT = (
    "the contact conductance per area at the local nominal pressure in series with the "
    "bodies' spreading resistance over the nominal contact (a cylinder: referred to the "
    "distance R, as its approach)"
)
ELECTRICAL = {
    "body_electrical_conductance": BodyQuantity(
        "electrical_contact_conductance", "constriction", "S",
        "electrical contact conductance of the body", description=_WHAT, bulk=_electrical_bulk,
        unbounded="electrical_contact_status",
    ),
}  # fmt: skip
THERMAL = {
    "body_thermal_conductance": BodyQuantity(
        "thermal_contact_conductance", "constriction", "W K-1",
        "thermal contact conductance of the body", description=_WHAT, bulk=_thermal_bulk,
        unbounded="thermal_contact_status",
    ),
}  # fmt: skip
