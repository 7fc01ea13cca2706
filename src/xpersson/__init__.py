"""xpersson: Persson's multiscale theory of rough-surface contact as a plugin framework.

Public API (imported lazily so that ``import xpersson`` and the CLI's ``--help`` stay cheap)::

    xpersson.solve(scene) -> xarray.Dataset
    xpersson.crosscheck(scene)        # the theory against a BEM (tamaas, extra [bem])
    xpersson.load_scene(path) -> Scene
    xpersson.open_dataset(path) -> xarray.Dataset
    xpersson.to_netcdf(ds, path)
    xpersson.analyse(ds, "gap_pdf", ...)  # an analysis of a solved (reopened) Dataset
    xpersson.plot.area(ds)            # matplotlib, imported only when plotting
    xpersson.sweep                    # the sweep mechanism (lists and ranges of parameters)
    xpersson.set_options(cache=False) # library options (xpersson.options), as xarray's
"""

from __future__ import annotations

from importlib import import_module
from typing import Any

__all__ = [
    "ArchiveError",
    "FolderBusyError",
    "analyse",
    "PluginFailure",
    "Scene",
    "SceneError",
    "XperssonWarning",
    "crosscheck",
    "get_options",
    "load_scene",
    "open_dataset",
    "solve",
    "to_netcdf",
    "plot",
    "set_options",
    "sweep",
    "__version__",
]

_LAZY = {
    "analyse": "xpersson.reanalysis",
    "ArchiveError": "xpersson.errors",
    "FolderBusyError": "xpersson.errors",
    "PluginFailure": "xpersson.checks",
    "crosscheck": "xpersson.bem",
    "solve": "xpersson.api",
    "XperssonWarning": "xpersson.errors",
    "Scene": "xpersson.scene",
    "SceneError": "xpersson.scene",
    "load_scene": "xpersson.scene",
    "get_options": "xpersson.options",
    "set_options": "xpersson.options",
    "open_dataset": "xpersson.io",
    "to_netcdf": "xpersson.io",
}


def __getattr__(name: str) -> Any:
    if name == "__version__":  # import_module: no import edge from the package to provenance
        return import_module("xpersson.provenance").version()
    if name in ("plot", "sweep"):
        return import_module(f"xpersson.{name}")
    if name in _LAZY:  # kept in the module once imported: later reads skip this hook
        value = globals()[name] = getattr(import_module(_LAZY[name]), name)
        return value
    raise AttributeError(f"module 'xpersson' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(__all__)
