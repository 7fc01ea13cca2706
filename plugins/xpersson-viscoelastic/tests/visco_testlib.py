"""Shared scenes of the xpersson-viscoelastic tests (a uniquely named module)."""

from __future__ import annotations

import copy
from typing import Any

SPECTRUM = {
    "model": "self_affine",
    "H": 0.8,
    "q_L": "1e3 1/m",
    "q_r": "1e4 1/m",
    "q_1": "1e7 1/m",
    "h_rms": "10 um",
}


def scene(coefficient: dict[str, Any], **sections: Any) -> dict[str, Any]:
    """A rubber-on-rough-surface scene with the ``viscoelastic`` coefficient."""
    sc: dict[str, Any] = {
        "spectrum": dict(SPECTRUM),
        "material": {"E": "3 MPa", "nu": 0.5},
        "load": {"p0": ["0.1 MPa", "0.4 MPa"]},
        "coefficient": {"model": "viscoelastic", **coefficient},
        "output": {"zeta_per_decade": 10},
    }
    sc.update(copy.deepcopy(sections))
    return sc


def elastic_scene(E: str, **sections: Any) -> dict[str, Any]:
    """The same scene with the built-in elastic coefficient and modulus ``E``."""
    coef = sections.pop("coefficient", {})
    sc = scene({}, **sections)
    sc["coefficient"] = {"model": "elastic", **coef}
    sc["material"] = {"E": E, "nu": 0.5}
    return sc
