"""Plugin labels for messages: group word, registered name, distribution and version."""

from __future__ import annotations

from typing import Any

from ..plugins import PLUGIN_GROUPS, get_registry, normalize_group

__all__ = ["plugin_label"]

_GROUP_WORD = {group: word for word, group in PLUGIN_GROUPS.items()}


class _Label:
    """A plugin's label, looked up (registry, distribution metadata) only when printed."""

    def __init__(self, group: str, plugin: Any, registry: Any, name: str | None) -> None:
        self._args = (group, plugin, registry, name)
        self._text: str | None = None

    def __str__(self) -> str:
        if self._text is None:
            self._text = _label_text(*self._args)
        return self._text

    def __format__(self, spec: str) -> str:
        return format(str(self), spec)

    def __repr__(self) -> str:
        return repr(str(self))


def plugin_label(group: str, plugin: Any, registry: Any = None, name: str | None = None) -> Any:
    """``"boundary plugin 'plastic' (distribution xpersson-plasticity 0.1.0)"``, lazily.

    Parameters
    ----------
    group : str
        Plugin group (``"boundaries"``, ...; singular forms accepted).
    plugin : object
        The plugin instance or class.
    registry : Registry, optional
        Where to look up the registered name and distribution.
    name : str, optional
        The name the scene used (preferred over the registry's).

    Returns
    -------
    object
        Formats as the label text; the (slow) distribution lookup runs only when an error
        message is built.
    """
    return _Label(group, plugin, registry, name)


def _label_text(group: str, plugin: Any, registry: Any, name: str | None) -> str:
    cls = plugin if isinstance(plugin, type) else type(plugin)
    try:
        group = normalize_group(group)
        reg = registry if registry is not None else get_registry()
        reg_name, info = reg.name_of(group, cls)
        if info is not None and not info.direct:
            dist = f"{info.dist} {info.version}".strip()
        else:
            dist = _distribution_of(cls.__module__, reg)
    except Exception:  # a label must never fail
        dist, reg_name = "unknown", f"{cls.__module__}:{cls.__qualname__}"
    word = _GROUP_WORD.get(group, group)
    return f"{word} plugin {name or reg_name!r} (distribution {dist})"


def _distribution_of(module: str, registry: Any) -> str:
    """Distribution and version of a class passed directly (not registered by entry point)."""
    dist, version = registry.module_distribution(module)
    if not dist.startswith("<"):  # "<direct>": no installed distribution provides it
        return f"{dist} {version}"
    return f"none: class {module} passed directly"
