"""Checks of everything a plugin hands to the pipeline, and attribution of plugin exceptions.

Every plugin contribution is checked before it enters a Dataset: declared name, dims and
sizes, finite values (NaN only where the :class:`~xpersson.plugins.VarSpec` documents its
meaning with ``nan_meaning``; ``inf`` never) and the declared ``valid_min`` / ``valid_max``.
Coefficient arrays, walls and spectra are checked the same way. A violation, or an exception
raised inside a plugin, becomes a :class:`PluginFailure` naming the plugin, its distribution,
the call or variable and the offending values.

Modules: ``_failure`` (:class:`PluginFailure`, :func:`calling`), ``_labels``
(:func:`plugin_label`), ``_arrays`` (arrays, spectra, walls), ``_dataset`` (Dataset
contributions, the engine's core outputs).
"""

from __future__ import annotations

from ._arrays import check_array, check_spectrum, check_walls
from ._dataset import (
    CORE_DIMS,
    CORE_RANGES,
    check_contributions,
    check_core,
    checked_variable,
    guard_dataset,
)
from ._failure import PluginFailure, calling
from ._labels import plugin_label

__all__ = [
    "CORE_DIMS",
    "CORE_RANGES",
    "PluginFailure",
    "calling",
    "check_array",
    "check_contributions",
    "check_core",
    "check_spectrum",
    "check_walls",
    "checked_variable",
    "guard_dataset",
    "plugin_label",
]
