"""Scenes as written by the user: a nested dict (from TOML or Python) and where it came from."""

from __future__ import annotations

import copy
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..errors import SceneError
from ..plugins import Registry, get_registry
from ._core import ResolvedScene
from ._resolve import resolve_scene

__all__ = ["Scene", "load_scene", "parse_cli_value", "set_value"]


#: Immutable leaves of a scene tree (shared by its copies).
_LEAVES = {str, int, float, bool}


def _copy_tree(obj: Any) -> Any:
    """A deep copy of a scene tree: tables and lists rebuilt, immutable leaves shared."""
    if isinstance(obj, dict):
        return {k: _copy_tree(v) for k, v in obj.items()}
    if isinstance(obj, list):
        if set(map(type, obj)) <= _LEAVES:  # e.g. 1000 load strings: one copy, no recursion
            return list(obj)
        return [_copy_tree(v) for v in obj]
    if obj is None or type(obj) in _LEAVES:
        return obj
    return copy.deepcopy(obj)


def _surface_topography(data: dict[str, Any]) -> dict[str, Any]:
    """A SurfaceTopography ``Topography`` given as the spectrum (or as ``spectrum.topography``)
    becomes the inline PSD table it gives, with what reproduces it (issue 26)."""
    from ..builtin.topography import from_surface_topography, is_surface_topography

    spec = data.get("spectrum")
    if is_surface_topography(spec):
        try:
            data["spectrum"] = from_surface_topography(spec)
        except ValueError as exc:
            raise SceneError(f"spectrum: {exc}") from None
    elif isinstance(spec, Mapping) and is_surface_topography(spec.get("topography")):
        rest = {k: v for k, v in spec.items() if k not in ("topography", "model")}
        if spec.get("model", "topography") != "topography":
            raise SceneError("spectrum.topography: a Topography object needs model 'topography'")
        ppd = rest.pop("points_per_decade", 20)
        try:
            data["spectrum"] = from_surface_topography(spec["topography"], ppd, **rest)
        except ValueError as exc:
            raise SceneError(f"spectrum.topography: {exc}") from None
    return data


@dataclass
class Scene:
    """A scene as written by the user (a nested dict), plus where it came from.

    Use :func:`load_scene` for files, ``Scene(dict)`` for dicts; :meth:`resolve` checks
    everything and returns a :class:`ResolvedScene`.
    """

    data: dict[str, Any]
    source: str | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.data, Mapping):
            raise SceneError(f"a scene must be a mapping of sections, got {type(self.data)}")
        self.data = _copy_tree(_surface_topography(dict(self.data)))

    @classmethod
    def _shared(cls, data: dict[str, Any], source: str | None = None) -> Scene:
        """A scene over ``data`` as it is (no copy, no conversion of a Topography): for data
        built from a scene made already, whose tables the caller does not change (a sweep's
        point scenes share their unswept tables with the plan's base, read only)."""
        out = cls.__new__(cls)
        out.data, out.source = data, source
        return out

    def with_values(self, **dotted: Any) -> Scene:
        """Copy with ``section.key`` values replaced: ``with_values(**{"load.p0": "1 MPa"})``."""
        new = Scene(self.data, self.source)
        for key, value in dotted.items():
            set_value(new.data, key, value)
        return new

    def resolve(self, registry: Registry | None = None) -> ResolvedScene:
        """Validate and resolve; raises :class:`SceneError` before any work."""
        return resolve_scene(self, registry or get_registry())


def load_scene(path: str | Path) -> Scene:
    """Read a TOML scene file.

    Parameters
    ----------
    path : str or pathlib.Path
        The ``.toml`` file.

    Raises
    ------
    SceneError
        The file is missing or is not valid TOML.
    """
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8")
    except OSError as exc:
        raise SceneError(f"cannot read scene file {str(p)!r}: {exc.strerror}") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(f"{p}: invalid TOML: {exc}") from None
    return Scene(data, source=str(p.resolve()))


def set_value(data: dict[str, Any], dotted: str, value: Any) -> None:
    """Set ``data[section][key] = value`` from a dotted name (creating the section)."""
    parts = dotted.split(".")
    if len(parts) < 2 or not all(parts):
        raise SceneError(f"--set needs section.key=value, got {dotted!r}")
    node = data
    for part in parts[:-1]:
        nxt = node.setdefault(part, {})
        if not isinstance(nxt, dict):
            raise SceneError(f"{dotted}: {part!r} is not a table")
        node = nxt
    node[parts[-1]] = value


def parse_cli_value(text: str) -> Any:
    """Interpret a ``--set`` value: a TOML value if it parses, else the raw string."""
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        return text
