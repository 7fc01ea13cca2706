"""Exception classes that several layers raise (the bottom layer: imports nothing of xpersson).

Re-exported where they are public: :class:`SceneError` by :mod:`xpersson.scene` (and the top
package), :class:`UnitError` by :mod:`xpersson.units`.
"""

from __future__ import annotations

__all__ = ["SceneError", "UnitError"]


class SceneError(ValueError):
    """A scene is malformed; the message names the offending parameter."""


class UnitError(ValueError):
    """A quantity has the wrong dimensionality or cannot be parsed."""
