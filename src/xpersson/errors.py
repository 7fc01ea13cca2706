"""Exception and warning classes that several layers raise (the bottom layer: imports nothing of
xpersson).

Re-exported where they are public: :class:`SceneError` by :mod:`xpersson.scene` (and the top
package), :class:`UnitError` by :mod:`xpersson.units`, :class:`XperssonWarning` by the top package,
:class:`MemoryBudgetError` by :mod:`xpersson.memory`, :class:`ArchiveError` and
:class:`FolderBusyError` by :mod:`xpersson.io`.
"""

from __future__ import annotations

__all__ = [
    "ArchiveError",
    "FolderBusyError",
    "MemoryBudgetError",
    "SceneError",
    "UnitError",
    "XperssonWarning",
]


class SceneError(ValueError):
    """A scene is malformed; the message names the offending parameter."""


class UnitError(ValueError):
    """A quantity has the wrong dimensionality or cannot be parsed."""


class XperssonWarning(UserWarning):
    """A result is returned but a request could not be met (see the Dataset's ``status``)."""


class MemoryBudgetError(SceneError):
    """A request larger than the memory budget (raised before any work)."""


class ArchiveError(ValueError):
    """An archive or sweep folder is corrupt, truncated, foreign or inconsistent; the message
    names the file (and the variable or part) and what is wrong."""


class FolderBusyError(ArchiveError):
    """Another run holds the lock of a sweep folder."""
