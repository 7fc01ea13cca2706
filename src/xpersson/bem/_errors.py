"""The cross-check's refusal: one line, before any work."""

from __future__ import annotations

from ..errors import SceneError

__all__ = ["CrosscheckError", "refuse"]


class CrosscheckError(SceneError):
    """A scene the cross-check cannot do (the physics, the spectrum or the grid), one line."""


def refuse(what: str) -> CrosscheckError:
    """The refusal ``crosscheck: WHAT`` (raise it)."""
    return CrosscheckError(f"crosscheck: {what}")
