"""The parameters the interface analyses share (``s_factor``, ``gamma``, ``zeta_per_decade``)."""

from __future__ import annotations

from xpersson.physics.closures import GAMMA_DEFAULT
from xpersson.plugins import ParamSpec
from xpersson.plugins.solved import FORMS

__all__ = ["_DENSE", "_FORM", "_FORM_AUTO", "_GAMMA"]

_FORM = ParamSpec(
    kind="choice",
    choices=FORMS,
    default="closure",
    description="correction factor S in energy and gap: the scene's closure, or Yang-Persson"
    " 2008 (S = gamma + (1 - gamma) A^2 with Persson's area; needs closure = persson01)",
)
_FORM_AUTO = ParamSpec(
    kind="choice",
    choices=("auto", *FORMS),
    default="auto",
    description="correction factor S in energy and gap: auto (yang_persson with an uncorrected"
    " area, else the closure's; chosen by accuracy against the BEM, docs/verification.md),"
    " the scene's closure, or Yang-Persson 2008 (needs closure = persson01)",
)
_GAMMA = ParamSpec(
    unit="1",
    default=None,
    bounds=(0.0, 1.0),
    inclusive=(False, True),
    description=f"gamma of s_factor = 'yang_persson' (default {GAMMA_DEFAULT}, the package-wide"
    " default); the closure form uses the coefficient's gamma",
)
_DENSE = ParamSpec(
    kind="int",
    default=40,
    bounds=(0, 10000),
    description="points per decade of zeta - 1 at which the solve is sampled for the zeta"
    " integrals (0: the Dataset's magnifications only)",
)
