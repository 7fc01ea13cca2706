"""Entry-point scanning: what the registry knows about a plugin without importing it.

One discovery pass (:func:`discover`) reads the entry points of the installed distributions
(:mod:`._metadata`, one scan per pass) into :class:`PluginInfo` records, warns about malformed
names and names registered twice, and adds the classes registered directly; the checks of names
and loaded classes live here too. :mod:`._registry` keeps the result as its discovery state and
imports plugins on demand.
"""

from __future__ import annotations

import importlib
import re
import warnings
from dataclasses import dataclass
from importlib.metadata import EntryPoint, EntryPoints
from typing import Any

from ._groups import ENTRY_POINT_PREFIX, GROUP_NAMES, PLUGIN_GROUPS
from ._limits import IMPORT_TIME_LIMIT, current_limit, limited
from ._metadata import dist_of as _dist_of
from ._metadata import scan as _scan

__all__ = [
    "CORE_DIST",
    "DIRECT",
    "PluginError",
    "PluginInfo",
    "check_loaded",
    "check_name",
    "discover",
    "duplicate_message",
    "import_target",
    "norm",
    "normalize_group",
    "qualname",
]

CORE_DIST = "xpersson"
DIRECT = "<direct>"
_NAME = re.compile(r"^[a-z][a-z0-9_]*$")


class PluginError(LookupError):
    """A plugin cannot be found or loaded; the message names the distribution and the cause."""


