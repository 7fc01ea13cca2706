"""The single-scene run, orchestration only: resolved scene -> coefficient -> walls -> engine ->
Dataset (the work of each step lives in :mod:`.frontend`, :mod:`.stages`, :mod:`.assemble`)."""

from __future__ import annotations

import contextlib

import numpy as np
import xarray as xr

from .. import checks, memory, plugins, provenance
from ..cache import solve_scope
from ..plugins.solved import unresolved_quiet
from ..scene import ResolvedScene, SceneError
from . import model_error
from ._draft import Draft
from .assemble import add_analyses, add_outputs, assemble, attributes, diagnostics_notes
from .body import body_dataset
from .frontend import (
    diffusion_clock,
    pressure_grid,
    replaced,
    scene_context,
    spectrum_kinks,
)
from .solve_at import make_solve_at
from .stages import coefficient_arrays, declares_shared_tau, load_walls, validate

__all__ = ["run"]


def run(rs: ResolvedScene, *, squeeze: bool = True, model_errors: bool = False) -> xr.Dataset:
    """Run a resolved scene (see :func:`xpersson.solve`).

    ``squeeze=False`` keeps a single load's ``p0`` dimension (a sweep squeezes its stacked
    blocks once instead of every point; see :func:`squeeze_p0`). ``model_errors``: the
    model-error ancillaries added (:func:`~xpersson.pipeline.model_error.attach`; a sweep adds
    them over its points instead). The Dataset is made once, at the end (the steps add to a
    :class:`~xpersson.pipeline._draft.Draft`; an analysis is handed the Dataset made before it
    runs). Every plugin call runs under
    ``[solver] plugin_time_limit`` when the scene sets one (:mod:`xpersson.plugins._limits`).
    The run is one solve of :mod:`xpersson.cache`: its ``"solve"``-scoped caches live until it
    returns.
    """
    with plugins.time_limit(rs.plugin_time_limit), solve_scope():
        return _run(rs, squeeze, model_errors)


def _run(rs: ResolvedScene, squeeze: bool, model_errors: bool) -> xr.Dataset:
    from .. import engine

    who = rs.labels  # plugin labels and provenance were captured when the scene was resolved
    analysis_labels = [rs.labels[f"analyses.{name}"] for name, _ in rs.analyses]
    ctx = scene_context(rs)
    validate(rs, ctx, who["boundary"], analysis_labels)  # the plugins' own checks first
    coef = rs.coefficient
    clock = diffusion_clock(ctx, coef, kinks=spectrum_kinks(rs.psd))
    tau_c, f_z, tau_eff, tau_shared = coefficient_arrays(coef, ctx, who["coefficient"], clock.key)
    walls = load_walls(rs, ctx, clock, who["boundary"])
    p_grid = pressure_grid(rs, walls, tau_eff) if rs.pressure_pdf else None
    if p_grid is not None:
        ctx = replaced(ctx, p=p_grid)

    memory.check_request(rs.p0.size, rs.zeta.size, None if p_grid is None else p_grid.size)
    # one engine call for the whole batch (loads sharing their walls are solved together)
    first = walls[0]
    shared = walls.count(first) == len(walls)  # identity first: cheap for shared walls
    # loads sharing tau(zeta) hand the engine one row (validated once, broadcast without copy)
    try:
        results = engine.solve_batch(
            tau_c if tau_shared else tau_eff,
            rs.p0,
            first if shared else walls,
            rtol=rs.rtol,
            atol=rs.atol,
            method=rs.method,
            p_out=p_grid,
            options=rs.solver_options or None,
        )
    except engine.MethodError as exc:  # (raised before any work)
        raise SceneError(f"solver.method = {rs.method!r}: {exc} [{who['boundary']}]") from None
    # (the variable where the closure may differ, its own writable copy where it did not)
    eff_out = None if declares_shared_tau(coef) else np.array(tau_eff) if tau_shared else tau_eff
    ds = assemble(rs, ctx, results, tau_c, f_z, eff_out, p_grid)
    core = checks.check_core(ds)  # the engine's outputs, like every plugin's (load -> message)
    if type(coef).interpret is not plugins.Coefficient.interpret:  # the base's gives nothing
        with checks.calling(who["coefficient"], "interpret()"):
            coef_out = coef.interpret(ctx)
        add_outputs(ds, coef_out, type(coef).outputs, who["coefficient"])
    with checks.calling(who["boundary"], "interpret()"):
        extra = rs.boundary.interpret(replaced(ctx, clock=clock), results)
    add_outputs(ds, extra, type(rs.boundary).outputs, who["boundary"])
    if rs.analyses or rs.geometry is not None:  # they may sample the solve densely
        ctx = replaced(
            ctx,
            coefficient=coef,
            boundary=rs.boundary,
            solve_at=make_solve_at(rs, ctx, walls, clock),
        )
    if rs.analyses:  # an analysis reads the Dataset
        ds = ds.dataset() if isinstance(ds, Draft) else ds
        with _quiet_for_bodies(rs):
            add_analyses(rs, ctx, ds, analysis_labels)
    attributes(
        ds, rs, lambda: provenance.global_attributes(rs), results, diagnostics_notes(ds), core
    )
    if rs.geometry is not None:  # a finite body: its nominal pressure on the solved interface
        with _quiet_for_bodies(rs):
            ds = body_dataset(rs, ctx, ds.dataset() if isinstance(ds, Draft) else ds)
    elif rs.p0_scalar and squeeze:  # one load: p0 a scalar coordinate (= ds.isel(p0=0))
        ds = ds.squeeze(own=True) if isinstance(ds, Draft) else Draft.of(ds).squeeze()
    if model_errors:
        model_error.attach(ds, rs)
    return ds.dataset() if isinstance(ds, Draft) else ds


def _quiet_for_bodies(rs: ResolvedScene) -> contextlib.AbstractContextManager[None]:
    """For a finite body, :class:`~xpersson.plugins.solved.UnresolvedDrop` silenced (its
    lightest rings, near the contact's edge, weigh ~nothing in its integrals); else nothing."""
    return unresolved_quiet() if rs.geometry is not None else contextlib.nullcontext()
