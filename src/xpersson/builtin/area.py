"""Built-in analysis: mean pressure in the real contact area."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..plugins import Analysis, ParamSpec, SceneContext, VarSpec

__all__ = ["ContactArea"]


class ContactArea(Analysis):
    """Mean contact pressure p0 / (A/A0) [Pa] and the contact-area slope kappa.

    ``kappa = (A/A0) E* h'_rms / p0`` at the final magnification: tends to sqrt(8/pi) = 1.596 at
    small load for Persson's theory (a direct check of the area-load law).
    """

    summary = "mean contact pressure p0/(A/A0) and the area-load slope kappa"
    references = ("10.1063/1.1388626",)
    parameters: dict[str, ParamSpec] = {}
    requires = ("area_fraction",)
    provides = ("mean_contact_pressure", "kappa")
    outputs = {
        "mean_contact_pressure": VarSpec(("p0", "zeta"), "Pa", "mean pressure in the real "
                                         "contact area", description="p0 / (A/A0)",
                                         nan_meaning="no contact (A/A0 = 0, or so small that "
                                         "p0 / (A/A0) exceeds the float range)"),
        "kappa": VarSpec(("p0",), "1", "area-load slope kappa = (A/A0) E* h'_rms / p0 at "
                         "zeta_max"),
    }

    def compute(self, ctx: SceneContext, ds: Any) -> dict[str, Any]:
        """Mean contact pressure [Pa] and kappa [1]."""
        area = np.asarray(ds["area_fraction"].transpose(..., "p0", "zeta").values, float)
        area = area.reshape(ctx.p0.size, -1)
        with np.errstate(over="ignore", divide="ignore"):
            mean_p = ctx.p0[:, None] / np.where(area > 0, area, np.nan)
        mean_p[~np.isfinite(mean_p)] = np.nan
        slope = float(np.sqrt(2 * np.pi * ctx.psd.moment(3, ctx.q_L, ctx.q[-1])))
        kappa = area[:, -1] * ctx.E_star * slope / ctx.p0
        return {"mean_contact_pressure": (("p0", "zeta"), mean_p), "kappa": (("p0",), kappa)}
