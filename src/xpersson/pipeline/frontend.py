"""The one front end of a solve: the scene from what the user gives, the context and clock the
plugins see, and the default pressure grid (shared by the single-scene run and the sweep)."""

from __future__ import annotations

import copy
import dataclasses
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from .. import provenance
from ..cache import Cache, made_key
from ..checks import plugin_label
from ..options import compiled_enabled
from ..physics.grids import GridError
from ..physics.grids import pressure_grid as _pressure_grid
from ..plugins import DiffusionClock, PluginError, Registry, SceneContext, fast_paths_on
from ..scene import (
    DEFAULT_MODEL,
    PLUGIN_SECTIONS,
    ResolvedScene,
    Scene,
    SceneError,
    analysis_plan,
    load_scene,
    plugin_records,
)

__all__ = [
    "as_scene",
    "resolve",
    "reused",
    "scene_context",
    "replaced",
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


_RESOLVED = Cache(
    "pipeline.resolved",
    scope="process",
    maxsize=16,
    doc="a flat scene resolved (plugins, analyses, SI arrays, the archived values and their "
    "JSON text) by the scene's content and source; its plugins looked up at every use",
)


def resolve(scene: Scene, registry: Registry) -> ResolvedScene:
    """``scene.resolve(registry)``, made once per content of a scene that is flat and names
    its plugins, each of a class that declares ``FastPaths(reused=True)`` (its instances give
    what their parameters say, whatever was asked before), as does every analysis the scene
    requests or pulls in as a provider, none given a file parameter (``kind="path"``: the file
    may change), with the JSON text of its archived values: the solves of one scene (a study's
    loads one by one, a benchmark) convert, build, check and serialise it once (about a
    quarter of a closed-form load's cost). At every use the registry is asked for each
    section's class and the analyses are planned again (another class or plan: resolved
    afresh); the labels and provenance records are the registry's and the scene is
    ``scene``. Resolved each time with the caches off or inside
    :func:`~xpersson.plugins.plain_paths`.
    """
    found = _kept(scene, registry, made=True)
    return scene.resolve(registry) if found is None else found


def reused(scene: Scene, registry: Registry) -> ResolvedScene | None:
    """The resolution :func:`resolve` would reuse for ``scene``, when one is kept (``None``:
    none is, nothing resolved). A kept resolution is of a scene that :func:`xpersson.solve`
    found to sweep nothing (:func:`xpersson.sweep.expand`, a function of the scene's content
    and its plugins' classes, which this checks again): a solve that gets one skips that
    search."""
    if "sweep" in scene.data:
        return None
    return _kept(scene, registry, made=False)


def _kept(scene: Scene, registry: Registry, made: bool) -> ResolvedScene | None:
    """:func:`resolve`'s reused resolution of ``scene`` (``made``: resolved and kept on a
    miss; else only looked up), or ``None`` when it has none."""
    data = scene.data
    if "geometry" in data or not fast_paths_on():
        return None
    classes = _section_classes(data, registry)
    plan = _analysis_classes(data.get("analyses"), classes, registry)
    if classes is None or plan is None:
        return None
    try:
        key = (data, scene.source, compiled_enabled())
        if made:
            kept = _RESOLVED.get(key, lambda: _reusable(scene, registry))
        else:
            kept = _RESOLVED.peek(key)
    except TypeError:  # a value without a content key (an object in the scene)
        return None
    plugins = {s: getattr(kept, s) for s in PLUGIN_SECTIONS} if kept is not None else {}
    if (
        kept is None
        or [type(p) for p in plugins.values()] != list(classes.values())
        or [(n, type(a)) for n, a in kept.analyses] != plan
    ):
        return None  # a file parameter, or the registry's class changed (or none kept)
    names = kept.plugin_names
    rs = copy.copy(kept)  # (a shallow copy: dataclasses.replace re-runs __init__, ~2x slower)
    rs.scene, rs.analyses = scene, list(kept.analyses)
    rs.plugin_records, rs.plugin_records_json = plugin_records(
        plugins, names, rs.analyses, registry
    )
    rs.labels = {s: plugin_label(s, plugins[s], registry, names[s]) for s in PLUGIN_SECTIONS}
    rs.labels.update(
        (f"analyses.{n}", plugin_label("analyses", a, registry, n)) for n, a in rs.analyses
    )
    return rs


def _section_classes(data: Mapping[str, Any], registry: Registry) -> dict[str, type] | None:
    """Section -> the registry's class of the plugin the scene names, or ``None`` when a
    section names none, or a class that does not declare ``reused``."""
    classes = {}
    for section, group in PLUGIN_SECTIONS.items():
        raw = data.get(section) or {}
        model = raw.get("model", DEFAULT_MODEL.get(section)) if type(raw) is dict else None
        try:
            cls = registry.resolve(group, model) if type(model) is str else None
        except PluginError:  # the resolution's message
            cls = None
        if cls is None or not cls.fast_paths.reused:
            return None
        classes[section] = cls
    return classes


def _analysis_classes(
    requested: Any, classes: dict[str, type] | None, registry: Registry
) -> list[tuple[str, type]] | None:
    """``(name, class)`` of every analysis the registry plans for the scene (providers
    first; ``[]`` without analyses), or ``None`` when one does not declare ``reused`` or the
    plan fails (the resolution's message)."""
    if not requested:
        return []
    if classes is None or type(requested) is not dict:
        return None
    if any(type(raw) is not dict for raw in requested.values()):
        return None  # (the resolution's message)
    try:
        plan = analysis_plan(requested, classes, registry)
    except SceneError:
        return None
    if not all(cls.fast_paths.reused for _, cls, _ in plan):
        return None
    return [(name, cls) for name, cls, _ in plan]


def _reusable(scene: Scene, registry: Registry) -> ResolvedScene | None:
    """The resolved ``scene`` with the JSON text of its archived values, or ``None`` when a
    plugin or analysis of it reads a file, a ``kind="path"`` parameter given (then resolved
    at each use: the file may change; a path parameter left at None reads nothing)."""
    rs = scene.resolve(registry)
    for plugin in [getattr(rs, s) for s in PLUGIN_SECTIONS] + [a for _, a in rs.analyses]:
        given = plugin.params
        if any(
            p.kind == "path" and given.get(name) is not None
            for name, p in type(plugin).parameters.items()
        ):
            return None
    text = provenance.scene_json(rs.resolved)
    kept = dataclasses.replace(rs, resolved_text=(rs.resolved, text))
    for name in ("p0", "zeta", "p"):  # shared by the later solves: an edit in place raises
        value = getattr(kept, name)
        if isinstance(value, np.ndarray):
            value.setflags(write=False)
    return kept


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


def replaced(ctx: SceneContext, **changes: Any) -> SceneContext:
    """``dataclasses.replace(ctx, **changes)`` of a :class:`~xpersson.plugins.SceneContext`
    (whose fields are all ``__init__`` arguments, without a ``__post_init__``): the same
    context, its fields copied instead of ``__init__`` called again (~0.8 us instead of ~4.6;
    a solve makes one or two, an analysis one per re-solve).

    Raises
    ------
    TypeError
        For a name that is not a field (as ``dataclasses.replace`` raises).
    """
    unknown = changes.keys() - _CONTEXT_FIELDS
    if unknown:
        raise TypeError(f"SceneContext has no field {sorted(unknown)[0]!r}")
    new = object.__new__(SceneContext)
    state = new.__dict__  # (frozen: the instance dict is written directly)
    state.update(ctx.__dict__)
    state.update(changes)
    return new


_CONTEXT_FIELDS = frozenset(f.name for f in dataclasses.fields(SceneContext))


def diffusion_clock(ctx: SceneContext, coef: Any, kinks: tuple[float, ...] = ()) -> DiffusionClock:
    """The coefficient's diffusion clock (tau(zeta) [Pa^2] and its inverse) up to zeta_max,
    keyed on :meth:`~xpersson.plugins.Coefficient.clock_key` when the coefficient knows it (a
    key holding anything :func:`~xpersson.cache.content_key` refuses: no key)."""
    key_of = getattr(coef, "clock_key", None)
    key = key_of(ctx) if key_of is not None else None
    if key is not None:
        try:
            key = made_key(key)  # (made once: it goes into the keys of the clock's uses)
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
