"""The plugin registry: discovery from entry-point metadata, in the manner of xarray's backends.

Listing reads only distribution metadata and imports no plugin module. A plugin is imported
when a scene selects it; a broken one (import error, missing optional dependency, API too new,
malformed metadata) fails only then, with a message naming its distribution and the cause, and
never breaks the listing or the other plugins.

Two distributions registering one name in one group are reported by a warning naming both when
the group is discovered; such a name must then be qualified as ``dist:name``.

The scanning of entry points and the :class:`PluginInfo` records live in :mod:`._discovery`;
this module keeps a registry's discovery state, loads plugins and records their provenance.
"""

from __future__ import annotations

import contextlib
import json
import os
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

from ._discovery import (
    CORE_DIST,
    DIRECT,
    PluginError,
    PluginInfo,
    check_loaded,
    check_name,
    discover,
    duplicate_message,
    import_target,
    norm,
    normalize_group,
    qualname,
)
from ._groups import ENTRY_POINT_PREFIX, GROUP_NAMES
from ._limits import PluginTimeout, limited

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
    _discovered: dict[str, dict[str, list[PluginInfo]]] | None = field(default=None, repr=False)
    _packages: dict[str, list[str]] | None = field(default=None, repr=False, compare=False)
    _records: dict[tuple[str, type], tuple[Any, dict[str, Any], dict[str | None, str]]] = field(
        default_factory=dict, repr=False, compare=False
    )

    def __post_init__(self) -> None:
        if self.autoload is None:
            self.autoload = os.environ.get(AUTOLOAD_ENV, "") in ("", "0")
        self.extra = {normalize_group(g): dict(v) for g, v in self.extra.items()}
        for plugins in self.extra.values():
            for name in plugins:
                check_name(name)

    # -- discovery ---------------------------------------------------------------------------
    def refresh(self) -> None:
        """Forget the discovery state (after installing a plugin at run time)."""
        self._discovered = None
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
        if self._discovered is None:
            self._discovered = discover(bool(self.autoload), self.extra)
        return self._discovered

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
        check_name(name)
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
            match = [i for i in bucket if norm(i.dist) == norm(dist)]
            if not match:
                raise PluginError(
                    f"no {group} plugin {name!r} in distribution {dist!r} "
                    f"(found in: {', '.join(i.dist for i in bucket)})"
                )
            return match[0]
        if len(bucket) > 1:
            raise PluginError("ambiguous name: " + duplicate_message(group, name, bucket))
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
                cls = import_target(info.value)
            except ModuleNotFoundError as exc:
                missing = exc.name or str(exc)
                if missing == info.module or info.module.startswith(missing + "."):
                    info.error = f"import failed (module {info.module!r} not found)"
                else:
                    info.error = f"import failed (missing optional dependency {missing!r})"
            except PluginTimeout as exc:  # the message says which limit (empty from a thread)
                info.error = f"import {exc or 'exceeded its time limit'}"
            except Exception as exc:  # a broken plugin must not break the caller's listing
                info.error = f"import failed ({type(exc).__name__}: {exc})"
            else:
                info.error = check_loaded(group, cls)
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
            bucket = self._discover()[group].get(name_or_class)  # a loaded plugin: as load's
            if bucket and len(bucket) == 1 and bucket[0].cls is not None and not bucket[0].error:
                return bucket[0].cls
            return self.load(group, name_or_class)
        if isinstance(name_or_class, type):
            err = check_loaded(group, name_or_class)
            if err:
                raise PluginError(f"{qualname(name_or_class)} cannot be used: {err}")
            return name_or_class
        raise TypeError(
            f"{group} plugin must be a name or a plugin class, got {type(name_or_class).__name__}"
        )

    def check(self, group: str | None = None, time_limit: float | None = None) -> list[PluginInfo]:
        """Import every discovered plugin (optionally of one group) and return all infos.

        Broken plugins are not raised; their :attr:`PluginInfo.status` says why. An import
        running longer than ``time_limit`` [s] is interrupted and reported as broken, its status
        saying so (``"broken: import exceeded the time limit of ... s"``; see :mod:`._limits` for
        what can be interrupted).
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
        return self._provenance(normalize_group(group), cls)[1]

    def provenance_json(self, group: str, cls: type, name: str | None = None) -> str:
        """``json.dumps`` (sorted keys) of :meth:`provenance`, with ``"name": name`` added when
        ``name`` is given (as an archive records it), made once per discovery and name."""
        _, record, texts = self._provenance(normalize_group(group), cls)
        text = texts.get(name)
        if text is None:
            text = json.dumps({**record, "name": name} if name else record, sort_keys=True)
            texts[name] = text
        return text

    def _provenance(
        self, group: str, cls: type
    ) -> tuple[Any, dict[str, Any], dict[str | None, str]]:
        """(discovery, record, JSON texts by name) of a plugin class (``group`` normalised)."""
        found = self._discover()
        hit = self._records.get((group, cls))
        if hit is None or hit[0] is not found:
            if len(self._records) > 256:
                self._records.clear()
            hit = (found, plugin_provenance(group, cls, self), {})
            self._records[(group, cls)] = hit
        return hit

    def name_of(self, group: str, cls: type) -> tuple[str, PluginInfo | None]:
        """Registered name and info of a loaded class (``(module:qualname, None)`` if none)."""
        group = normalize_group(group)
        for name, bucket in self.entries(group).items():
            for info in bucket:
                if info.cls is cls or (info.cls is None and info.value == qualname(cls)):
                    return name, info
        return qualname(cls), None


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
        name, info = qualname(cls), None
    if info is not None and not info.direct:
        dist, version = info.dist, info.version
    else:
        dist, version = reg.module_distribution(cls.__module__)
    return {
        "group": group,
        "name": name,
        "distribution": dist,
        "version": version,
        "class": qualname(cls),
        "api_version": int(getattr(cls, "api_version", 0)),
        "summary": str(getattr(cls, "summary", "")),
        "references": list(getattr(cls, "references", ())),
    }


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
