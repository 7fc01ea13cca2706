"""The model error of a finite body's outputs, from the rough-sphere campaign.

The same mechanism as the flat outputs' (:mod:`xpersson.pipeline.model_error`): every covered
output ``X`` of a ``[geometry]`` scene (``real_contact_area``, ``nominal_contact_radius``,
``approach``, over ``force``) gets the CF ancillary variables ``X_exact_low``, ``X_exact_high``
(the interval where exact contact lies) and ``X_model_error_status`` (``verified`` /
``not_verified``; the bounds NaN where not verified). The bands come from the packaged table
``xpersson/data/body_model_error.json``, written by ``benchmarks/bem_sphere_report.py
--write-table`` from the rough-sphere campaign (``benchmarks/bem_sphere_campaign.py``: the
theory against the boundary-element sphere of :mod:`xpersson.bem.sphere`). Its entries have the
model-error table's form; the per-force features are ``johnson`` (Johnson's roughness
parameter ``sigma R / a0^2``) and ``contact_rolloff`` (the Hertz radius times ``q_L``), the
scene's are those of :func:`xpersson.pipeline.model_error.scene_features` plus ``geometry``
(the body's model name). A scene outside every entry is ``not_verified``.
"""

from __future__ import annotations

from importlib import resources
from typing import Any

import numpy as np
import xarray as xr

from ..plugins.stored import spectrum_of
from ._insert import insert_or_set
from .model_error import FLAG, SUFFIXES, band_table, bands_of, nan_meaning, scene_features

__all__ = ["OUTPUTS", "attach_body", "body_table"]

#: The body outputs the campaign compared.
OUTPUTS = ("real_contact_area", "nominal_contact_radius", "approach")


def body_table() -> dict[str, Any]:
    """The packaged body band table (read once)."""
    path = resources.files("xpersson").joinpath("data", "body_model_error.json")
    return band_table(str(path))


def attach_body(ds: xr.Dataset, rs: Any, table: dict[str, Any] | None = None) -> list[str]:
    """Add the ancillary variables of every covered body output of ``ds`` (over ``force``, in
    place); nothing when the scene sets ``[output] model_error = false``. Returns their names.
    """
    if not rs.resolved.get("output", {}).get("model_error", True):
        return []
    table = table or body_table()
    names = {e["variable"] for e in table["bands"]} | set(table.get("variables", ()))
    feats = scene_features(rs) | {"geometry": rs.resolved.get("geometry", {}).get("model")}
    alpha = np.asarray(ds.variables["johnson_parameter"].values, float)
    feats["johnson"] = alpha
    q_L = float(spectrum_of(ds).q_L)  # the solved Dataset's spectrum, as the body's outputs
    feats["contact_rolloff"] = np.asarray(ds.variables["hertz_radius"].values, float) * q_L
    prov = table.get("provenance", {})
    comment = (
        f"rough-sphere campaign {prov.get('campaign', '?')} ({prov.get('date', '?')}): 90 % of "
        "exact/theory over its calibration points in the scene's regime of Johnson's parameter "
        "(docs/user_guide/15_geometry.md)"
    )
    added: list[str] = []
    for name in (n for n in OUTPUTS if n in names and n in ds.data_vars):
        low, high, status = bands_of(name, feats, {}, alpha.shape, table)
        added += _variables(ds, name, low, high, status, comment)
    return added


def _variables(
    ds: xr.Dataset, name: str, low: Any, high: Any, status: Any, comment: str
) -> list[str]:
    """``name``'s three ancillary variables (the bounds are the factors times the value)."""
    var = ds.variables[name]
    x = np.asarray(var.values, float)
    units = var.attrs.get("units", "1")
    quality = {"coverage_content_type": "qualityInformation"}
    new = {}
    for suffix, factor, side in (("_exact_low", low, "lower"), ("_exact_high", high, "upper")):
        new[name + suffix] = xr.Variable(
            var.dims,
            x * factor,
            {
                "units": units,
                "long_name": f"{side} end of the interval where exact contact's {name} lies",
                "comment": f"{comment} {nan_meaning(name)}",
            }
            | quality,
            fastpath=True,  # numpy data: no probe of dask
        )
    new[name + "_model_error_status"] = xr.Variable(
        var.dims,
        status,
        {
            "units": "1",
            "long_name": f"whether the rough-sphere campaign covers {name} in this regime",
            "flag_values": FLAG["flag_values"],
            "flag_meanings": FLAG["flag_meanings"],
        }
        | quality,
        fastpath=True,
    )
    insert_or_set(ds, new)
    ds.variables[name].attrs["ancillary_variables"] = " ".join(name + s for s in SUFFIXES)
    return list(new)
