"""Global attributes: CF/ACDD metadata and JSON provenance (scene, plugins, environment).

Reads only the resolved scene: the plugins' provenance records are captured when the scene is
resolved (this module imports neither the scene nor the registry).

ACDD discovery attributes (creator, institution, project, license, ...) come, weakest first,
from xpersson's defaults, the user's metadata file (:func:`user_metadata`: the TOML file named by
``XPERSSON_METADATA``, else ``$XDG_CONFIG_HOME/xpersson/metadata.toml``, by default
``~/.config/xpersson/metadata.toml``) and the scene's ``[metadata]`` table.
"""

from __future__ import annotations

import copy
import json
import os
import platform
import sys
import time
import tomllib
from importlib import metadata
from pathlib import Path
from typing import Any

import numpy as np

from .cache import Cache, memoize
from .errors import SceneError
from .schema import CONVENTIONS, METADATA_KEYS, STANDARD_NAME_VOCABULARY

__all__ = [
    "global_attributes",
    "scene_json",
    "plugins_used",
    "environment",
    "version",
    "user_metadata",
    "user_metadata_path",
    "METADATA_ENV",
]

METADATA_ENV = "XPERSSON_METADATA"
"""Environment variable naming the user's metadata file (an empty value: no file)."""


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


def user_metadata_path() -> Path | None:
    """The user's metadata file: ``$XPERSSON_METADATA`` when set (empty: none), else
    ``$XDG_CONFIG_HOME/xpersson/metadata.toml`` (``~/.config/...``) when it exists, else None."""
    env = os.environ
    named = env.get(METADATA_ENV)
    if named is not None:
        return Path(named).expanduser() if named.strip() else None
    # strings, not Paths (a look-up at every solve): Path.home() only without $HOME
    base = env.get("XDG_CONFIG_HOME") or os.path.join(
        env.get("HOME") or str(Path.home()), ".config"
    )
    path = os.path.join(base, "xpersson", "metadata.toml")
    return Path(path) if os.path.isfile(path) else None


def user_metadata() -> dict[str, str]:
    """ACDD attributes of the user's metadata file (:func:`user_metadata_path`; {} without one).

    The file is TOML: the keys of a scene's ``[metadata]`` table, at the top level or in a
    ``[metadata]`` table, strings. Read at every solve (parsed once per content).

    Raises
    ------
    SceneError
        When the file named by ``XPERSSON_METADATA`` does not exist, is not TOML, or holds an
        unknown key or a value that is not a string (the message names the file and the key).
    """
    path = user_metadata_path()
    if path is None:
        return {}
    try:
        content = path.read_bytes()
    except OSError:
        raise SceneError(f"{METADATA_ENV}: {path} does not exist or cannot be read") from None
    return dict(_parse_metadata(str(path), content))


