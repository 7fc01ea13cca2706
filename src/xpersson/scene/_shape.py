"""A scene's shape checked before anything is converted: its top-level keys, each section's
type, the required sections, ``[metadata]``'s keys and ``solver.method``'s name (the first
checks of :func:`._resolve.resolve_scene`)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from ..errors import SceneError
from ._core import CORE, METADATA_KEYS, PLUGIN_SECTIONS, TOP_LEVEL
from ._geometry import check_load_keys, is_flat

__all__ = ["check_method", "check_sections"]


def check_method(method: Any) -> None:
    """``solver.method`` is ``"auto"``, a registered method name or an EngineMethod class."""
    if method == "auto":  # the default (no look-up of the engine's methods)
        return
    from ..engine import METHODS, EngineMethod

    if isinstance(method, type):
        if not issubclass(method, EngineMethod):
            raise SceneError(
                f"solver.method: {method!r} is not an xpersson.engine.EngineMethod subclass"
            )
        return
    if method != "auto" and method not in METHODS:
        raise SceneError(
            f"solver.method: {method!r} is not an engine method; one of "
            f"{', '.join(['auto', *sorted(METHODS)])}"
        )


def check_sections(data: Mapping[str, Any]) -> None:
    """Top-level keys, section types and the required sections."""
    unknown = sorted(set(data) - TOP_LEVEL)
    if unknown:
        raise SceneError(
            f"{unknown[0]}: unknown section or key; allowed: {', '.join(sorted(TOP_LEVEL))}"
        )
    if "sweep" in data:
        raise SceneError(
            "sweep: a sweep scene is solved point by point; use xpersson.solve "
            "(or xpersson.sweep.expand to list its points)"
        )
    for key in ("title", "description"):
        if key in data and not isinstance(data[key], str):
            raise SceneError(f"{key}: must be a string")
    _check_metadata(data.get("metadata", {}))
    for sec in (*CORE, *PLUGIN_SECTIONS, "analyses"):
        if sec in data and not isinstance(data[sec], Mapping):
            raise SceneError(f"{sec}: must be a table, got {type(data[sec]).__name__}")
    if "spectrum" not in data:
        raise SceneError("spectrum: required section (e.g. model = 'self_affine')")
    check_load_keys(data)
    if "load" not in data or ("p0" not in data["load"] and is_flat(data)):
        raise SceneError("load.p0: required (nominal pressure, e.g. '1 MPa')")


def _check_metadata(meta: Any) -> None:
    """``[metadata]``: ACDD discovery attributes, strings, from :data:`METADATA_KEYS`."""
    if not isinstance(meta, Mapping):
        raise SceneError(f"metadata: must be a table, got {type(meta).__name__}")
    for key, value in meta.items():
        if key not in METADATA_KEYS:
            allowed = ", ".join(sorted(METADATA_KEYS))
            raise SceneError(f"metadata.{key}: unknown key; allowed (ACDD-1.3): {allowed}")
        if not isinstance(value, str):
            raise SceneError(f"metadata.{key}: must be a string, got {type(value).__name__}")
