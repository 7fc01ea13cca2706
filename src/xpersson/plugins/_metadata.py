"""Distribution metadata for plugin discovery: one scan per discovery pass (private).

``importlib.metadata.entry_points(group=...)`` reads the entry points of every installed
distribution at each call; a discovery pass asks for every plugin group, so the scan is made
once per pass (:func:`scan`, emptied by :func:`forget` when a pass starts) and each
distribution's name and version are parsed once per pass (:func:`dist_of`).
"""

from __future__ import annotations

import functools
from importlib.metadata import EntryPoint, EntryPoints, entry_points
from typing import Any

__all__ = ["dist_of", "forget", "scan"]

_UNKNOWN = ("<unknown>", "")
_names: dict[int, tuple[Any, tuple[str, str]]] = {}


@functools.lru_cache(maxsize=1)
def scan() -> EntryPoints:
    """Every entry point of every installed distribution (cached until :func:`forget`)."""
    return entry_points()


def forget() -> None:
    """Drop the cached scan and distribution names (a discovery pass starts afresh)."""
    scan.cache_clear()
    _names.clear()


def dist_of(ep: EntryPoint) -> tuple[str, str]:
    """Name and version of the distribution that declares ``ep`` (``"<unknown>"`` when its
    metadata are missing or unreadable)."""
    dist = getattr(ep, "dist", None)
    if dist is None:
        return _UNKNOWN
    known = _names.get(id(dist))
    if known is not None and known[0] is dist:
        return known[1]
    try:
        name = dist.metadata["Name"] or getattr(dist, "name", None) or "<unknown>"
        found = (str(name), str(dist.version or ""))
    except Exception:  # unreadable metadata must not break listing
        found = _UNKNOWN
    _names[id(dist)] = (dist, found)
    return found
