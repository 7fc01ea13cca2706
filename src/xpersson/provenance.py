"""Global attributes: CF/ACDD metadata and JSON provenance (scene, plugins, environment).

Reads only the resolved scene: the plugins' provenance records are captured when the scene is
resolved (this module imports neither the scene nor the registry).
"""

from __future__ import annotations

import copy
import datetime as _dt
import json
import platform
import sys
from importlib import metadata
from typing import Any

from .cache import memoize
from .schema import CONVENTIONS

__all__ = ["global_attributes", "plugins_used", "environment", "version"]


@memoize("provenance.version", scope="process", maxsize=1)
def version() -> str:
    """Installed version of xpersson (read once per process)."""
    try:
        return metadata.version("xpersson")
    except metadata.PackageNotFoundError:  # running from a source tree
        return "0+unknown"


@memoize("provenance.environment", scope="process", maxsize=1)
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


def plugins_used(rs: Any) -> list[dict[str, Any]]:
    """Group, name, distribution, version, class and references of every plugin of a run.

    Parameters
    ----------
    rs : ResolvedScene
        The resolved scene; its ``plugin_records`` were captured at resolution.
    """
    return copy.deepcopy(_plugins_used(rs))


def _plugins_used(rs: Any) -> list[dict[str, Any]]:
    """:func:`plugins_used` sharing the cached records (read-only: only serialised)."""
    return [{**record, "name": name} if name else record for record, name in rs.plugin_records]


def _plugins_json(rs: Any) -> tuple[str, list[str]]:
    """JSON of :func:`plugins_used` and the sorted references (about 13 us: no cache, whose
    content key of the records would cost as much)."""
    used = _plugins_used(rs)
    return json.dumps(used, sort_keys=True), sorted({r for p in used for r in p["references"]})


def global_attributes(rs: Any, registry: Any = None) -> dict[str, str]:
    """CF-1.12 / ACDD-1.3 global attributes and the JSON provenance of a run.

    Parameters
    ----------
    rs : ResolvedScene
        The resolved scene: its resolved values, source and the plugin records captured at
        resolution (:attr:`~xpersson.scene.ResolvedScene.plugin_records`).
    registry : object, optional
        Ignored (the records were captured at resolution); accepted until every caller passes
        ``rs`` alone.

    Returns
    -------
    dict
        Global attributes (str values).
    """
    del registry
    now = _dt.datetime.now(_dt.UTC).replace(microsecond=0).isoformat()
    plugins_json, refs = _plugins_json(rs)
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
        **dict(rs.resolved.get("metadata", {})),  # the scene's ACDD attributes win
        "xpersson_version": version(),
        "xpersson_scene": json.dumps(rs.resolved, sort_keys=True),
        "xpersson_scene_source": rs.scene.source or "<dict>",
        "xpersson_plugins": plugins_json,
        "xpersson_environment": _environment_json(),
    }
