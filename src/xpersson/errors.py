"""Exception and warning classes raised by several layers of xpersson."""

from __future__ import annotations

from .scene import SceneError

__all__ = ["XperssonWarning", "MemoryBudgetError"]


class XperssonWarning(UserWarning):
    """A result is returned but a request could not be met (see the Dataset's ``status``)."""


class MemoryBudgetError(SceneError):
    """A request larger than the memory budget (raised before any work)."""
