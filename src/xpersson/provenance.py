"""Global attributes: CF/ACDD metadata and JSON provenance (scene, plugins, environment)."""

from __future__ import annotations

import copy
import datetime as _dt
import functools
import json
import platform
import sys
from importlib import metadata
from typing import TYPE_CHECKING, Any

from .schema import CONVENTIONS

if TYPE_CHECKING:  # pragma: no cover
    from .plugins._registry import Registry
    from .scene import ResolvedScene

__all__ = ["global_attributes", "plugins_used", "environment", "version"]


@functools.lru_cache(maxsize=1)
def version() -> str:
    """Installed version of xpersson (read once per process)."""
    try:
        return metadata.version("xpersson")
    except metadata.PackageNotFoundError:  # running from a source tree
        return "0+unknown"


@functools.lru_cache(maxsize=1)
def _environment_json() -> str:
    env = {"python": sys.version.split()[0], "platform": platform.platform()}
    for pkg in ("numpy", "scipy", "xarray", "netCDF4", "pint"):
        try:
            env[pkg] = metadata.version(pkg)
        except metadata.PackageNotFoundError:
            env[pkg] = "not installed"
    return json.dumps(env, sort_keys=True)


def environment() -> dict[str, str]:
    """Python, platform and the versions of the numerical stack (computed once per process)."""
    return json.loads(_environment_json())


_PLUGIN_RECORDS: dict[tuple[str, type, int], tuple[Any, Any, dict[str, Any]]] = {}


def _shared_record(group: str, cls: type, reg: Registry) -> dict[str, Any]:
    """:func:`plugin_provenance`, looked up once per (group, class, registry discovery).

    Returns the cached record itself: callers must not modify it.
    """
    from .plugins._registry import plugin_provenance

    key = (group, cls, id(reg))
    found = reg._discover()  # noqa: SLF001 - cached discovery; a refresh() replaces it
    hit = _PLUGIN_RECORDS.get(key)
    if hit is None or hit[0] is not reg or hit[1] is not found:
        if len(_PLUGIN_RECORDS) > 256:
            _PLUGIN_RECORDS.clear()
        hit = (reg, found, plugin_provenance(group, cls, reg))
        _PLUGIN_RECORDS[key] = hit
    return hit[2]


def plugins_used(rs: ResolvedScene, reg: Registry) -> list[dict[str, Any]]:
    """Group, name, distribution, version, class and references of every plugin of a run."""
    return copy.deepcopy(_plugins_used(rs, reg))


def _items(rs: ResolvedScene) -> list[tuple[str, Any, Any]]:
    """(group, name, instance) of every plugin of a run."""
    return [
        ("spectra", rs.plugin_names.get("spectrum"), rs.spectrum),
        ("coefficients", rs.plugin_names.get("coefficient"), rs.coefficient),
        ("boundaries", rs.plugin_names.get("boundary"), rs.boundary),
        *[("analyses", name, inst) for name, inst in rs.analyses],
    ]


def _plugins_used(rs: ResolvedScene, reg: Registry) -> list[dict[str, Any]]:
    """:func:`plugins_used` sharing the cached records (read-only: only serialised)."""
    out = []
    for group, name, inst in _items(rs):
        record = _shared_record(group, type(inst), reg)
        out.append({**record, "name": name} if name else record)
    return out


_PLUGINS_JSON: dict[tuple, tuple[Any, Any, str, list[str]]] = {}


def _plugins_json(rs: ResolvedScene, reg: Registry) -> tuple[str, list[str]]:
    """JSON of :func:`plugins_used` and the sorted references, serialised once per set of
    plugin classes and names (the records are cached per registry discovery)."""
    key = (id(reg), *((group, type(inst), name) for group, name, inst in _items(rs)))
    found = reg._discover()  # noqa: SLF001 - cached discovery; a refresh() replaces it
    hit = _PLUGINS_JSON.get(key)
    if hit is None or hit[0] is not reg or hit[1] is not found:
        used = _plugins_used(rs, reg)
        if len(_PLUGINS_JSON) > 256:
            _PLUGINS_JSON.clear()
        refs = sorted({r for p in used for r in p["references"]})
        hit = (reg, found, json.dumps(used, sort_keys=True), refs)
        _PLUGINS_JSON[key] = hit
    return hit[2], hit[3]


def global_attributes(rs: ResolvedScene, reg: Registry) -> dict[str, str]:
    """CF-1.12 / ACDD-1.3 global attributes and the JSON provenance of a run."""
    now = _dt.datetime.now(_dt.UTC).replace(microsecond=0).isoformat()
    plugins_json, refs = _plugins_json(rs, reg)
    title = rs.resolved.get("title") or "Persson contact-mechanics solution"
    return {
        "Conventions": CONVENTIONS,
        "title": title,
        "summary": rs.resolved.get(
            "description",
            "Pressure distribution and contact area of a rough interface by Persson's "
            "multiscale contact theory (diffusion equation in magnification).",
        ),
        "source": f"xpersson {version()}",
        "history": f"{now} xpersson {version()} solve",
        "date_created": now,
        "references": "; ".join(f"doi:{r}" if r.startswith("10.") else r for r in refs),
        "keywords": "contact mechanics, roughness, Persson theory, contact area",
        "xpersson_version": version(),
        "xpersson_scene": json.dumps(rs.resolved, sort_keys=True),
        "xpersson_scene_source": rs.scene.source or "<dict>",
        "xpersson_plugins": plugins_json,
        "xpersson_environment": _environment_json(),
    }
