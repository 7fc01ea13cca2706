"""Scenes: parse, validate and resolve a TOML file or dict into plugins and SI arrays.

Everything is checked before any work starts: dimensionality and ranges of every quantity,
unknown keys (named in the error), plugin names, and the spectrum's own consistency
(``q_L < q_r <= q_1``). Errors are :class:`SceneError` and name the parameter as
``section.key``, its unit and the allowed range.

Modules: ``_core`` (the core sections' parameters and limits, :class:`ResolvedScene`),
``_convert`` (values: kinds, units, ranges, sweep values), ``_resolve`` (resolution into
plugins, labels and provenance records), ``_scene`` (:class:`Scene`, :func:`load_scene`).
"""

from __future__ import annotations

from ..errors import SceneError
from ._convert import (
    RANGE_KEYS,
    convert_param,
    convert_params,
    is_sweep_value,
    sweep_values,
)
from ._core import (
    CORE,
    DEFAULT_MODEL,
    MAX_POINTS,
    MAX_PRESSURE,
    MAX_ZETA,
    PLUGIN_SECTIONS,
    TOP_LEVEL,
    ResolvedScene,
)
from ._resolve import analysis_plan, plugin_message, plugin_records, with_spectrum
from ._scene import Scene, load_scene, parse_cli_value, set_value

__all__ = [
    "CORE",
    "DEFAULT_MODEL",
    "MAX_POINTS",
    "MAX_PRESSURE",
    "MAX_ZETA",
    "PLUGIN_SECTIONS",
    "RANGE_KEYS",
    "TOP_LEVEL",
    "ResolvedScene",
    "Scene",
    "SceneError",
    "analysis_plan",
    "convert_param",
    "convert_params",
    "is_sweep_value",
    "load_scene",
    "parse_cli_value",
    "plugin_message",
    "plugin_records",
    "set_value",
    "sweep_values",
    "with_spectrum",
]
