"""Plugin discovery from entry-point metadata, in the manner of xarray's backends.

Listing reads only distribution metadata and imports no plugin module. A plugin is imported
when a scene selects it; a broken one (import error, missing optional dependency, API too new,
malformed metadata) fails only then, with a message naming its distribution and the cause, and
never breaks the listing or the other plugins.

Two distributions registering one name in one group are reported by a warning naming both when
the group is discovered; such a name must then be qualified as ``dist:name``.
"""

from __future__ import annotations

import contextlib
import importlib
import os
import re
import warnings
from collections.abc import Iterator
from dataclasses import dataclass, field
from importlib.metadata import EntryPoint, EntryPoints
from typing import Any

from ._groups import ENTRY_POINT_PREFIX, GROUP_NAMES, PLUGIN_GROUPS
from ._limits import PluginTimeout, limited
from ._metadata import dist_of as _dist_of
from ._metadata import scan as _scan

__all__ = [
    "AUTOLOAD_ENV",
    "CORE_DIST",
    "ENTRY_POINT_PREFIX",
    "GROUP_NAMES",
    "PluginError",
    "PluginInfo",
    "Registry",
    "get_registry",
    "normalize_group",
    "plugin_provenance",
    "set_registry",
    "using_registry",
]

AUTOLOAD_ENV = "XPERSSON_DISABLE_PLUGIN_AUTOLOAD"
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


