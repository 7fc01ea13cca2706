"""Built-in analysis: mean pressure in the real contact area."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..plugins import Analysis, FastPaths, ParamSpec, SceneContext, VarSpec
from ..plugins.stored import contact_modulus, spectrum_of

__all__ = ["ContactArea"]


class ContactArea(Analysis):
    """Mean contact pressure p0 / (A/A0) [Pa] and the contact-area slope kappa.

    ``A`` is the area that carries the load, as the boundary declares it
    (:attr:`xpersson.plugins.Boundary.contact_area`: the elastic area for the elastic wall,
    elastic + plastic contact for plasticity), so the mean pressure lies in ``[p0, sigma_Y]``
    for a plastic contact. ``kappa = (A/A0) E* h'_rms / p0`` at the final magnification: tends to
    sqrt(8/pi) = 1.596 at small load for Persson's theory (a direct check of the area-load law).
    Where the contact area underflows to 0 the mean pressure is undefined (NaN); with an adhesive
    boundary and a tensile load (p0 < 0) both outputs are negative.
    """

    summary = "mean contact pressure p0/(A/A0) and the area-load slope kappa"
    references = ("10.1063/1.1388626",)
    parameters: dict[str, ParamSpec] = {}
    requires = ("area_fraction",)
    provides = ("mean_contact_pressure", "kappa")
    #: contact similarity: the mean pressure scales with p0, kappa is a ratio (both similar in
    #: units of E*); stacked: a block of points at once (:meth:`compute_stacked`)
    fast_paths = FastPaths(contact_similarity=True, stacked_params=frozenset(), reused=True)
    outputs = {
        "mean_contact_pressure": VarSpec(
            ("p0", "zeta"),
            "Pa",
            "mean pressure in the real contact area",
            description="p0 / (A/A0), A the load-bearing contact area declared by the boundary",
            nan_meaning="no contact (A/A0 = 0, or so small that "
            "p0 / (A/A0) exceeds the float range)",
        ),
        "kappa": VarSpec(("p0",), "1", "area-load slope kappa = (A/A0) E* h'_rms / p0 at zeta_max"),
    }

    def compute(self, ctx: SceneContext, ds: Any) -> dict[str, Any]:
        """Mean contact pressure [Pa] and kappa [1]."""
        names = getattr(type(ctx.boundary), "contact_area", ("area_fraction",))
        area = sum(_loads_by_zeta(ds.variables[n], ctx.p0.size) for n in names)
        with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
            mean_p = ctx.p0[:, None] / np.where(area > 0, area, np.nan)
        mean_p[~np.isfinite(mean_p)] = np.nan
        kappa = area[:, -1] * contact_modulus(ds) * _slope(ds) / ctx.p0
        return {"mean_contact_pressure": (("p0", "zeta"), mean_p), "kappa": (("p0",), kappa)}

    def compute_stacked(self, ctx_of: Any, ds: Any) -> dict[str, Any]:
        """:meth:`compute` for a block of points (leading ``point`` dimension) at once."""
        import xarray as xr

        ctx = ctx_of(0)
        names = getattr(type(ctx.boundary), "contact_area", ("area_fraction",))
        order = ("point", "p0", "zeta")
        area = sum(np.asarray(ds[n].transpose(*order).values, float) for n in names)
        with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
            mean_p = ctx.p0[None, :, None] / np.where(area > 0, area, np.nan)
        mean_p[~np.isfinite(mean_p)] = np.nan

        def points(name: str) -> range:  # each point's, where the Dataset has one per point
            return range(area.shape[0] if "point" in ds.variables[name].dims else 1)

        E_star = np.array([contact_modulus(ds, point=k) for k in points("E_star")])
        slope = np.array([_slope(ds, point=k) for k in points("psd_C")])
        kappa = area[..., -1] * E_star[:, None] * slope[:, None] / ctx.p0[None, :]
        return {
            "mean_contact_pressure": xr.DataArray(mean_p, dims=order),
            "kappa": xr.DataArray(kappa, dims=order[:2]),
        }


def _slope(ds: Any, **point: int) -> float:
    """rms slope [1] of the Dataset's spectrum up to its largest magnification (the solve's:
    :func:`~xpersson.plugins.stored.spectrum_of`), ``sqrt(2 pi int_{q_L}^{q_max} q^3 C dq)``."""
    psd = spectrum_of(ds, **point)
    q_max = float(ds.variables["zeta"].values[-1]) * psd.q_L
    return float(np.sqrt(2 * np.pi * psd.moment(3, psd.q_L, q_max)))


def _loads_by_zeta(var: Any, n_loads: int) -> np.ndarray:
    """The values of ``var`` as (p0, everything else..., zeta) flattened to (p0, -1)."""
    dims = list(var.dims)
    order = [i for i, d in enumerate(dims) if d not in ("p0", "zeta")] + [
        dims.index("p0"),
        dims.index("zeta"),
    ]
    arr = np.transpose(np.asarray(var.values, float), order)
    return arr.reshape(n_loads, -1)
