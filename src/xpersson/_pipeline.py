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

from . import provenance
from .plugins import DiffusionClock, SceneContext, VarSpec
from .plugins._registry import Registry, get_registry
from .scene import ResolvedScene, Scene, SceneError, load_scene
from .schema import COORDS, CORE_VARIABLES, stamp

__all__ = ["solve", "XperssonWarning", "as_scene"]


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
    try:
        rs.boundary.validate(ctx)
    except ValueError as exc:
        raise SceneError(f"boundary: {exc}") from None
    coef = rs.coefficient
    zeta = rs.zeta
    tau_c = np.asarray(coef.tau(ctx, zeta), float)
    f_z = np.asarray(coef.f(ctx, zeta), float)
    tau_eff = np.asarray(coef.effective_tau(ctx, zeta), float).reshape(rs.p0.size, zeta.size)
    clock = DiffusionClock(lambda z: coef.tau(ctx, z), lambda z: coef.f(ctx, z), ctx.zeta_max)
    walls = [rs.boundary.walls(ctx, float(p0), clock) for p0 in rs.p0]
    p_grid = _pressure_grid(rs, walls, tau_eff) if rs.pressure_pdf else None
    if p_grid is not None:
        ctx = dataclasses.replace(ctx, p=p_grid)

    results = []
    for i, p0 in enumerate(rs.p0):
        lower, upper = walls[i]
        results.append(
            engine.solve(tau_eff[i], float(p0), lower, upper, rtol=rs.rtol, atol=rs.atol,
                         method=rs.method, p_out=p_grid, options=rs.solver_options or None)
        )
    ds = _assemble(rs, ctx, results, tau_c, f_z, tau_eff, p_grid)
    _add(ds, coef.interpret(ctx), type(coef).outputs, "coefficient")
    extra = rs.boundary.interpret(ctx, results)
    _add(ds, extra, type(rs.boundary).outputs, "boundary")
    if rs.analyses:  # analyses read the scene's declarations and may sample the solve densely
        ctx = dataclasses.replace(
            ctx, coefficient=coef, boundary=rs.boundary, solve_at=_solve_at(rs, ctx, walls)
        )
    for name, analysis in rs.analyses:
        out = analysis.compute(ctx, ds)
        missing = [v for v in type(analysis).provides if v not in out]
        if missing:
            raise RuntimeError(f"analysis {name!r} did not provide {missing}")
        _add(ds, out, type(analysis).outputs, f"analysis {name!r}")
    _attributes(ds, rs, reg, results)
    if rs.p0_scalar:
        ds = ds.squeeze("p0")
    return ds


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
    results: list[Any],
    tau_c: np.ndarray,
    f_z: np.ndarray,
    tau_eff: np.ndarray,
    p_grid: np.ndarray | None,
) -> xr.Dataset:
    def stack(attr: str) -> np.ndarray:
        return np.stack([np.asarray(getattr(r, attr), float) for r in results])

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
        "solver_status": (("p0",), np.array([r.status for r in results], dtype=object)),
    }
    if not np.allclose(tau_eff, tau_c[None, :], rtol=1e-15, atol=0):
        data["effective_diffusion_time"] = (pz, tau_eff)
    if p_grid is not None:
        coords["p"] = ("p", p_grid)
        data["P"] = (("p0", "zeta", "p"), np.stack([np.asarray(r.P, float) for r in results]))
    ds = xr.Dataset(data, coords=coords)
    stamp(ds, COORDS)
    stamp(ds, CORE_VARIABLES)
    return ds


def _persson_G(tau_c: np.ndarray, p0: np.ndarray) -> np.ndarray:
    """``G = tau / p0^2`` per (p0, zeta); ``inf`` at a zero load (adhesive boundaries)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        G = tau_c[None, :] / p0[:, None] ** 2
    return np.where(np.isnan(G), np.inf, G)


def _add(ds: xr.Dataset, values: Mapping[str, Any], specs: Mapping[str, VarSpec], who: str) -> None:
    for name, value in values.items():
        if name not in specs:
            raise RuntimeError(f"{who} returned {name!r} without declaring it in its outputs")
        if name in ds.variables:
            raise RuntimeError(f"{who} returned {name!r}, which the Dataset already has")
        spec = specs[name]
        if isinstance(value, xr.DataArray):
            da = value.copy()
            da.attrs = {}
        else:
            dims, arr = value
            da = xr.DataArray(np.asarray(arr), dims=dims)
        if tuple(d for d in spec.dims) != tuple(da.dims):
            da = da.transpose(*[d for d in spec.dims if d in da.dims], ...)
        ds[name] = da
        ds[name].attrs.update(spec.attrs())


def _attributes(ds: xr.Dataset, rs: ResolvedScene, reg: Registry, results: list[Any]) -> None:
    bad = [(float(rs.p0[i]), r) for i, r in enumerate(results) if not r.success]
    status = "success" if not bad else bad[0][1].status
    message = "all loads met the requested tolerance" if not bad else "; ".join(
        f"p0 = {p:g} Pa: {r.status}: {r.message}" for p, r in bad[:5]
    )
    ds.attrs.update(provenance.global_attributes(rs, reg))
    ds.attrs["status"] = status
    ds.attrs["status_message"] = message
    ds.attrs["xpersson_solver"] = json.dumps(
        {
            "method": rs.resolved["solver"]["method"],
            "methods_used": sorted({r.method for r in results}),
            "rtol": rs.rtol,
            "atol": rs.atol,
            "max_error_estimate": float(max(np.max(r.error_estimate) for r in results)),
            "work": {
                "nsteps": int(sum(getattr(r, "nsteps", 0) for r in results)),
                "wall_time_s": float(sum(getattr(r, "wall_time", 0.0) for r in results)),
            },
        }
    )
    if bad:
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