@memoize("provenance.user_metadata", scope="process", maxsize=4)
def _parse_metadata(path: str, content: bytes) -> tuple[tuple[str, str], ...]:
    """The validated (key, value) pairs of metadata file ``path`` holding ``content``."""
    try:
        data = tomllib.loads(content.decode("utf-8"))
    except (UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        raise SceneError(f"metadata file {path}: {exc}") from None
    table = data["metadata"] if isinstance(data.get("metadata"), dict) else data
    for key, value in table.items():
        if key not in METADATA_KEYS:
            allowed = ", ".join(sorted(METADATA_KEYS))
            raise SceneError(
                f"metadata file {path}: {key}: unknown key; allowed (ACDD-1.3): {allowed}"
            )
        if not isinstance(value, str):
            raise SceneError(
                f"metadata file {path}: {key}: must be a string, got {type(value).__name__}"
            )
    return tuple(sorted(table.items()))


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
    """JSON of :func:`plugins_used` and the sorted references (the text made at resolution,
    ``ResolvedScene.plugin_records_json``, from the registry's text of each record: each
    record's ``json.dumps`` once per discovery; made here when a scene has none)."""
    used = _plugins_used(rs)
    text = getattr(rs, "plugin_records_json", None)
    if text is None:
        text = json.dumps(used, sort_keys=True)
    return text, sorted({r for p in used for r in p["references"]})


_GRID_JSON = Cache(
    "provenance.grid_json",
    scope="process",
    maxsize=16,
    doc="JSON text of a resolved scene's output grid (float reprs: about 0.4 us per value)",
)
_GRID_TOKEN = "\x00xpersson output grid\x00"
_GRID_TOKEN_JSON = json.dumps(_GRID_TOKEN)
_LOADS_TOKEN = "\x00xpersson loads\x00"
_LOADS_TOKEN_JSON = json.dumps(_LOADS_TOKEN)


def scene_json(resolved: dict[str, Any]) -> str:
    """``json.dumps(resolved, sort_keys=True)``, with the text of the output grid (a list of
    floats, the same for every solve of a study) made once per grid and the text of a list of
    loads (strings, :func:`_strings_json`) made by one join, spliced in."""
    scene, pieces = resolved, {}
    out = resolved.get("output")
    zeta = out.get("zeta") if isinstance(out, dict) else None
    if isinstance(zeta, list) and len(zeta) > 8 and set(map(type, zeta)) == {float}:
        # the list's floats, bit for bit, key their text (repr is a function of the bits)
        grid = _GRID_JSON.get(np.array(zeta, dtype=float), lambda: json.dumps(zeta))
        scene, pieces[_GRID_TOKEN_JSON] = {**scene, "output": {**out, "zeta": _GRID_TOKEN}}, grid
    load = resolved.get("load")
    p0 = load.get("p0") if isinstance(load, dict) else None
    listed = _strings_json(p0) if type(p0) is list and len(p0) > 8 else None
    if listed is not None:
        scene, pieces[_LOADS_TOKEN_JSON] = {**scene, "load": {**load, "p0": _LOADS_TOKEN}}, listed
    if not pieces:
        return json.dumps(resolved, sort_keys=True)
    text = json.dumps(scene, sort_keys=True)
    if any(text.count(token) != 1 for token in pieces):  # a token in the scene's own text
        return json.dumps(resolved, sort_keys=True)
    for token, piece in pieces.items():  # no piece holds a token (no backslash in either)
        text = text.replace(token, piece, 1)
    return text


#: the characters ``json.dumps`` writes as they are (printable ASCII but ``"`` and ``\``)
_PLAIN = bytes(c for c in range(0x20, 0x7F) if c not in b'"\\')


def _strings_json(values: list[Any]) -> str | None:
    """``json.dumps(values)`` of a list of strings by one join (a fifth of its cost for 1000
    loads), where no string holds a character JSON escapes; ``None`` otherwise."""
    try:
        text = '["' + '", "'.join(values) + '"]'
    except TypeError:  # a value that is not a string
        return None
    # only the quotes around the values: each is its own text in JSON
    if text.isascii() and text.encode().translate(None, _PLAIN) == b'"' * (2 * len(values)):
        return text
    return None


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
    # (datetime.now(UTC).replace(microsecond=0).isoformat()'s text, in a third of its time)
    now = time.strftime("%Y-%m-%dT%H:%M:%S+00:00", time.gmtime())
    out = dict(_kind_attributes(rs, user_metadata()))  # a copy: the Dataset's own attrs
    out["history"] = f"{now} {out['history']}"
    out["date_created"] = now
    made = getattr(rs, "resolved_text", None)  # the text made with a reused resolution
    resolved = rs.resolved
    out["xpersson_scene"] = made[1] if made and made[0] is resolved else scene_json(resolved)
    # the file name only: no machine-specific path goes into an archive
    out["xpersson_scene_source"] = Path(rs.scene.source).name if rs.scene.source else "<dict>"
    return out


_KIND = Cache(
    "provenance.kind_attributes",
    scope="process",
    maxsize=64,
    doc="the global attributes every scene of a kind shares (the same plugins, title, "
    "description and metadata, the same user's metadata file), in their order",
)


def _kind_attributes(rs: Any, user: dict[str, str]) -> dict[str, str]:
    """The attributes of :func:`global_attributes` in their order, those that depend only on
    the kind of scene (its plugins' records, title, description and ``[metadata]``) and the
    user's metadata ``user`` set, the others placeholders (``history`` without its time,
    ``date_created``, ``xpersson_scene`` and ``xpersson_scene_source`` empty: set at each
    solve): made once per kind of scene, read only (the caller copies it)."""
    resolved = rs.resolved
    title = resolved.get("title") or "Persson contact-mechanics solution"
    summary = resolved.get("description", _SUMMARY)
    meta = resolved.get("metadata", {})

    def make() -> dict[str, str]:
        release = version()
        plugins_json, refs = _plugins_json(rs)
        return {
            "Conventions": CONVENTIONS,
            "title": title,
            "summary": summary,
            "source": f"xpersson {release}",
            "history": f"xpersson {release} solve",
            "date_created": "",
            "references": "; ".join(f"doi:{r}" if r.startswith("10.") else r for r in refs),
            "keywords": "contact mechanics, roughness, Persson theory, contact area",
            "standard_name_vocabulary": STANDARD_NAME_VOCABULARY,
            "processing_level": "model output",
            "product_version": release,
            **user,  # the user's defaults (a metadata file)
            **dict(meta),  # the scene's ACDD attributes win
            "xpersson_version": release,
            "xpersson_scene": "",
            "xpersson_scene_source": "",
            "xpersson_plugins": plugins_json,
            "xpersson_environment": _environment_json(),
        }

    records = getattr(rs, "plugin_records_json", None)
    if records is None:  # no text of the records to key on: made each time
        return make()
    key = (records, title, summary, tuple(meta.items()), tuple(user.items()))
    try:
        return _KIND.get(key, make)
    except TypeError:  # a value without a content key (not a string)
        return make()


_SUMMARY = (
    "Pressure distribution and contact area of a rough interface by Persson's "
    "multiscale contact theory (diffusion equation in magnification)."
)