@dataclass
class Registry:
    """Plugin registry for the four groups.

    Parameters
    ----------
    autoload : bool, optional
        Discover third-party entry points. Default: true unless the environment variable
        ``XPERSSON_DISABLE_PLUGIN_AUTOLOAD`` is set to a non-empty value other than ``0``;
        the built-in plugins of the ``xpersson`` distribution are always discovered.
    extra : dict, optional
        ``{group: {name: class}}`` registered directly (tests, notebooks); a direct class
        shadows entry points of the same name.

    Examples
    --------
    >>> reg = Registry(extra={"boundaries": {"mywall": MyWall}})  # doctest: +SKIP
    >>> reg.load("boundaries", "mywall") is MyWall                # doctest: +SKIP
    True
    """

    autoload: bool | None = None
    extra: dict[str, dict[str, type]] = field(default_factory=dict)
    # Discovery state, not a cache of a computation: what is installed (entry points, the
    # top-level packages of each distribution) as found by the last discovery pass, and the
    # provenance records of that pass. It changes when the environment does, so it stays when
    # xpersson's caches are off; refresh() starts a new pass.
    _cache: dict[str, dict[str, list[PluginInfo]]] | None = field(default=None, repr=False)
    _packages: dict[str, list[str]] | None = field(default=None, repr=False, compare=False)
    _records: dict[tuple[str, type], tuple[Any, dict[str, Any]]] = field(
        default_factory=dict, repr=False, compare=False
    )

    def __post_init__(self) -> None:
        if self.autoload is None:
            self.autoload = os.environ.get(AUTOLOAD_ENV, "") in ("", "0")
        self.extra = {normalize_group(g): dict(v) for g, v in self.extra.items()}
        for plugins in self.extra.values():
            for name in plugins:
                _check_name(name)

    # -- discovery ---------------------------------------------------------------------------
    def refresh(self) -> None:
        """Forget the discovery state (after installing a plugin at run time)."""
        self._cache = None
        self._packages = None
        self._records.clear()

    def module_distribution(self, module: str) -> tuple[str, str]:
        """Distribution and version of a module (for classes passed directly; ``(DIRECT,
        "")`` when no installed distribution provides it), from the installed distributions'
        top-level packages as found once per discovery (the scan takes ~0.2 s)."""
        from importlib.metadata import packages_distributions, version

        try:
            if self._packages is None:
                self._packages = dict(packages_distributions())
            dists = self._packages.get(module.partition(".")[0], [])
            if dists:
                return dists[0], version(dists[0])
        except Exception:
            pass
        return DIRECT, ""

    def _discover(self) -> dict[str, dict[str, list[PluginInfo]]]:
        if self._cache is not None:
            return self._cache
        found: dict[str, dict[str, list[PluginInfo]]] = {g: {} for g in GROUP_NAMES}
        installed = _scan()  # one scan of the installed distributions for all groups of this pass
        for group in GROUP_NAMES:
            for ep in _entry_points(ENTRY_POINT_PREFIX + group, installed):
                dist, version = _dist_of(ep)
                if not self.autoload and _norm(dist) != CORE_DIST:
                    continue
                if not _NAME.match(ep.name):
                    warnings.warn(
                        f"ignoring {group} plugin {ep.name!r} of distribution {dist!r}: plugin "
                        f"names must match {_NAME.pattern}",
                        stacklevel=3,
                    )
                    continue
                bucket = found[group].setdefault(ep.name, [])
                if not any(_norm(i.dist) == _norm(dist) and i.value == ep.value for i in bucket):
                    bucket.append(PluginInfo(group, ep.name, ep.value, dist, version))
            for name, bucket in found[group].items():
                if len(bucket) > 1 and name not in self.extra.get(group, {}):
                    warnings.warn(_duplicate_message(group, name, bucket), stacklevel=3)
            for name, cls in self.extra.get(group, {}).items():
                err = _check_loaded(group, cls)
                found[group][name] = [
                    PluginInfo(
                        group,
                        name,
                        _qualname(cls),
                        DIRECT,
                        _version_of(cls),
                        cls=None if err else cls,
                        error=err,
                        loaded=err is None,
                    )
                ]
        self._cache = found
        return found

    def entries(self, group: str) -> dict[str, list[PluginInfo]]:
        """All discovered plugins of ``group`` by name (imports nothing)."""
        return self._discover()[normalize_group(group)]

    def names(self, group: str) -> list[str]:
        """Sorted plugin names of ``group`` (imports nothing)."""
        return sorted(self.entries(group))

    def infos(self, group: str | None = None) -> Iterator[PluginInfo]:
        """Iterate over every discovered plugin, optionally of one group (imports nothing)."""
        for g in (normalize_group(group),) if group else GROUP_NAMES:
            for name in sorted(self.entries(g)):
                yield from self.entries(g)[name]

    def register(self, group: str, name: str, cls: type) -> None:
        """Register a class directly under ``name`` (shadows an entry point of that name)."""
        group = normalize_group(group)
        _check_name(name)
        self.extra.setdefault(group, {})[name] = cls
        self.refresh()

    # -- loading -----------------------------------------------------------------------------
    def info(self, group: str, name: str) -> PluginInfo:
        """The :class:`PluginInfo` for ``name`` or ``dist:name`` (imports nothing).

        Raises
        ------
        PluginError
            Unknown name, unknown distribution, or a name registered by two distributions
            (the message names both and asks for ``dist:name``).
        """
        group = normalize_group(group)
        entries = self.entries(group)
        dist = None
        if ":" in name:
            dist, name = name.split(":", 1)
        bucket = entries.get(name)
        if not bucket:
            avail = ", ".join(sorted(entries)) or "none"
            raise PluginError(
                f"no {group} plugin named {name!r} (installed: {avail}); "
                f"see `xpersson plugins list --group {group}`"
            )
        if dist is not None:
            match = [i for i in bucket if _norm(i.dist) == _norm(dist)]
            if not match:
                raise PluginError(
                    f"no {group} plugin {name!r} in distribution {dist!r} "
                    f"(found in: {', '.join(i.dist for i in bucket)})"
                )
            return match[0]
        if len(bucket) > 1:
            raise PluginError("ambiguous name: " + _duplicate_message(group, name, bucket))
        return bucket[0]

    def load(self, group: str, name: str) -> type:
        """Import and return the plugin class (checked against the API version).

        Raises
        ------
        PluginError
            The plugin is unknown or broken; the message names the distribution, its version
            and the cause (failed import, missing optional dependency, API too new, malformed
            metadata).
        """
        group = normalize_group(group)
        info = self.info(group, name)
        if info.cls is None and info.error is None:
            try:
                cls = _import(info.value)
            except ModuleNotFoundError as exc:
                missing = exc.name or str(exc)
                if missing == info.module or info.module.startswith(missing + "."):
                    info.error = f"import failed (module {info.module!r} not found)"
                else:
                    info.error = f"import failed (missing optional dependency {missing!r})"
            except Exception as exc:  # a broken plugin must not break the caller's listing
                info.error = f"import failed ({type(exc).__name__}: {exc})"
            else:
                info.error = _check_loaded(group, cls)
                if info.error is None:
                    info.cls = cls
                    info.loaded = True
        if info.error is not None:
            version = f" {info.version}" if info.version else ""
            raise PluginError(
                f"{group} plugin {info.name!r} ({info.value}) from distribution "
                f"{info.dist!r}{version} cannot be used: {info.error}"
            )
        assert info.cls is not None
        return info.cls

    def resolve(self, group: str, name_or_class: str | type) -> type:
        """A registered name, ``dist:name``, or a plugin class passed directly."""
        group = normalize_group(group)
        if isinstance(name_or_class, str):
            return self.load(group, name_or_class)
        if isinstance(name_or_class, type):
            err = _check_loaded(group, name_or_class)
            if err:
                raise PluginError(f"{_qualname(name_or_class)} cannot be used: {err}")
            return name_or_class
        raise TypeError(
            f"{group} plugin must be a name or a plugin class, got {type(name_or_class).__name__}"
        )

    def check(self, group: str | None = None, time_limit: float | None = None) -> list[PluginInfo]:
        """Import every discovered plugin (optionally of one group) and return all infos.

        Broken plugins are not raised; their :attr:`PluginInfo.status` says why. An import
        running longer than ``time_limit`` [s] is interrupted and reported broken (:mod:`._limits`).
        """
        out = []
        for info in list(self.infos(group)):
            with contextlib.suppress(PluginError, PluginTimeout), limited(time_limit):
                self.load(info.group, info.qualified if info.dist != DIRECT else info.name)
            out.append(info)
        return out

    def provenance(self, group: str, cls: type) -> dict[str, Any]:
        """:func:`plugin_provenance` of ``cls`` in this registry, computed once per discovery.

        Returns the cached record itself (shared by every scene that uses the class): callers
        must not modify it. :meth:`refresh` (a new discovery) makes it be computed again.
        """
        group = normalize_group(group)
        found = self._discover()
        hit = self._records.get((group, cls))
        if hit is None or hit[0] is not found:
            if len(self._records) > 256:
                self._records.clear()
            hit = (found, plugin_provenance(group, cls, self))
            self._records[(group, cls)] = hit
        return hit[1]

    def name_of(self, group: str, cls: type) -> tuple[str, PluginInfo | None]:
        """Registered name and info of a loaded class (``(module:qualname, None)`` if none)."""
        group = normalize_group(group)
        for name, bucket in self.entries(group).items():
            for info in bucket:
                if info.cls is cls or (info.cls is None and info.value == _qualname(cls)):
                    return name, info
        return _qualname(cls), None


