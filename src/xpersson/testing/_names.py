"""Names shared by the kit's modules: the injected plugin's scene name and message labels."""

from __future__ import annotations

from typing import Any

#: The name under which the plugin under check is injected into a scene.
CHECK_NAME = "plugin_under_check"

#: Plugin group -> the scene section that selects a plugin of that group.
SECTION = {
    "spectra": "spectrum",
    "coefficients": "coefficient",
    "boundaries": "boundary",
    "analyses": "analyses",
}


def qual(cls: Any) -> str:
    """``module.QualName`` of a class, for messages (never raises)."""
    return f"{getattr(cls, '__module__', '?')}.{getattr(cls, '__qualname__', repr(cls))}"
