"""The one group mapping: a plugin group's short name -> its group.

The short name is the scene's section (``[spectrum]``, ``[coefficient]``, ``[boundary]``,
``[geometry]``) or the singular of the group; the group names the entry-point group
``xpersson.<group>``.
"""

from __future__ import annotations

__all__ = ["ENTRY_POINT_PREFIX", "GEOMETRY_SYMMETRIES", "GROUP_NAMES", "PLUGIN_GROUPS"]

ENTRY_POINT_PREFIX = "xpersson."
"""Prefix of the entry-point groups (``xpersson.spectra``, ...)."""

PLUGIN_GROUPS: dict[str, str] = {
    "spectrum": "spectra",
    "coefficient": "coefficients",
    "boundary": "boundaries",
    "analysis": "analyses",
    "geometry": "geometries",
}
"""Short name (singular; the scene's section) -> group (entry-point group ``xpersson.<group>``)."""

GROUP_NAMES: tuple[str, ...] = tuple(PLUGIN_GROUPS.values())
"""The five groups, in pipeline order (derived from :data:`PLUGIN_GROUPS`)."""

GEOMETRY_SYMMETRIES: tuple[str, ...] = ("axisymmetric", "plane")
"""A geometry's symmetry: ``axisymmetric`` (p(r), force [N]) or ``plane`` (p(x), a line contact:
force per length)."""
