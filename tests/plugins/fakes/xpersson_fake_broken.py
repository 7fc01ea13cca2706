"""A plugin module whose optional dependency is missing."""

import xpersson_nonexistent_optional_dependency  # noqa: F401

from xpersson.plugins import Boundary


class BrokenWall(Boundary):
    summary = "never importable"
