"""``[geometry]`` and ``load.force``: a finite body pressed on the rough flat by a total force.

``[geometry] model = "flat"`` (the default, or no ``[geometry]`` table) is the nominally flat
contact under ``load.p0``; nothing here runs for it. Any other model is a plugin of the group
``xpersson.geometries`` (``sphere``: ``radius``; ``cylinder``: ``radius`` and ``length``) and
takes ``load.force`` [N] (a value, a list or a range, as ``load.p0``; a cylinder's force is its
total force, the line load is ``force/length``). Everything is checked before any work: the
force's unit and range, a force whose smooth contact outgrows the body (small slopes), a
pressure given to a body or a force given to a flat contact, and a scene whose boundary and
coefficient do not give Persson's separation ``u(p)`` (the coupling needs it).

The body samples the rough interface at the nominal pressures of a grid (:func:`pressure_grid`)
solved in one batch; :mod:`xpersson.pipeline.body` solves the body on it.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from ..errors import SceneError
from ..plugins import Plugin, PluginError, Registry
from ._convert import (
    convert_params,
    increasing_values,
    jsonable,
)
from ._core import CORE

__all__ = ["FLAT", "FORCE", "GeometryPart", "geometry_part", "pressure_grid"]

FLAT = "flat"
"""The default geometry: a nominally flat contact under a nominal pressure ``load.p0``."""
FORCE = dataclasses.replace(
    CORE["load"]["p0"],
    unit="N",
    bounds=(0, 1e12),
    description="total force on the body: scalar, list or {start, stop, num}",
)
"""``load.force``: the total force [N] on a finite body (a cylinder's, over its length)."""
_NEEDS = {
    "boundary": frozenset({"repulsive", "load_similar"}),
    "coefficient": frozenset({"elastic_spectrum"}),
}
PER_DECADE = 8
"""Pressures per decade of the grid the body samples the rough interface on."""


@dataclasses.dataclass(frozen=True)
class GeometryPart:
    """What a scene with a finite body adds to its resolution."""

    geometry: Plugin
    name: str
    force: np.ndarray  # [N], increasing
    scalar: bool
    resolved: dict[str, Any]
    force_resolved: Any


def is_flat(data: Mapping[str, Any]) -> bool:
    """Whether the scene is the flat contact (no ``[geometry]`` or ``model = "flat"``)."""
    geo = data.get("geometry")
    return geo is None or (isinstance(geo, Mapping) and geo.get("model", FLAT) == FLAT)


def check_load_keys(data: Mapping[str, Any]) -> None:
    """A pressure for the flat contact, a force for a body: one clear line otherwise."""
    geo = data.get("geometry")
    if geo is not None and not isinstance(geo, Mapping):
        raise SceneError(f"geometry: must be a table, got {type(geo).__name__}")
    load = data.get("load")
    if not isinstance(load, Mapping):
        return
    if is_flat(data):
        if geo is not None and set(geo) - {"model"}:
            extra = sorted(set(geo) - {"model"})[0]
            raise SceneError(f"geometry.{extra}: unknown parameter; the flat geometry has none")
        if "force" in load:
            raise SceneError(
                "load.force: a total force needs a finite body; give [geometry] model = "
                "'sphere' (radius) or 'cylinder' (radius, length), or a nominal pressure "
                "load.p0 [Pa] for the flat contact"
            )
        return
    model = geo.get("model")
    if "p0" in load:
        raise SceneError(
            f"load.p0: a {model} takes a total force load.force [N] (e.g. '1 N'), not a "
            "nominal pressure; the nominal pressure is solved for"
        )
    if "force" not in load:
        raise SceneError(f"load.force: required for geometry {model!r} (a total force [N])")
    unknown = sorted(set(load) - {"force"})
    if unknown:
        raise SceneError(f"load.{unknown[0]}: unknown parameter; allowed in [load]: force")


def forces(raw: Any) -> tuple[np.ndarray, bool]:
    """``load.force`` in N (strictly increasing when a list) and whether it was a scalar."""
    return increasing_values(FORCE, raw, "load.force", "forces")


def geometry_part(data: Mapping[str, Any], registry: Registry, E_star: float) -> GeometryPart:
    """The geometry plugin and the forces of a scene with a finite body (checked)."""
    raw = dict(data["geometry"])
    model = raw.pop("model")
    try:
        cls = registry.resolve("geometries", model)
    except (PluginError, TypeError) as exc:
        raise SceneError(f"geometry.model: {exc}; or 'flat' (the default)") from None
    params = convert_params(cls.parameters, raw, "geometry")
    try:
        geo = cls(**params)
    except (ValueError, TypeError) as exc:
        raise SceneError(f"geometry: {exc}") from None
    force, scalar = forces(data["load"]["force"])
    for f in force:
        try:
            geo.check_force(float(f), E_star)
        except ValueError as exc:
            raise SceneError(f"load.{exc} (geometry {model!r})") from None
    name = model if isinstance(model, str) else registry.name_of("geometries", cls)[0]
    texts = [f"{v!r} N" for v in force.tolist()]  # re-loads to exactly these forces
    force_res = texts[0] if scalar else texts
    return GeometryPart(
        geo, name, force, scalar, {"model": name, **jsonable(params, cls.parameters)}, force_res
    )


def check_plugins(plugins: Mapping[str, Plugin], model: str) -> None:
    """The coupling needs Persson's ``u(p)``: an elastic, load-similar, repulsive contact."""
    for section, need in _NEEDS.items():
        have = frozenset(getattr(type(plugins[section]), "traits", ()))
        if not need <= have:
            raise SceneError(
                f"geometry: a {model} couples to the separation u(p) of an elastic contact; "
                f"the {section} must declare the traits {', '.join(sorted(need))} "
                f"({type(plugins[section]).__name__} declares {', '.join(sorted(have)) or 'none'})"
            )


def pressure_grid(part: GeometryPart, E_star: float) -> np.ndarray:
    """Nominal pressures [Pa] the rough interface is solved at: from 1e-4 of the smallest
    force's mean Hertz pressure to twice the largest peak, :data:`PER_DECADE` per decade."""
    geo = part.geometry
    means, peaks = [], []
    for f in part.force:
        _, _, peak = geo.reference(geo.solver_load(float(f)), E_star)
        peaks.append(peak)
        means.append(peak * (2.0 / 3.0 if geo.symmetry == "axisymmetric" else math.pi / 4))
    lo, hi = 1e-4 * min(means), 2.0 * max(peaks)
    num = max(24, math.ceil(PER_DECADE * math.log10(hi / lo)) + 1)
    return np.geomspace(lo, hi, num)
