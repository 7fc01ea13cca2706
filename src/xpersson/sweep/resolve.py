"""Resolve a sweep's points: every point before any work (bad input fails there, naming the
point), or the points of one block (a worker's task); a material or stackable region resolves
one point per combination of the other swept values."""

from __future__ import annotations

import dataclasses
import itertools
import math
from collections.abc import Callable
from typing import Any

import numpy as np

from ..pipeline import default_pressure_grid
from ..plugins import get_registry
from ..scene import SceneError, with_spectrum
from .batched import SweepPoints, material_dims, resolved_region
from .blocks import Block
from .derived import derived_region
from .plan import SweepPlan

__all__ = ["resolve_points", "resolve_block", "resolve_index", "grid_summary", "GRID_CHANGES"]


def _where(plan: SweepPlan, index: tuple[int, ...]) -> str:
    """A point's swept values, for messages."""
    return ", ".join(
        f"{g[0].path} = {g[0].values[i]:g}" for g, i in zip(plan.groups, index, strict=True)
    )


def resolve_index(plan: SweepPlan, index: tuple[int, ...], registry: Any) -> Any:
    """Resolve one point; a :class:`SceneError` names the point's swept values."""
    try:
        return plan.point_scene(index).resolve(registry)
    except SceneError as exc:
        raise SceneError(f"sweep point {_where(plan, index)}: {exc}") from None


def _resolver(plan: SweepPlan, registry: Any, first: Any = None) -> Callable[..., Any]:
    """``resolve(index)``: :func:`resolve_index`, the first point given as ``first`` when it
    was resolved already (:func:`check_size`)."""
    zero = (0,) * len(plan.shape)

    def resolve(index: tuple[int, ...]) -> Any:
        if first is not None and tuple(index) == zero:
            return first
        return resolve_index(plan, index, registry)

    return resolve


def _spectrum_resolver(
    plan: SweepPlan, registry: Any, first_point: Any = None
) -> Callable[[tuple[int, ...]], Any]:
    """``resolve(index)`` for the sub-points of a batched region: when every swept parameter
    outside the material is a spectrum parameter, the first point is resolved in full and
    every later one rebuilds only its spectrum (:func:`~xpersson.scene._resolve.with_spectrum`:
    the same checks of the same inputs, the same result)."""
    material = material_dims(plan.groups)
    spectral = all(
        p.path.startswith("spectrum.")
        for g, m in zip(plan.groups, material, strict=True)
        if not m
        for p in g
    )
    first: list[Any] = []
    memo: dict[Any, Any] = {}  # spectrum values converted once for the whole sweep
    full = _resolver(plan, registry, first_point)

    def resolve(index: tuple[int, ...]) -> Any:
        if not (spectral and first):
            first.append(full(index))
            return first[-1]
        try:
            return with_spectrum(first[0], plan.point_scene(index), registry, memo)
        except SceneError as exc:
            raise SceneError(f"sweep point {_where(plan, index)}: {exc}") from None

    return resolve


def _region(
    plan: SweepPlan,
    start: tuple[int, ...],
    stop: tuple[int, ...],
    registry: Any,
    first: Any = None,
) -> Any:
    """The resolved points of a region: one resolve per non-material combination
    (:func:`.batched.resolved_region`), one per region where the swept parameters are declared
    stackable (``fast_paths.stacked_params``, :func:`.derived.derived_region`), or ``None``
    (resolve every point); ``first``: the sweep's first point, resolved already."""
    region = resolved_region(plan.groups, start, stop, _spectrum_resolver(plan, registry, first))
    if region is not None:
        return region
    return derived_region(
        plan,
        start,
        stop,
        _resolver(plan, registry, first),
        lambda i: _where(plan, i),
        registry,
    )


GRID_CHANGES = (
    "sweep: the swept parameters change the magnification grid (q_1/q_L differs "
    "between points); give output.zeta_max (at most the smallest q_1/q_L) or "
    "output.zeta so that every point shares one grid"
)


def resolve_points(plan: SweepPlan, registry: Any, first: Any = None) -> list[Any]:
    """Resolve every point before any work (bad input fails here, naming the point);
    ``first``: the first point resolved already (as :func:`check_size` returns it)."""
    registry = registry or get_registry()
    points: Any = _region(plan, (0,) * len(plan.shape), plan.shape, registry, first)
    if points is None:
        resolve = _resolver(plan, registry, first)
        points = [resolve(index) for index in plan.indices()]
    summary = grid_summary(points)
    if summary[0] is None:
        raise SceneError(GRID_CHANGES)
    if summary[1] is not None:
        grid = np.linspace(*summary[1], points[0].p_points)
        points = [dataclasses.replace(rs, p=grid) for rs in points]
    return points


def grid_summary(points: list[Any]) -> tuple[np.ndarray | None, tuple[float, float] | None]:
    """(the shared zeta grid or None when the points differ, default pressure-grid bounds)."""
    if isinstance(points, SweepPoints):  # derived points share their sub-point's grids
        if any(rs.pressure_pdf and rs.p is None for rs in points.distinct()):
            points = list(points)
        else:
            points = points.distinct()
    zeta = points[0].zeta
    for rs in points[1:]:
        if rs.zeta.shape != zeta.shape or not np.array_equal(rs.zeta, zeta):
            return None, None
    if not (points[0].pressure_pdf and points[0].p is None):
        return zeta, None
    lo, hi = math.inf, -math.inf
    for rs in points:
        grid = default_pressure_grid(rs)
        lo, hi = min(lo, float(grid[0])), max(hi, float(grid[-1]))
    return zeta, (lo, hi)


def resolve_block(plan: SweepPlan, block: Block, registry: Any) -> list[Any]:
    """Resolve the points of one block (a worker's task), in C order."""
    registry = registry or get_registry()
    region = _region(plan, block.start, block.stop, registry)
    if region is not None:
        return region
    ranges = (range(a, b) for a, b in zip(block.start, block.stop, strict=True))
    return [resolve_index(plan, index, registry) for index in itertools.product(*ranges)]
