"""The plugin-author kit: contract checks, scenes, schema assertions and independent oracles.

Typical use in a plugin's own test-suite::

    from xpersson.testing import check_plugin, registry_with

    def test_contract():
        check_plugin(MyWall)                       # metadata, pickle, determinism, engine

    def test_from_a_scene():
        with registry_with(boundaries={"mywall": MyWall}):
            ds = xpersson.solve({..., "boundary": {"model": "mywall", "s": "1 kPa"}})

One job per module: :mod:`~xpersson.testing.contracts` (:func:`check_plugin`),
:mod:`~xpersson.testing.fastpaths` (:func:`check_fast_paths`: each declared fast path against
the plain path),
:mod:`~xpersson.testing.registry` (:func:`registry_with`), :mod:`~xpersson.testing.scenes`
(:data:`TINY_SCENE`, :func:`tiny_scene`, the factories :func:`scene`, :func:`spectrum`,
:func:`material`), :mod:`~xpersson.testing.schema` (:func:`assert_schema`),
:mod:`~xpersson.testing.oracles` (closed forms), :mod:`~xpersson.testing.referee`
(:func:`markov_cross_check`), :mod:`~xpersson.testing.analysis_referee`
(:func:`check_analysis`, the analysis-side referee) and
:mod:`~xpersson.testing.pytest_plugin` (fixtures, registered through the ``pytest11`` entry
point ``xpersson``).

Importing this package imports neither numpy-heavy libraries nor the core pipeline; they are
imported by the checks that need them.
"""

from __future__ import annotations

from .analysis_referee import check_analysis
from .contracts import HEAVY_MODULES, check_plugin
from .fastpaths import check_fast_paths
from .oracles import (
    constant_wall_area,
    constant_wall_load,
    linear_wall_area,
    linear_wall_load,
    mirrored_gaussian_area,
    oracles,
    two_wall_areas,
)
from .referee import markov_cross_check
from .registry import registry_with
from .scenes import (
    TINY_SCENE,
    material,
    merge_scene,
    pressures,
    sample_params,
    scene,
    spectrum,
    tiny_scene,
)
from .schema import KNOWN_DIMS, assert_schema

try:  # the fixtures, also for ``pytest_plugins = ["xpersson.testing"]`` in a conftest.py
    from .pytest_plugin import xpersson_oracles, xpersson_tiny_scene  # noqa: F401
except ImportError:  # pragma: no cover - pytest not installed
    pass

__all__ = [
    "HEAVY_MODULES",
    "KNOWN_DIMS",
    "TINY_SCENE",
    "assert_schema",
    "check_analysis",
    "check_fast_paths",
    "check_plugin",
    "constant_wall_area",
    "constant_wall_load",
    "linear_wall_area",
    "linear_wall_load",
    "markov_cross_check",
    "material",
    "merge_scene",
    "mirrored_gaussian_area",
    "oracles",
    "pressures",
    "registry_with",
    "sample_params",
    "scene",
    "spectrum",
    "tiny_scene",
    "two_wall_areas",
]
