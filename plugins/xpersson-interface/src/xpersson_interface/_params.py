"""The parameters the interface analyses share (``s_factor``, ``gamma``, ``zeta_per_decade``), the
leak analysis's own, and the error of the loads an analysis interpolates."""

from __future__ import annotations

from xpersson.physics.closures import GAMMA_DEFAULT
from xpersson.plugins import ParamSpec, VarSpec
from xpersson.plugins.solved import FORMS

__all__ = [
    "LEAKAGE_PARAMS",
    "UNTABLED",
    "_DENSE",
    "_FORM",
    "_FORM_AUTO",
    "_GAMMA",
    "_NEVER",
    "load_error",
]

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

#: The leak analysis's own parameters (with the shared S-factor form).
LEAKAGE_PARAMS: dict[str, ParamSpec] = {
    "a_c": ParamSpec(
        unit="1",
        default=0.42,
        bounds=(0.0, 1.0),
        inclusive=(False, False),
        description="percolation threshold of the contact area",
    ),
    "fluid": ParamSpec(
        kind="choice",
        choices=("liquid", "gas"),
        default="liquid",
        description="incompressible liquid or ideal gas (isothermal)",
    ),
    "viscosity": ParamSpec(
        unit="Pa*s",
        default=1e-3,
        bounds=(0.0, None),
        inclusive=(False, True),
        description="dynamic viscosity of the fluid",
    ),
    "pressure_drop": ParamSpec(
        unit="Pa", default=1e5, bounds=(0.0, None),
        description="liquid: pressure drop from the inlet to the outlet side",
    ),
    "p_in": ParamSpec(
        unit="Pa", default=2e5, bounds=(0.0, None),
        description="gas: inlet (high) pressure; must be >= p_out",
    ),
    "p_out": ParamSpec(
        unit="Pa",
        default=1e5,
        bounds=(0.0, None),
        inclusive=(False, True),
        description="gas: outlet (low) pressure, reference of the reported volume flow",
    ),
    "seal_width": ParamSpec(
        unit="m",
        default=1e-3,
        bounds=(0.0, None),
        inclusive=(False, True),
        description="seal width L_x along the flow",
    ),
    "seal_length": ParamSpec(
        unit="m",
        default=1e-2,
        bounds=(0.0, None),
        inclusive=(False, True),
        description="seal length L_y across the flow",
    ),
    "emt_threshold": ParamSpec(
        kind="choice",
        choices=("bruggeman", "a_c"),
        default="bruggeman",
        description="EMT percolation at contact weight 1/2 (plain) or rescaled to a_c",
    ),
    "n_bins": ParamSpec(
        kind="int",
        default=60,
        bounds=(10, 100000),
        description="magnification bins of the gap distribution (EMT)",
    ),
}  # fmt: skip


def load_error(
    tol: float, least: int, margin: str = "1/16 of", counted: str = "", never: str = ""
) -> VarSpec:
    """The estimated error of the loads an analysis interpolates in the load
    (:mod:`._by_load`) from ``least`` loads on (``counted``: which, e.g. those not sealed), at
    most ``tol``; ``margin``: how the estimate scales the error of the nodes at twice the
    spacing; ``never``: the parameters with which no load is interpolated."""
    return VarSpec(
        ("p0",),
        "1",
        "estimated relative error of the load's outputs interpolated in the load",
        valid_min=0.0,
        valid_max=tol,
        description=f"where the loads{counted} number {least} or more and at least 3 times "
        "the table's nodes, the analysis's outputs are computed directly "
        "at node loads 1/16 decade apart (denser where needed) and interpolated in ln p0 "
        f"between them (8-point Lagrange of the logarithm): {margin} the error the nodes at "
        "twice the spacing make, relative to the load's value (a row: its largest; at least "
        "1e-30 of the largest over the loads), plus the direct path's own irregularity in the "
        f"load through the interpolation weights; at most {tol:g}, else the load is computed "
        f"directly (0){never}",
    )


#: ``gap_pdf`` parameter values whose loads are all computed directly, never through the load
#: table (:mod:`._by_load`): their outputs are not smooth in the load. Almqvist's far tail (``u1``
#: of bins of vanishing weight at many ``h_rms``, moving with the load) makes ``gap_mean`` and
#: the density's tail elements jump between the table's nodes; the diffusion solver's grid adds
#: its own irregularity. Tabled at 1000 (``almqvist``) and 500 (``diffusion``) loads on the
#: scenes of the speed design and ``--held-out 2026``, their interpolated loads were off by up
#: to 3.0e-3 and 3.1e-3 (61 and 35 times their stated error; a tolerance of 1e-4) and, without
#: the spike guard (``_stencils.SPIKE``), single elements by up to 6e9 times their row's
#: maximum (``benchmarks/load_table_extreme.py``). ``s_factor = "yang_persson"`` keeps the
#: table: within 0.54 of the estimate on those 24 scenes.
UNTABLED = frozenset({("separation", "almqvist"), ("method", "diffusion")})
#: ``gap_pdf_load_error``'s note on :data:`UNTABLED`.
_NEVER = "; never with " + " or ".join(f"{k} = {v!r}" for k, v in sorted(UNTABLED)) + " (0)"
