"""Distribution metadata for plugin discovery (private).

``importlib.metadata.entry_points(group=...)`` reads the entry points of every installed
distribution at each call; a discovery pass asks for every plugin group, so the pass makes
one :func:`scan` and selects each group from it. Nothing here is kept between calls: what a
pass found is the registry's discovery state (:meth:`xpersson.plugins.Registry.refresh`).
"""

from __future__ import annotations

from importlib.metadata import EntryPoint, EntryPoints, entry_points

__all__ = ["dist_of", "scan"]

_UNKNOWN = ("<unknown>", "")


def scan() -> EntryPoints:
    """Every entry point of every installed distribution (read now)."""
    return entry_points()


def dist_of(ep: EntryPoint) -> tuple[str, str]:
    """Name and version of the distribution that declares ``ep`` (``"<unknown>"`` when its
    metadata are missing or unreadable)."""
    dist = getattr(ep, "dist", None)
    if dist is None:
        return _UNKNOWN
    try:
        name = dist.metadata["Name"] or getattr(dist, "name", None) or "<unknown>"
        return str(name), str(dist.version or "")
    except Exception:  # unreadable metadata must not break listing
        return _UNKNOWN