def plugin_provenance(group: str, cls: type, registry: Registry | None = None) -> dict[str, Any]:
    """What an archive records about one plugin it used.

    Parameters
    ----------
    group : str
        Plugin group (``"boundaries"``, ...).
    cls : type
        The plugin class actually used.
    registry : Registry, optional
        Where to look up the registered name and distribution (default registry if omitted).

    Returns
    -------
    dict
        ``group``, ``name`` (registered name, or ``module:qualname`` for a class passed
        directly), ``distribution``, ``version``, ``class`` (``module:qualname``),
        ``api_version``, ``summary`` and ``references`` (list of DOIs); JSON-serialisable.
    """
    group = normalize_group(group)
    reg = registry if registry is not None else get_registry()
    try:
        name, info = reg.name_of(group, cls)
    except Exception:  # provenance must never fail a finished run
        name, info = _qualname(cls), None
    if info is not None and not info.direct:
        dist, version = info.dist, info.version
    else:
        dist, version = reg.module_distribution(cls.__module__)
    return {
        "group": group,
        "name": name,
        "distribution": dist,
        "version": version,
        "class": _qualname(cls),
        "api_version": int(getattr(cls, "api_version", 0)),
        "summary": str(getattr(cls, "summary", "")),
        "references": list(getattr(cls, "references", ())),
    }


