"""Diagnostics the pipeline adds to every Dataset: resolution of the stored P, theory regime.

* ``P_integral(p0, zeta)``: ``int P dp`` over the stored pressure grid (trapezoidal rule) and
  ``P_resolved(p0, zeta)``: 1 where it equals ``area_fraction`` within
  :data:`P_RTOL`, 0 where the grid does not resolve the distribution (a narrow peak at small
  magnification, or mass beyond the grid's ends). The contact area itself never comes from P.
* regime warnings: the scene lies outside the range where Persson's small-slope, linear-elastic
  theory holds (rms slope far above 1, nominal pressure above the contact modulus).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..plugins import VarSpec

__all__ = ["P_RTOL", "SLOPE_LIMIT", "DIAGNOSTICS", "pdf_resolution", "regime_warnings"]

P_RTOL = 1e-3
"""Relative agreement of int P dp with A/A0 that counts as resolved."""
SLOPE_LIMIT = 3.0
"""rms slope above which the small-slope theory is reported as left [1]."""

DIAGNOSTICS: dict[str, VarSpec] = {
    "P_integral": VarSpec(
        ("p0", "zeta"),
        "1",
        "integral of P over the stored pressure grid",
        description="trapezoidal int P dp; equals area_fraction where P_resolved is 1",
    ),
    "P_resolved": VarSpec(
        ("p0", "zeta"),
        "1",
        "whether the stored P resolves the distribution",
        description=f"1 where |int P dp - A/A0| <= {P_RTOL:g} A/A0 on the stored grid",
        extra={"flag_meanings": "unresolved resolved"},
        valid_min=0,
        valid_max=1,
    ),
}


def pdf_resolution(ds: Any) -> str | None:
    """Add ``P_integral`` and ``P_resolved`` to ``ds`` (when it holds P); return a message
    naming the unresolved zeta points, or ``None`` when every point is resolved."""
    if "P" not in ds or "p" not in ds.dims:
        return None
    P = ds["P"].transpose("p0", "zeta", "p")
    p = np.asarray(ds["p"].values, float)
    integral = np.trapezoid(np.asarray(P.values, float), p, axis=-1)
    area = np.asarray(ds["area_fraction"].transpose("p0", "zeta").values, float)
    ok = np.abs(integral - area) <= P_RTOL * np.maximum(area, 1e-300)
    ds["P_integral"] = (("p0", "zeta"), integral)
    ds["P_resolved"] = (("p0", "zeta"), ok.astype(np.int8))
    for name, spec in DIAGNOSTICS.items():
        ds[name].attrs.update(spec.attrs())
    flags = ds["P_resolved"].attrs
    flags["flag_values"] = np.array([0, 1], np.int8)
    # CF 2.5: the valid range has the variable's own type
    flags["valid_min"], flags["valid_max"] = np.int8(0), np.int8(1)
    zeta = np.asarray(ds["zeta"].values, float)
    # at zeta = 1 (tau = 0) P is the initial delta: flagged, but no reason to warn
    ok_or_delta = ok | (np.asarray(ds["diffusion_time"].values, float) == 0)[None, :]
    if ok_or_delta.all():
        return None
    bad_z = zeta[~ok_or_delta.all(axis=0)]
    return (
        f"P is not resolved by the stored pressure grid at {int((~ok_or_delta).sum())} of "
        f"{ok.size} "
        f"(p0, zeta) points (zeta {bad_z.min():.4g} .. {bad_z.max():.4g}; see P_resolved, "
        "P_integral): a finer grid (output.p_points, output.p) or a narrower zeta range "
        "resolves them"
    )


def regime_warnings(ds: Any) -> list[str]:
    """Where the scene leaves the regime of the theory (each a one-line message)."""
    out = []
    var = ds.variables  # plain Variables: no DataArray (with its coordinates) per lookup
    slope = float(var["rms_slope"].values)
    if slope > SLOPE_LIMIT:
        out.append(
            f"rms slope {slope:.3g} is far above 1: Persson's theory assumes small slopes "
            f"(warned above {SLOPE_LIMIT:g})"
        )
    e_star = float(var["E_star"].values)
    p0 = np.asarray(var["p0"].values, float)
    high = p0[p0 > e_star]
    if high.size:
        out.append(
            f"{high.size} load(s) p0 up to {high.max():.4g} Pa exceed the contact modulus "
            f"E* = {e_star:.4g} Pa: strains of order 1 are outside linear elasticity"
        )
    return out
