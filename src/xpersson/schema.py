"""The variable table of xpersson Datasets and the attribute stamping.

One table (:data:`CORE_VARIABLES`) gives the dims, CF units and long names of every variable
the core writes; plugins declare theirs in their ``outputs``. Attributes are *set* from these
declarations (never propagated through arithmetic), in the manner of xclim.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from .specs import VarSpec

__all__ = [
    "CORE_VARIABLES",
    "COORDS",
    "stamp",
    "CONVENTIONS",
    "METADATA_KEYS",
    "STANDARD_NAME_VOCABULARY",
]

CONVENTIONS = "CF-1.11, ACDD-1.3"  # the versions the IOOS compliance-checker verifies

# The CF standard-name table the ``standard_name`` attributes come from. Contact mechanics has
# almost no names there: only ``area_fraction`` (the fraction of an area, here the nominal one,
# with some characteristic: in contact) and ``status_flag`` fit, and no invented name is used
# (a name outside the table would be a CF error); every variable has a ``long_name``.
STANDARD_NAME_VOCABULARY = "CF Standard Name Table v93"

# ACDD-1.3 discovery attributes a scene's [metadata] table or the user's metadata file may set
# (strings; stored as global attributes of the archive, overriding xpersson's defaults for
# summary and keywords)
METADATA_KEYS = frozenset(
    {
        "acknowledgement", "comment", "contributor_name", "contributor_role", "creator_email",
        "creator_institution", "creator_name", "creator_type", "creator_url", "id",
        "institution", "keywords", "keywords_vocabulary", "license", "naming_authority",
        "processing_level", "product_version", "program", "project", "publisher_email",
        "publisher_institution", "publisher_name", "publisher_type", "publisher_url", "summary",
    }
)  # fmt: skip

COORDS: dict[str, VarSpec] = {
    "zeta": VarSpec(("zeta",), "1", "magnification", description="zeta = q / q_L"),
    "p0": VarSpec(("p0",), "Pa", "nominal pressure", description="applied (squeezing) pressure"),
    "p": VarSpec(
        ("p",), "Pa", "local contact pressure", description="compressive positive; tensile negative"
    ),
    "q": VarSpec(("zeta",), "m-1", "wavevector of the magnification", description="q = zeta q_L"),
    "q_psd": VarSpec(("q_psd",), "m-1", "wavevector of the power spectrum nodes"),
}

CORE_VARIABLES: dict[str, VarSpec] = {
    "area_fraction": VarSpec(
        ("p0", "zeta"),
        "1",
        "relative contact area A/A0",
        description="probability of contact at magnification zeta",
        standard_name="area_fraction",
    ),
    "non_contact_fraction": VarSpec(
        ("p0", "zeta"),
        "1",
        "1 - A/A0",
        description="computed without cancellation (erfc or the absorbed flux)",
    ),
    "G": VarSpec(("p0", "zeta"), "1", "Persson's G = tau / p0^2"),
    "diffusion_time": VarSpec(("zeta",), "Pa2", "diffusion time tau = int_1^zeta f dzeta"),
    "effective_diffusion_time": VarSpec(
        ("p0", "zeta"),
        "Pa2",
        "diffusion time of the correction closure",
        description="V/2 of the mirrored Gaussian",
    ),
    "diffusion_coefficient": VarSpec(("zeta",), "Pa2", "diffusion coefficient f(zeta)"),
    "P": VarSpec(
        ("p0", "zeta", "p"),
        "Pa-1",
        "probability density of the contact pressure",
        description="normalised to the contact area: int P dp = A/A0",
    ),
    "psd_C": VarSpec(
        ("q_psd",),
        "m4",
        "isotropic power spectral density (Persson convention)",
        description="C(q) = (2 pi)^-2 int d2x <h(x) h(0)> exp(-i q.x)",
    ),
    "psd_exponent": VarSpec(
        ("q_psd",),
        "1",
        "log-log slope of the power spectrum from this node to the next",
        description="C(q) = psd_C (q / q_psd)^psd_exponent up to the next node: with psd_C it "
        "defines the spectrum the solve used exactly (xpersson.plugins.stored.spectrum_of).",
        nan_meaning="the last node: no segment starts there",
    ),
    "E": VarSpec((), "Pa", "Young's modulus"),
    "nu": VarSpec((), "1", "Poisson ratio"),
    "E_star": VarSpec((), "Pa", "contact modulus E / (1 - nu^2)"),
    "h_rms": VarSpec((), "m", "rms roughness height"),
    "rms_slope": VarSpec((), "1", "rms surface gradient (2-D)"),
    "map_h_rms": VarSpec((), "m", "rms height of the measured map (detrended)"),
    "map_rms_slope": VarSpec((), "1", "rms 2-D gradient of the measured map"),
    "psd_dropped_height": VarSpec((), "1", "share of the map's mean-square height not in psd_C"),
    "psd_dropped_slope": VarSpec((), "1", "share of the map's mean-square slope not in psd_C"),
    "load": VarSpec(("p0", "zeta"), "Pa", "load carried in the domain int p P dp"),
    "absorbed_lower": VarSpec(("p0", "zeta"), "1", "probability absorbed at the lower wall"),
    "absorbed_upper": VarSpec(("p0", "zeta"), "1", "probability absorbed at the upper wall"),
    "load_balance": VarSpec(
        ("p0", "zeta"),
        "1",
        "residual of the load identity",
        description="e.g. int p P dp / p0 - 1 for the elastic wall",
        extra={"coverage_content_type": "qualityInformation"},
    ),
    "probability_balance": VarSpec(
        ("p0", "zeta"),
        "1",
        "residual of the probability balance",
        description="int P dp + absorbed - 1",
        extra={"coverage_content_type": "qualityInformation"},
    ),
    "error_estimate": VarSpec(
        ("p0", "zeta"),
        "1",
        "estimated absolute error of A/A0",
        extra={"coverage_content_type": "qualityInformation"},
    ),
    "solver_status": VarSpec(
        ("p0",),
        "1",
        "engine status per load",
        standard_name="status_flag",
        extra={
            "flag_meanings": "success max_steps balance_violated tolerance_not_met invalid_input"
        },
    ),
}


def stamp(ds: Any, specs: Mapping[str, VarSpec]) -> None:
    """Set CF attrs (units, long_name, ...) of the variables in ``ds`` named in ``specs``."""
    for name, spec in specs.items():
        if name in ds.variables:
            ds[name].attrs.update(spec.attrs())
