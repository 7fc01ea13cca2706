"""One-directional data flow: resolved scene -> coefficient -> walls -> engine -> Dataset."""

from __future__ import annotations

import dataclasses
import json
import warnings
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from . import _checks, memory, provenance
from .plugins import DiffusionClock, SceneContext, VarSpec
from .plugins._registry import Registry, get_registry
from .scene import ResolvedScene, Scene, SceneError, load_scene
from .schema import COORDS, CORE_VARIABLES, stamp

__all__ = ["solve", "XperssonWarning", "as_scene", "PluginFailure"]

PluginFailure = _checks.PluginFailure


class XperssonWarning(UserWarning):
    """A result is returned but a request could not be met (see the Dataset's ``status``)."""


def as_scene(scene: str | Path | Mapping[str, Any] | Scene) -> Scene:
    """Accept a path, a dict or a :class:`Scene`."""
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, str | Path):
        return load_scene(scene)
    if isinstance(scene, Mapping):
        return Scene(dict(scene))
    raise TypeError(f"scene must be a path, a dict or a Scene, got {type(scene).__name__}")


def solve(
    scene: str | Path | Mapping[str, Any] | Scene,
    *,
    registry: Registry | None = None,
    scheduler: Any = None,
    progress: bool | None = False,
    output: str | Path | None = None,
    chunk: int | None = None,
    workers: int | None = None,
    **overrides: Any,
) -> xr.Dataset:
    """Solve a scene and return the Dataset over (sweep dims..., p0, zeta[, p]).

    Parameters
    ----------
    scene : path, dict or Scene
        A TOML scene file, the same structure as a dict, or a :class:`~xpersson.Scene`.
        Sweepable parameters may be lists or ranges (see :mod:`xpersson.sweep`).
    registry : Registry, optional
        Plugin registry (default: the entry-point registry).
    scheduler : None, str or distributed.Client
        Where the points of a sweep run: ``None``/``"serial"`` (default), ``"threads"``,
        ``"processes"`` (a dask ``LocalCluster``), a scheduler address or a ``Client``.
    progress : bool or None
        Show a progress bar on stderr (``None``: when stderr is a terminal).
    output : path, optional
        Folder for a sweep written as one netCDF part per block plus an index; the returned
        Dataset is then opened lazily from it (see :func:`xpersson.open_dataset`).
    chunk : int, optional
        Points per block (task); default about a quarter of the points per worker.
    workers : int, optional
        Worker count for ``"threads"``/``"processes"`` (default: the number of cores).
    **overrides
        ``section__key=value`` replacements, e.g. ``load__p0="1 MPa"``.

    Returns
    -------
    xarray.Dataset
        CF-annotated results; ``ds.attrs["status"]`` is ``"success"`` when every load met the
        requested tolerance (otherwise an :class:`XperssonWarning` is issued too).

    Raises
    ------
    SceneError
        Malformed scene (raised before any work, naming the parameter).
    """
    sc = as_scene(scene)
    if overrides:
        sc = sc.with_values(**{k.replace("__", "."): v for k, v in overrides.items()})
    reg = registry or get_registry()
    from .sweep import expand

    plan = expand(sc, reg)
    if plan is not None:
        from ._sweeprun import solve_sweep

        return solve_sweep(plan, reg, scheduler=scheduler, progress=progress, output=output,
                           chunk=chunk, workers=workers)
    rs = sc.resolve(reg)
    return run(rs, reg)


