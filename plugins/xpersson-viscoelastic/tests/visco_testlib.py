"""Shared scenes of the xpersson-viscoelastic tests (a uniquely named module)."""

from __future__ import annotations

import copy
from typing import Any

from xpersson import testing

SPECTRUM = testing.spectrum(h_rms="10 um")


def scene(coefficient: dict[str, Any], **sections: Any) -> dict[str, Any]:
    """A rubber-on-rough-surface scene with the ``viscoelastic`` coefficient."""
    sc = testing.scene(
        SPECTRUM,
        testing.material("3 MPa"),
        p0=["0.1 MPa", "0.4 MPa"],
        coefficient={"model": "viscoelastic", **coefficient},
        output={"zeta_per_decade": 10},
    )
    sc.update(copy.deepcopy(sections))
    return sc


def elastic_scene(E: str, **sections: Any) -> dict[str, Any]:
    """The same scene with the built-in elastic coefficient and modulus ``E``."""
    coef = sections.pop("coefficient", {})
    sc = scene({}, **sections)
    sc["coefficient"] = {"model": "elastic", **coef}
    sc["material"] = testing.material(E)
    return sc
