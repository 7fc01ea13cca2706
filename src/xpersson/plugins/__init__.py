"""Plugin contracts (base classes, specs), the scene context, the registry and the planner.

Importing this package does not import numpy: :class:`SceneContext`,
:class:`DiffusionClock` and :data:`CLOSURE_PARAMETERS` are loaded on first access. The public
module :mod:`xpersson.plugins.solved` (the solved area curve that analyses of several plugins
read) is imported on its own.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from ..specs import REQUIRED, ParamSpec, SpecError, VarSpec
from ._analyses import PlanError, plan_analyses
from ._base import (
    API_VERSION,
    BOUNDARY_TRAITS,
    COEFFICIENT_TRAITS,
    GEOMETRY_SYMMETRIES,
    GROUPS,
    Analysis,
    Boundary,
    Coefficient,
    Geometry,
    Plugin,
    Spectrum,
    check_plugin_class,
)
from ._bodyquantity import COMBINES, BodyQuantity
from ._fastpaths import NO_FAST_PATHS, FastPaths, fast_paths_on, plain_paths
from ._groups import ENTRY_POINT_PREFIX, GROUP_NAMES, PLUGIN_GROUPS
from ._limits import PluginTimeout, current_limit, limited, time_limit
from ._registry import (
    PluginError,
    PluginInfo,
    Registry,
    get_registry,
    normalize_group,
    plugin_provenance,
    set_registry,
    using_registry,
)

if TYPE_CHECKING:  # pragma: no cover
    from ._closures import CLOSURE_PARAMETERS
    from ._context import DiffusionClock, SceneContext

__all__ = [
    "API_VERSION",
    "BOUNDARY_TRAITS",
    "CLOSURE_PARAMETERS",
    "COEFFICIENT_TRAITS",
    "COMBINES",
    "ENTRY_POINT_PREFIX",
    "NO_FAST_PATHS",
    "GEOMETRY_SYMMETRIES",
    "GROUPS",
    "GROUP_NAMES",
    "PLUGIN_GROUPS",
    "REQUIRED",
    "Analysis",
    "BodyQuantity",
    "Boundary",
    "Coefficient",
    "DiffusionClock",
    "FastPaths",
    "Geometry",
    "ParamSpec",
    "PlanError",
    "Plugin",
    "PluginError",
    "PluginInfo",
    "PluginTimeout",
    "Registry",
    "SceneContext",
    "SpecError",
    "Spectrum",
    "VarSpec",
    "check_plugin_class",
    "current_limit",
    "fast_paths_on",
    "get_registry",
    "limited",
    "normalize_group",
    "plain_paths",
    "plan_analyses",
    "plugin_provenance",
    "set_registry",
    "time_limit",
    "using_registry",
]

_LAZY = {
    "SceneContext": "_context",
    "DiffusionClock": "_context",
    "CLOSURE_PARAMETERS": "_closures",
}


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        from importlib import import_module

        return getattr(import_module(f"{__name__}.{_LAZY[name]}"), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))
