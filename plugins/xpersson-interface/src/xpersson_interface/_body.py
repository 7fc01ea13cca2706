"""Local quantities a finite body integrates (:class:`xpersson.plugins.BodyQuantity`).

The leak rate of a flat seal of width ``L_x`` and length ``L_y`` is ``(L_y/L_x) s(p)`` with
``s`` the sheet flow conductance times the effective pressure drop [m^3/s]; an O-ring cord
(a ``[geometry] model = "cylinder"`` of the cord's radius, its ``length`` the seal's
circumference) pressed on the rough flat leaks ``L / int dx / s(p(x))`` across its nominal
contact (the flow resistances of the strips in series, Lorenz and Persson 2009). The elastic
energy stored at the interface adds over the nominal contact.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from xpersson.plugins import BodyQuantity

__all__ = ["ENERGY", "LEAKAGE"]


def _per_square(p: Mapping[str, Any]) -> float:
    """The flat seal's ``L_x / L_y`` [1]: its leak rate per square."""
    return float(p["seal_width"]) / float(p["seal_length"])


_SEAL = (
    "a cylinder (an O-ring cord, length = the seal's circumference) across its nominal contact: "
    "L / int dx / s(p(x)), s the flat seal's leak rate per square at the local pressure"
)
LEAKAGE = {
    "body_leak_rate": BodyQuantity(
        "leak_rate", "series", "m3 s-1", "leak rate across the body's nominal contact "
        "(critical junction)", description=_SEAL, factor=_per_square,
    ),
    "body_leak_rate_emt": BodyQuantity(
        "leak_rate_emt", "series", "m3 s-1", "leak rate across the body's nominal contact "
        "(effective medium)", description=_SEAL, factor=_per_square,
    ),
}  # fmt: skip
ENERGY = {
    "body_elastic_energy": BodyQuantity(
        "elastic_energy",
        "area",
        "J",
        "elastic energy stored at the interface of the body",
        description="int U_el/A0(p(r)) dA over the nominal contact (a cylinder: over its "
        "length); not the body's macroscopic elastic energy",
    ),
}