def run(rs: ResolvedScene, reg: Registry) -> xr.Dataset:
    """Run a resolved scene (see :func:`solve`)."""
    from . import engine

    ctx = SceneContext(
        psd=rs.psd, E=rs.E, nu=rs.nu, E_star=rs.E_star, p0=rs.p0, zeta=rs.zeta,
        p=None, rtol=rs.rtol, atol=rs.atol, method=rs.method,
    )
    who = _labels(rs, reg)
    try:
        with _checks.calling(who["boundary"], "validate()", passthrough=(ValueError,)):
            rs.boundary.validate(ctx)
    except ValueError as exc:
        raise SceneError(f"boundary: {exc} [{who['boundary']}]") from None
    coef = rs.coefficient
    tau_c, f_z, tau_eff = _coefficient_arrays(coef, ctx, who["coefficient"])
    clock = DiffusionClock(lambda z: coef.tau(ctx, z), lambda z: coef.f(ctx, z), ctx.zeta_max)
    if getattr(type(rs.boundary), "walls_per_load", True):
        loads = [float(p0) for p0 in rs.p0]
    else:  # the boundary declares walls that do not depend on the load: ask once
        loads = [float(rs.p0[0])]
    walls = []
    for p0 in loads:
        with _checks.calling(who["boundary"], f"walls() for p0 = {p0:g} Pa"):
            pair = rs.boundary.walls(ctx, p0, clock)
        walls.append(_checks.check_walls(pair, p0, who["boundary"]))
    if len(walls) == 1 and rs.p0.size > 1:
        for p0 in rs.p0[1:]:  # the shared walls must leave every load inside
            _checks.check_walls(walls[0], float(p0), who["boundary"])
        walls = walls * rs.p0.size
    p_grid = _pressure_grid(rs, walls, tau_eff) if rs.pressure_pdf else None
    if p_grid is not None:
        ctx = dataclasses.replace(ctx, p=p_grid)

    memory.check_request(rs.p0.size, rs.zeta.size, None if p_grid is None else p_grid.size)
    # one engine call for the whole batch (loads sharing their walls are solved together)
    first = walls[0]
    shared = all(w is first or w == first for w in walls[1:])
    results = engine.solve_batch(tau_eff, rs.p0, first if shared else walls, rtol=rs.rtol,
                                 atol=rs.atol, method=rs.method, p_out=p_grid,
                                 options=rs.solver_options or None)
    ds = _assemble(rs, ctx, results, tau_c, f_z, tau_eff, p_grid)
    with _checks.calling(who["coefficient"], "interpret()"):
        coef_out = coef.interpret(ctx)
    _add(ds, coef_out, type(coef).outputs, who["coefficient"])
    with _checks.calling(who["boundary"], "interpret()"):
        extra = rs.boundary.interpret(ctx, results)
    _add(ds, extra, type(rs.boundary).outputs, who["boundary"])
    if rs.analyses:  # analyses read the scene's declarations and may sample the solve densely
        ctx = dataclasses.replace(
            ctx, coefficient=coef, boundary=rs.boundary, solve_at=_solve_at(rs, ctx, walls)
        )
    for name, analysis in rs.analyses:
        label = _checks.plugin_label("analyses", analysis, reg, name)
        with _checks.guard_dataset(ds, label) as view, _checks.calling(label, "compute()"):
            out = analysis.compute(ctx, view)
        missing = [v for v in type(analysis).provides if v not in (out or {})]
        if missing:
            raise _checks.PluginFailure(f"{label} did not provide {missing}", plugin=label)
        _add(ds, out, type(analysis).outputs, label)
    _attributes(ds, rs, reg, results, _diagnostics_notes(ds))
    if rs.p0_scalar:
        ds = ds.isel(p0=0)  # = squeeze("p0"): p0 becomes a scalar coordinate
    return ds


def _labels(rs: ResolvedScene, reg: Registry) -> dict[str, Any]:
    """Plugin labels (name + distribution) used in error messages."""
    return {
        section: _checks.plugin_label(section, getattr(rs, section), reg,
                                      rs.plugin_names.get(section))
        for section in ("spectrum", "coefficient", "boundary")
    }