def normalize_group(group: str) -> str:
    """``"boundaries"``, ``"boundary"`` or ``"xpersson.boundaries"`` -> ``"boundaries"``."""
    g = group.removeprefix(ENTRY_POINT_PREFIX) if isinstance(group, str) else group
    g = PLUGIN_GROUPS.get(g, g)
    if g not in GROUP_NAMES:
        raise ValueError(f"plugin group must be one of {GROUP_NAMES}, got {group!r}")
    return g


def _check_name(name: str) -> None:
    if not isinstance(name, str) or not _NAME.match(name):
        raise ValueError(f"plugin names must match {_NAME.pattern}, got {name!r}")


def _duplicate_message(group: str, name: str, bucket: list[PluginInfo]) -> str:
    cands = " and ".join(f"{i.dist!r} ({i.value})" for i in bucket)
    quals = " or ".join(f"'{i.qualified}'" for i in bucket)
    return (
        f"two {group} plugins are named {name!r}, from distributions {cands}; select one as {quals}"
    )


def _entry_points(group: str, installed: EntryPoints | None = None) -> list[EntryPoint]:
    """The entry points of ``group`` in a scan (default: a new one)."""
    return list((_scan() if installed is None else installed).select(group=group))


def _norm(dist: str) -> str:
    return re.sub(r"[-_.]+", "-", dist).lower()


def _version_of(cls: type) -> str:
    return str(getattr(cls, "__version__", "") or "")


def _import(value: str) -> Any:
    module, _, attr = value.partition(":")
    obj: Any = importlib.import_module(module.strip())
    for part in attr.strip().split(".") if attr else ():
        obj = getattr(obj, part)
    return obj


def _qualname(cls: Any) -> str:
    return f"{getattr(cls, '__module__', '?')}:{getattr(cls, '__qualname__', repr(cls))}"


def _check_loaded(group: str, cls: Any) -> str | None:
    from ._base import API_VERSION, GROUPS

    base = GROUPS[group]
    if not isinstance(cls, type) or not issubclass(cls, base):
        return f"{_qualname(cls) if isinstance(cls, type) else repr(cls)} is not a {base.__name__}"
    if getattr(cls, "abstract", True):
        return f"{_qualname(cls)} is abstract"
    if cls.api_version > API_VERSION:
        return (
            f"needs plugin API v{cls.api_version}, this xpersson provides v{API_VERSION}; "
            "upgrade xpersson"
        )
    return None


_DEFAULT: Registry | None = None


def get_registry() -> Registry:
    """The process-wide default registry (created on first use)."""
    global _DEFAULT
    if _DEFAULT is None:
        _DEFAULT = Registry()
    return _DEFAULT


def set_registry(reg: Registry | None) -> Registry | None:
    """Replace the default registry; returns the previous one (``None`` resets)."""
    global _DEFAULT
    old, _DEFAULT = _DEFAULT, reg
    return old


@contextlib.contextmanager
def using_registry(reg: Registry) -> Iterator[Registry]:
    """Temporarily make ``reg`` the default registry."""
    old = set_registry(reg)
    try:
        yield reg
    finally:
        set_registry(old)
