"""A finite body's analyses after the fact (:func:`analyse_body`).

A ``[geometry]`` archive holds the solved flat (over the pressure grid ``p0``) and the body's
outputs over ``force`` (and ``r``). The analysis runs on the flat as the solve ran it
(:mod:`._point`); the body is then computed again from that Dataset
(:func:`xpersson.pipeline.body.body_dataset`: the same separation and nominal pressure, bit for
bit, since it reads only the flat's Dataset and the scene's geometry), which integrates the
analysis's declared local quantities (``body_quantities``) over the body's nominal pressure.
The body's grid of cells is not stored, so this one body solve is repeated (a fraction of a
second); the flat is not solved again.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import xarray as xr

from .. import plugins
from ..cache import solve_scope
from ..errors import ArchiveError
from ..pipeline.body import OUTPUTS as BODY_OUTPUTS
from ..pipeline.body import body_dataset
from ..pipeline.model_error import SUFFIXES
from ..plugins import get_registry
from ..plugins.solved import unresolved_quiet
from ._point import analysed, archived_scene, attach_model_error, point_scene

__all__ = ["analyse_body", "is_body"]


def is_body(ds: xr.Dataset) -> bool:
    """Whether ``ds`` is a finite body's Dataset (its ``geometry`` attribute)."""
    return "geometry" in ds.attrs


def analyse_body(ds: xr.Dataset, name: str, params: dict[str, Any]) -> xr.Dataset:
    """:func:`xpersson.analyse` of a finite body's Dataset (see its docstring)."""
    data = archived_scene(ds, body=True)
    flat = ds.drop_vars(_body_variables(ds, data))
    data["analyses"] = {name: dict(params)}
    rs = point_scene(data, flat)
    _check_forces(rs, ds)
    with plugins.time_limit(rs.plugin_time_limit), solve_scope(), unresolved_quiet():
        out, ctx = analysed(rs, flat)
        body = body_dataset(rs, ctx, out)
    kept = {n: ds.variables[n] for n in ds.data_vars if n not in body.variables}
    out = body.assign(kept)  # the other analyses' body quantities, as the archive has them
    attach_model_error(out, ds, data)
    return out


def _check_forces(rs: Any, ds: xr.Dataset) -> None:
    """The Dataset's forces must be its scene's (the flat's grid of loads was chosen for all
    of them, and the body is computed again for each)."""
    force = np.atleast_1d(np.asarray(ds["force"].values, dtype=float))
    if not np.array_equal(force, np.asarray(rs.force, dtype=float)):
        raise ArchiveError(
            "the Dataset's force is not its scene's (was it subset along force with sel/isel?): "
            "the pressure grid p0 was chosen for all the scene's forces and the body is "
            "computed again for each; analyse the whole Dataset, then select forces"
        )


def _body_variables(ds: xr.Dataset, data: dict[str, Any]) -> list[str]:
    """The names of ``ds``'s body variables: along ``force`` or ``r``, the body's outputs and
    their model-error variables, and the archived analyses' body quantities."""
    names = {"force", "r", *BODY_OUTPUTS}
    names |= {n + s for n in BODY_OUTPUTS for s in SUFFIXES}
    registry = get_registry()
    for analysis in data.get("analyses", {}) or {}:
        try:
            cls = registry.load("analyses", analysis)
        except Exception:  # noqa: BLE001 - an analysis no longer installed: its dims decide
            continue
        for q in getattr(cls, "body_quantities", {}) or {}:
            names |= {q, f"{q}_grid_error"}
    along = {n for n, v in ds.variables.items() if {"force", "r"} & set(v.dims)}
    return sorted((names | along) & set(ds.variables))