@dataclass
class PluginInfo:
    """What the registry knows about one plugin, without importing it.

    Attributes
    ----------
    group : str
        One of :data:`GROUP_NAMES`.
    name : str
        Registered name (the entry-point name).
    value : str
        Entry-point target ``"module:Class"``.
    dist, version : str
        Distribution name and version providing the plugin (``"<direct>"`` for a class
        registered directly).
    cls : type or None
        The class once loaded.
    error : str or None
        Why the plugin cannot be used (set when loading failed).
    loaded : bool
        Whether the class was imported and checked.
    """

    group: str
    name: str
    value: str
    dist: str
    version: str
    cls: type | None = None
    error: str | None = None
    loaded: bool = False

    @property
    def status(self) -> str:
        """``"ok"`` (loaded), ``"not loaded"``, or ``"broken: <cause>"``."""
        if self.error:
            return f"broken: {self.error}"
        return "ok" if self.loaded else "not loaded"

    @property
    def direct(self) -> bool:
        """Whether the class was registered directly (no entry point, no distribution)."""
        return self.dist == DIRECT

    @property
    def qualified(self) -> str:
        """``dist:name``, the spelling that selects this plugin unambiguously."""
        return f"{self.dist}:{self.name}"

    @property
    def module(self) -> str:
        """The module the entry point names (imported only when the plugin is loaded)."""
        return self.value.partition(":")[0].strip()

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready summary (used by ``xpersson plugins list --json``)."""
        return {
            "group": self.group,
            "name": self.name,
            "distribution": self.dist,
            "version": self.version,
            "value": self.value,
            "status": self.status,
        }


def discover(
    autoload: bool, extra: dict[str, dict[str, type]]
) -> dict[str, dict[str, list[PluginInfo]]]:
    """One discovery pass: ``{group: {name: [PluginInfo, ...]}}`` (imports no plugin).

    Reads the entry points of one scan of the installed distributions (only the core's
    ``xpersson`` distribution unless ``autoload``), warns about malformed names and about a name
    registered by two distributions, and adds the classes of ``extra`` (``{group: {name:
    class}}``, registered directly; they shadow entry points of the same name).
    """
    found: dict[str, dict[str, list[PluginInfo]]] = {g: {} for g in GROUP_NAMES}
    installed = _scan()  # one scan of the installed distributions for all groups of this pass
    for group in GROUP_NAMES:
        for ep in _entry_points(ENTRY_POINT_PREFIX + group, installed):
            dist, version = _dist_of(ep)
            if not autoload and norm(dist) != CORE_DIST:
                continue
            if not _NAME.match(ep.name):
                warnings.warn(
                    f"ignoring {group} plugin {ep.name!r} of distribution {dist!r}: plugin "
                    f"names must match {_NAME.pattern}",
                    stacklevel=4,
                )
                continue
            bucket = found[group].setdefault(ep.name, [])
            if not any(norm(i.dist) == norm(dist) and i.value == ep.value for i in bucket):
                bucket.append(PluginInfo(group, ep.name, ep.value, dist, version))
        for name, bucket in found[group].items():
            if len(bucket) > 1 and name not in extra.get(group, {}):
                warnings.warn(duplicate_message(group, name, bucket), stacklevel=4)
        for name, cls in extra.get(group, {}).items():
            err = check_loaded(group, cls)
            found[group][name] = [
                PluginInfo(
                    group,
                    name,
                    qualname(cls),
                    DIRECT,
                    version_of(cls),
                    cls=None if err else cls,
                    error=err,
                    loaded=err is None,
                )
            ]
    return found


def normalize_group(group: str) -> str:
    """``"boundaries"``, ``"boundary"`` or ``"xpersson.boundaries"`` -> ``"boundaries"``."""
    g = group.removeprefix(ENTRY_POINT_PREFIX) if isinstance(group, str) else group
    g = PLUGIN_GROUPS.get(g, g)
    if g not in GROUP_NAMES:
        raise ValueError(f"plugin group must be one of {GROUP_NAMES}, got {group!r}")
    return g


def check_name(name: str) -> None:
    if not isinstance(name, str) or not _NAME.match(name):
        raise ValueError(f"plugin names must match {_NAME.pattern}, got {name!r}")


def duplicate_message(group: str, name: str, bucket: list[PluginInfo]) -> str:
    cands = " and ".join(f"{i.dist!r} ({i.value})" for i in bucket)
    quals = " or ".join(f"'{i.qualified}'" for i in bucket)
    return (
        f"two {group} plugins are named {name!r}, from distributions {cands}; select one as {quals}"
    )


def _entry_points(group: str, installed: EntryPoints | None = None) -> list[EntryPoint]:
    """The entry points of ``group`` in a scan (default: a new one)."""
    return list((_scan() if installed is None else installed).select(group=group))


def norm(dist: str) -> str:
    """A distribution name normalised for comparison (PEP 503)."""
    return re.sub(r"[-_.]+", "-", dist).lower()


def version_of(cls: type) -> str:
    return str(getattr(cls, "__version__", "") or "")


def import_target(value: str) -> Any:
    """Import the object an entry point names (``"module:attr.attr"``), within
    :data:`~._limits.IMPORT_TIME_LIMIT` (or the smaller limit in force): an import that never
    returns raises :class:`~._limits.PluginTimeout`."""
    module, _, attr = value.partition(":")
    limit = current_limit()
    with limited(IMPORT_TIME_LIMIT if limit is None else min(limit, IMPORT_TIME_LIMIT)):
        obj: Any = importlib.import_module(module.strip())
    for part in attr.strip().split(".") if attr else ():
        obj = getattr(obj, part)
    return obj


def qualname(cls: Any) -> str:
    return f"{getattr(cls, '__module__', '?')}:{getattr(cls, '__qualname__', repr(cls))}"


def check_loaded(group: str, cls: Any) -> str | None:
    """Why ``cls`` cannot be used as a plugin of ``group`` (``None``: it can)."""
    from ._base import API_VERSION, GROUPS

    base = GROUPS[group]
    if not isinstance(cls, type) or not issubclass(cls, base):
        return f"{qualname(cls) if isinstance(cls, type) else repr(cls)} is not a {base.__name__}"
    if getattr(cls, "abstract", True):
        return f"{qualname(cls)} is abstract"
    if cls.api_version > API_VERSION:
        return (
            f"needs plugin API v{cls.api_version}, this xpersson provides v{API_VERSION}; "
            "upgrade xpersson"
        )
    return None
