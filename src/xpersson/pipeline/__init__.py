"""The single-scene pipeline: resolved scene -> coefficient -> walls -> engine -> Dataset.

Modules: :mod:`.frontend` (the one front end: a scene from a path or dict, the plugins'
context and clock, the default pressure grid), :mod:`.stages` (the checked plugin calls
before the engine), :mod:`.run` (the run itself, orchestration only), :mod:`.assemble` (the
Dataset: core variables, plugin contributions, attributes), :mod:`.solve_at` (the analyses'
``ctx.solve_at``), :mod:`.diagnostics` (P resolution, theory regime) and :mod:`.progress`.
"""

from __future__ import annotations

from ._insert import direct_dataset
from .assemble import squeeze_p0
from .diagnostics import DIAGNOSTICS, P_RTOL, SLOPE_LIMIT, pdf_resolution, regime_warnings
from .frontend import as_scene, default_pressure_grid, scene_context
from .progress import progress_bar, run_with_progress
from .run import run

__all__ = [
    "run",
    "run_with_progress",
    "as_scene",
    "scene_context",
    "default_pressure_grid",
    "squeeze_p0",
    "direct_dataset",
    "progress_bar",
    "DIAGNOSTICS",
    "P_RTOL",
    "SLOPE_LIMIT",
    "pdf_resolution",
    "regime_warnings",
]