def _coefficient_arrays(
    coef: Any, ctx: SceneContext, who: Any
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """tau(zeta), f(zeta) and the per-load effective tau [Pa^2], each checked."""
    nz, nl = ctx.zeta.size, ctx.p0.size
    with _checks.calling(who, "tau(zeta)"):
        tau_c = coef.tau(ctx, ctx.zeta)
    tau_c = _checks.check_array(tau_c, who, "tau(zeta)", (nz,), nonnegative=True,
                                nondecreasing_axis=0, unit="Pa2")
    with _checks.calling(who, "f(zeta)"):
        f_z = coef.f(ctx, ctx.zeta)
    f_z = _checks.check_array(f_z, who, "f(zeta)", (nz,), nonnegative=True, unit="Pa2")
    with _checks.calling(who, "effective_tau(zeta)"):
        tau_eff = coef.effective_tau(ctx, ctx.zeta)
    tau_eff = _checks.check_array(tau_eff, who, "effective_tau(zeta)", (nl, nz),
                                  nonnegative=True, nondecreasing_axis=1, unit="Pa2")
    return tau_c, f_z, tau_eff


def _solve_at(rs: ResolvedScene, ctx: SceneContext, walls: list[Any]) -> Any:
    """``(zeta, loads) -> area variables`` of the same solve at other magnifications."""
    from . import engine

    cache: dict[bytes, dict[str, np.ndarray]] = {}

    def solve_at(zeta: np.ndarray, loads: np.ndarray | None = None) -> dict[str, np.ndarray]:
        z = np.asarray(zeta, float)
        idx = np.arange(rs.p0.size) if loads is None else np.asarray(loads, dtype=int)
        key = z.tobytes() + idx.tobytes()
        if key in cache:  # several analyses sample the same grid
            return cache[key]
        c = dataclasses.replace(ctx, zeta=z, p=None, p0=rs.p0[idx])
        tau_eff = np.asarray(rs.coefficient.effective_tau(c, z), float).reshape(idx.size, -1)
        res = [
            engine.solve(tau_eff[k], float(rs.p0[i]), *walls[i], rtol=rs.rtol, atol=rs.atol,
                         method=rs.method)
            for k, i in enumerate(idx)
        ]
        out = {
            "area_fraction": np.stack([np.asarray(r.area, float) for r in res]),
            "non_contact_fraction": np.stack([np.asarray(r.non_area, float) for r in res]),
            "diffusion_time": np.asarray(rs.coefficient.tau(c, z), float),
            "effective_diffusion_time": tau_eff,
        }
        for name, value in rs.boundary.interpret(c, res).items():
            out[name] = np.asarray(value[1] if isinstance(value, tuple) else value, float)
        cache.clear()
        cache[key] = out
        return out

    return solve_at


def _pressure_grid(rs: ResolvedScene, walls: list[Any], tau_eff: np.ndarray) -> np.ndarray:
    if rs.p is not None:
        return rs.p
    tau_end = float(np.max(tau_eff[:, -1]))
    lo, hi = 0.0, float(np.max(rs.p0)) + 8.0 * np.sqrt(2.0 * max(tau_end, 0.0))
    for lower, upper in walls:
        lo = min(lo, float(np.min(_wall_positions(lower, tau_eff))))
        if upper is not None:
            hi = min(hi, float(np.max(_wall_positions(upper, tau_eff))))
    if rs.p_max is not None:
        hi = rs.p_max
    if not hi > lo:
        raise SceneError(f"output.p_max: must exceed the lower wall {lo:g} Pa")
    return np.linspace(lo, hi, rs.p_points)


def _wall_positions(wall: Any, tau_eff: np.ndarray) -> np.ndarray:
    pos = wall.position
    if callable(pos):
        return np.asarray(pos(tau_eff.ravel()), float)
    return np.asarray([pos], float)


def _assemble(
    rs: ResolvedScene,
    ctx: SceneContext,
    results: Any,
    tau_c: np.ndarray,
    f_z: np.ndarray,
    tau_eff: np.ndarray,
    p_grid: np.ndarray | None,
) -> xr.Dataset:
    def stack(attr: str) -> np.ndarray:
        return np.asarray(getattr(results, attr), float)  # EngineBatch: stacked arrays

    psd = rs.psd
    q_nodes = np.asarray(psd.nodes(), float)
    coords: dict[str, Any] = {
        "zeta": ("zeta", rs.zeta),
        "p0": ("p0", rs.p0),
        "q": ("zeta", rs.zeta * psd.q_L),
        "q_psd": ("q_psd", q_nodes),
    }
    pz = ("p0", "zeta")
    data: dict[str, Any] = {
        "area_fraction": (pz, stack("area")),
        "non_contact_fraction": (pz, stack("non_area")),
        "G": (pz, _persson_G(tau_c, rs.p0)),
        "diffusion_time": (("zeta",), tau_c),
        "diffusion_coefficient": (("zeta",), f_z),
        "psd_C": (("q_psd",), np.asarray(psd.C(q_nodes), float)),
        "E": ((), rs.E),
        "nu": ((), rs.nu),
        "E_star": ((), rs.E_star),
        "h_rms": ((), float(psd.h_rms())),
        "rms_slope": ((), float(psd.rms_slope())),
        "load_balance": (pz, stack("load_balance")),
        "probability_balance": (pz, stack("probability_balance")),
        "error_estimate": (pz, stack("error_estimate")),
        "solver_status": (("p0",), np.array(results.status, dtype=object)),
    }
    if not np.array_equal(tau_eff, np.broadcast_to(tau_c, tau_eff.shape)):
        data["effective_diffusion_time"] = (pz, tau_eff)
    if p_grid is not None:
        coords["p"] = ("p", p_grid)
        data["P"] = (("p0", "zeta", "p"), stack("P"))
    return _dataset(data, coords)


_ATTRS: dict[str, dict[str, Any]] = {}


def _attrs_of(name: str) -> dict[str, Any]:
    """CF attrs of a core variable or coordinate (computed once per process, copied out)."""
    if name not in _ATTRS:
        spec = COORDS.get(name) or CORE_VARIABLES.get(name)
        _ATTRS[name] = spec.attrs() if spec is not None else {}
    return dict(_ATTRS[name])


def _dataset(data: dict[str, Any], coords: dict[str, Any]) -> xr.Dataset:
    """Build the Dataset in one pass: variables carry their CF attrs from the schema table.

    Equivalent to ``xr.Dataset(data, coords=coords)`` followed by :func:`stamp`; the direct
    constructor skips xarray's merge/alignment (nothing to align: one set of coordinates).
    """
    def var(name: str, dims: Any, val: Any) -> xr.Variable:
        arr = np.asarray(val)
        if arr.dtype.kind in "fiub" or (arr.dtype == object and arr.ndim == 1):
            return xr.Variable(dims, arr, _attrs_of(name), fastpath=True)  # already an ndarray
        return xr.Variable(dims, val, _attrs_of(name))

    variables = {name: var(name, dims, val) for name, (dims, val) in data.items()}
    cvars = {name: var(name, dims, val) for name, (dims, val) in coords.items()}
    try:
        from xarray.core.indexes import PandasIndex

        indexes = {}
        for name, var in cvars.items():
            if var.dims == (name,):
                indexes[name] = PandasIndex.from_variables({name: var}, options={})
                cvars[name] = indexes[name].create_variables({name: var})[name]
        dims: dict[str, int] = {}
        for var in (*variables.values(), *cvars.values()):
            dims.update(zip(var.dims, var.shape, strict=True))
        return xr.Dataset._construct_direct(  # noqa: SLF001 - see docstring
            {**variables, **cvars}, set(cvars), dims, {}, indexes
        )
    except (AttributeError, TypeError, ImportError):  # pragma: no cover - other xarray versions
        ds = xr.Dataset(data, coords=coords)
        stamp(ds, COORDS)
        stamp(ds, CORE_VARIABLES)
        return ds


def _persson_G(tau_c: np.ndarray, p0: np.ndarray) -> np.ndarray:
    """``G = tau / p0^2`` per (p0, zeta); ``inf`` at a zero load (adhesive boundaries)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        G = tau_c[None, :] / p0[:, None] ** 2
    return np.where(np.isnan(G), np.inf, G)


def _add(
    ds: xr.Dataset, values: Mapping[str, Any], specs: Mapping[str, VarSpec], who: object
) -> None:
    """Check a plugin's contribution against its VarSpecs (see :mod:`._checks`), then add it."""
    checked = _checks.check_contributions(ds, values, specs, who)
    for name, da in checked.items():
        try:
            ds[name] = da
        except ValueError as exc:  # conflicting sizes of a plugin's own dimension
            raise _checks.PluginFailure(f"{who}: variable {name!r}: {exc}", plugin=who,
                                        variable=name) from None
        ds[name].attrs.update(specs[name].attrs())


def _diagnostics_notes(ds: xr.Dataset) -> list[str]:
    """Add the P-resolution diagnostics; collect them and the regime warnings as notes."""
    from . import _diagnostics

    notes = _diagnostics.regime_warnings(ds)
    ds.attrs["regime_warnings"] = json.dumps(notes)
    unresolved = _diagnostics.pdf_resolution(ds)
    return notes + ([unresolved] if unresolved else [])


def _attributes(
    ds: xr.Dataset, rs: ResolvedScene, reg: Registry, results: Any, notes: list[str]
) -> None:
    success = np.asarray(results.success, dtype=bool)
    bad = [(float(rs.p0[i]), results[int(i)]) for i in np.flatnonzero(~success)[:5]]
    status = "success" if not bad else bad[0][1].status
    message = "all loads met the requested tolerance" if not bad else "; ".join(
        f"p0 = {p:g} Pa: {r.status}: {r.message}" for p, r in bad
    )
    if notes:
        message = "; ".join([message, *notes])
    ds.attrs.update(provenance.global_attributes(rs, reg))
    ds.attrs["status"] = status
    ds.attrs["status_message"] = message
    ds.attrs["xpersson_solver"] = json.dumps(
        {
            "method": rs.resolved["solver"]["method"],
            "methods_used": sorted(set(results.method)),
            "rtol": rs.rtol,
            "atol": rs.atol,
            "max_error_estimate": float(np.max(results.error_estimate)),
            "work": {
                "nsteps": int(np.sum(results.nsteps)),
                "wall_time_s": float(results.wall_time),
            },
        }
    )
    if bad or notes:
        warnings.warn(f"xpersson: {message}", XperssonWarning, stacklevel=4)


def default_pressure_grid(rs: ResolvedScene) -> np.ndarray:
    """The pressure grid [Pa] :func:`run` uses for ``rs`` when the scene gives none."""
    ctx = SceneContext(
        psd=rs.psd, E=rs.E, nu=rs.nu, E_star=rs.E_star, p0=rs.p0, zeta=rs.zeta,
        p=None, rtol=rs.rtol, atol=rs.atol, method=rs.method,
    )
    coef = rs.coefficient
    tau_eff = np.asarray(coef.effective_tau(ctx, rs.zeta), float).reshape(rs.p0.size, -1)
    clock = DiffusionClock(lambda z: coef.tau(ctx, z), lambda z: coef.f(ctx, z), ctx.zeta_max)
    walls = [rs.boundary.walls(ctx, float(p0), clock) for p0 in rs.p0]
    return _pressure_grid(rs, walls, tau_eff)
