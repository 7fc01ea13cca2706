"""The one front end of a solve: the scene from what the user gives, the context and clock the
plugins see, and the default pressure grid (shared by the single-scene run and the sweep)."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from ..cache import content_key
from ..physics.grids import GridError
from ..physics.grids import pressure_grid as _pressure_grid
from ..plugins import DiffusionClock, SceneContext
from ..scene import ResolvedScene, Scene, SceneError, load_scene

__all__ = [
    "as_scene",
    "scene_context",
    "diffusion_clock",
    "spectrum_kinks",
    "pressure_grid",
    "default_pressure_grid",
]


def as_scene(scene: str | Path | Mapping[str, Any] | Scene) -> Scene:
    """Accept a path, a dict or a :class:`Scene`."""
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, str | Path):
        return load_scene(scene)
    if isinstance(scene, Mapping):
        return Scene(dict(scene))
    raise TypeError(f"scene must be a path, a dict or a Scene, got {type(scene).__name__}")


def scene_context(rs: ResolvedScene) -> SceneContext:
    """The :class:`~xpersson.plugins.SceneContext` of a resolved scene (no pressure grid yet)."""
    return SceneContext(
        psd=rs.psd,
        E=rs.E,
        nu=rs.nu,
        E_star=rs.E_star,
        p0=rs.p0,
        zeta=rs.zeta,
        p=None,
        rtol=rs.rtol,
        atol=rs.atol,
        method=rs.method,
    )


def diffusion_clock(ctx: SceneContext, coef: Any, kinks: tuple[float, ...] = ()) -> DiffusionClock:
    """The coefficient's diffusion clock (tau(zeta) [Pa^2] and its inverse) up to zeta_max,
    keyed on :meth:`~xpersson.plugins.Coefficient.clock_key` when the coefficient knows it (a
    key holding anything :func:`~xpersson.cache.content_key` refuses: no key)."""
    key_of = getattr(coef, "clock_key", None)
    key = key_of(ctx) if key_of is not None else None
    if key is not None:
        try:
            key = content_key(key)
        except TypeError:
            key = None
    return DiffusionClock(
        lambda z: coef.tau(ctx, z), lambda z: coef.f(ctx, z), ctx.zeta_max, kinks=kinks, key=key
    )


def spectrum_kinks(psd: Any) -> tuple[float, ...]:
    """The spectrum's nodes as magnifications q/q_L (where f may have kinks: a hint for the
    clock's inverse); none for a spectrum with very many nodes or without nodes (no ``nodes``
    method, or one that raises :class:`NotImplementedError`). Any other error of ``nodes()``
    or ``q_L`` propagates: a broken spectrum is not a spectrum without nodes."""
    nodes_of = getattr(psd, "nodes", None)
    if nodes_of is None:
        return ()
    try:
        raw = nodes_of()
    except NotImplementedError:
        return ()
    nodes = np.asarray(raw, dtype=float) / float(psd.q_L)
    if nodes.ndim != 1 or nodes.size > 4096:
        return ()
    return tuple(nodes.tolist())


def pressure_grid(rs: ResolvedScene, walls: list[Any], tau_eff: np.ndarray) -> np.ndarray:
    """The scene's pressure grid [Pa]: ``output.p`` or the default of
    :func:`xpersson.physics.grids.pressure_grid` for these walls and effective tau [Pa^2]."""
    if rs.p is not None:
        return rs.p
    try:
        return _pressure_grid(rs.p0, walls, tau_eff, rs.p_points, rs.p_max)
    except GridError as exc:
        raise SceneError(f"output.p_max: {exc}") from None


def default_pressure_grid(rs: ResolvedScene) -> np.ndarray:
    """The pressure grid [Pa] :func:`~xpersson.pipeline.run` uses for ``rs`` when the scene
    gives none."""
    ctx = scene_context(rs)
    coef = rs.coefficient
    tau_eff = np.asarray(coef.effective_tau(ctx, rs.zeta), float).reshape(rs.p0.size, -1)
    clock = diffusion_clock(ctx, coef)
    walls = [rs.boundary.walls(ctx, float(p0), clock) for p0 in rs.p0]
    return pressure_grid(rs, walls, tau_eff)
