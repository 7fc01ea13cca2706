"""Sweep points derived from one resolved point (issue 25: stacked sweeps resolved per block).

Where every swept parameter is a parameter of the scene's ``coefficient`` or ``boundary`` that
its plugin declares stackable (``fast_paths.stacked_params``), the points of a region differ
from its first point only in those plugins' parameters. Only that first point is resolved in
full (scene checks, spectrum, grids, provenance); the swept values are converted and
range-checked once per value (as a point's resolution converts them), and every other point is
the first with new plugin instances built from the merged parameters (the plugin's own
``__init__`` checks run per point, so a bad combination fails here, before any work, with the
message point-by-point resolution gives: the point's swept values, the section and parameter,
its unit and allowed range).
"""

from __future__ import annotations

import dataclasses
import itertools
from collections.abc import Callable
from typing import Any

from ..checks import plugin_label
from ..plugins import fast_paths_on
from ..scene import SceneError, convert_param, plugin_message, sweep_values
from .plan import SweepPlan

__all__ = ["derived_region"]

#: The scene sections whose swept parameters may be derived (one plugin instance per point).
SECTIONS = ("coefficient", "boundary")


def _swept(plan: SweepPlan) -> list[tuple[int, Any, str, str]] | None:
    """``(dimension, param, section, key)`` of every swept parameter, or ``None`` when one is
    not a coefficient or boundary parameter."""
    out = []
    for d, group in enumerate(plan.groups):
        for p in group:
            section, _, key = p.path.partition(".")
            if section not in SECTIONS or not key or "." in key:
                return None
            out.append((d, p, section, key))
    return out


def _declared(rs: Any, swept: list[tuple[int, Any, str, str]]) -> bool:
    """Whether each swept parameter is in its plugin's ``fast_paths.stacked_params``."""
    return all(type(getattr(rs, section)).fast_paths.stacks(key) for _, _, section, key in swept)


def derived_region(
    plan: SweepPlan,
    start: tuple[int, ...],
    stop: tuple[int, ...],
    resolve: Callable[[tuple[int, ...]], Any],
    where: Callable[[tuple[int, ...]], str],
    registry: Any,
) -> list[Any] | None:
    """The resolved points of the region ``start:stop`` (C order) from one resolved point, or
    ``None`` where the sweep's parameters are not all declared stackable (resolve each point).

    Parameters
    ----------
    plan : SweepPlan
        The sweep.
    start, stop : tuple of int
        The region (the whole plan or one block).
    resolve : callable
        ``resolve(index)`` resolves the point at a global index (raising its SceneError).
    where : callable
        ``where(index)`` names a point's swept values for messages.
    registry : Registry
        The plugin registry (labels of the derived plugins).
    """
    swept = _swept(plan)
    if not fast_paths_on() or swept is None or plan.size < 2:
        return None
    rs0 = resolve(tuple(start))
    if not _declared(rs0, swept):
        return None
    # each swept value converted once, as a point's resolution converts it (SI value, archive)
    values: dict[str, dict[int, tuple[Any, Any]]] = {}
    for d, p, section, key in swept:
        spec = type(getattr(rs0, section)).parameters[key]
        entries = {i: p.scene_value(i) for i in range(start[d], stop[d])}  # as archived
        converted = _converted(spec, list(entries.values()), p.path)
        values[p.path] = dict(zip(entries, converted, strict=True))
    ranges = [range(a, b) for a, b in zip(start, stop, strict=True)]
    out = []
    for index in itertools.product(*ranges):
        if index == tuple(start):
            out.append(rs0)
            continue
        changes: dict[str, dict[str, tuple[Any, Any]]] = {}
        for d, p, section, key in swept:
            changes.setdefault(section, {})[key] = values[p.path][index[d]]
        try:
            out.append(_derive(rs0, changes, registry))
        except SceneError as exc:
            raise SceneError(f"sweep point {where(index)}: {exc}") from None
    return out


def _converted(spec: Any, entries: list[Any], where: str) -> list[tuple[Any, Any]]:
    """``(SI value, entry)`` of each swept entry, as :func:`~xpersson.scene.convert_param`
    converts it: a list of quantity strings at once (one parse per unit,
    :func:`~xpersson.scene.sweep_values`: the same floats), anything else value by value."""
    if spec.kind == "quantity" and not spec.array and spec.unit not in ("1", ""):
        try:
            si = sweep_values(spec, entries, where).tolist()
        except SceneError:  # the message of convert_param, naming the value
            si = None
        if si is not None and len(si) == len(entries):
            return list(zip(si, entries, strict=True))
    return [(convert_param(spec, entry, where), entry) for entry in entries]


def _derive(rs0: Any, changes: dict[str, dict[str, tuple[Any, Any]]], registry: Any) -> Any:
    """``rs0`` with the plugins of ``changes`` (section -> key -> (SI value, archived value))
    rebuilt; the analyses' scene checks run again against them."""
    plugins = {s: getattr(rs0, s) for s in SECTIONS}
    resolved = dict(rs0.resolved)
    labels = dict(rs0.labels)
    for section, new in changes.items():
        cls = type(plugins[section])
        params = {**plugins[section].params, **{k: v[0] for k, v in new.items()}}
        try:
            plugins[section] = cls(**params)
        except (ValueError, TypeError) as exc:
            raise SceneError(plugin_message(section, cls, exc)) from None
        resolved[section] = {**resolved[section], **{k: v[1] for k, v in new.items()}}
        labels[section] = plugin_label(
            section, plugins[section], registry, rs0.plugin_names[section]
        )
    names = rs0.plugin_names
    for name, inst in rs0.analyses:
        try:
            inst.check_scene(plugins["coefficient"], plugins["boundary"])
        except (ValueError, TypeError) as exc:
            msg = plugin_message(f"analyses.{name}", type(inst), exc)
            raise SceneError(
                f"{msg} (scene: boundary {names['boundary']!r}, "
                f"coefficient {names['coefficient']!r})"
            ) from None
    return dataclasses.replace(rs0, **plugins, resolved=resolved, labels=labels)
