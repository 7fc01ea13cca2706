"""Temporary alias of :mod:`xpersson.checks` (to be deleted at merge).

Kept only so that ``_pipeline.py``, ``_stack.py``, ``_sweeprun.py`` and ``cli.py`` (moved by
another branch) keep working until they import :mod:`xpersson.checks`.
"""

from __future__ import annotations

from .checks import (  # noqa: F401
    CORE_DIMS,
    CORE_RANGES,
    PluginFailure,
    calling,
    check_array,
    check_contributions,
    check_core,
    check_spectrum,
    check_walls,
    checked_variable,
    guard_dataset,
    plugin_label,
)
