"""The one group mapping: a plugin group's short name -> its group.

The short name is the scene's section (``[spectrum]``, ``[coefficient]``, ``[boundary]``) or the
singular of the group; the group names the entry-point group ``xpersson.<group>``.
"""

from __future__ import annotations

__all__ = ["ENTRY_POINT_PREFIX", "GROUP_NAMES", "PLUGIN_GROUPS"]

ENTRY_POINT_PREFIX = "xpersson."
"""Prefix of the entry-point groups (``xpersson.spectra``, ...)."""

PLUGIN_GROUPS: dict[str, str] = {
    "spectrum": "spectra",
    "coefficient": "coefficients",
    "boundary": "boundaries",
    "analysis": "analyses",
}
"""Short name (singular; the scene's section) -> group (entry-point group ``xpersson.<group>``)."""

GROUP_NAMES: tuple[str, ...] = tuple(PLUGIN_GROUPS.values())
"""The four groups, in pipeline order (derived from :data:`PLUGIN_GROUPS`)."""
