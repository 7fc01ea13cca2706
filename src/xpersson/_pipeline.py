"""One-directional data flow: resolved scene -> coefficient -> walls -> engine -> Dataset."""

from __future__ import annotations

import dataclasses
import json
import sys
import warnings
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from . import _checks, memory, provenance
from .plugins import Analysis, DiffusionClock, SceneContext, VarSpec
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

        return solve_sweep(
            plan,
            reg,
            scheduler=scheduler,
            progress=progress,
            output=output,
            chunk=chunk,
            workers=workers,
        )
    rs = sc.resolve(reg)
    if progress is False or (progress is None and not sys.stderr.isatty()):
        return run(rs, reg)
    return _run_with_progress(rs, reg, progress)


def _run_with_progress(rs: ResolvedScene, reg: Registry, progress: bool | None) -> xr.Dataset:
    """:func:`run` with a counter of the engine's work on stderr (long moving-wall solves).

    The bar appears only once a solver reports work (closed-form solves print nothing).
    """
    from ._sweeprun import _progress_bar
    from .engine import progress_reporting

    bar: list[Any] = []

    def advance(node_steps: int) -> None:
        if not bar:  # first report: make the bar (None when tqdm is missing: warned once)
            bar.append(_progress_bar(None, progress, "xpersson solve", unit="node-step"))
        if bar[0] is not None:
            bar[0].update(node_steps)

    try:
        with progress_reporting(advance):
            return run(rs, reg)
    finally:
        if bar and bar[0] is not None:
            bar[0].close()


def run(rs: ResolvedScene, reg: Registry, *, squeeze: bool = True) -> xr.Dataset:
    """Run a resolved scene (see :func:`solve`).

    ``squeeze=False`` keeps a single load's ``p0`` dimension (a sweep squeezes its stacked
    blocks once instead of every point; see :func:`squeeze_p0`).
    """
    from . import engine

    ctx = SceneContext(
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
    who = _labels(rs, reg)
    try:
        with _checks.calling(who["boundary"], "validate()", passthrough=(ValueError,)):
            rs.boundary.validate(ctx)
    except ValueError as exc:
        raise SceneError(f"boundary: {exc} [{who['boundary']}]") from None
    for name, analysis in rs.analyses:  # the analyses' own checks, before any solving
        if type(analysis).validate is Analysis.validate:
            continue
        label = _checks.plugin_label("analyses", analysis, reg, name)
        try:
            with _checks.calling(label, "validate()", passthrough=(ValueError,)):
                analysis.validate(ctx)
        except ValueError as exc:
            raise SceneError(f"analyses.{name}: {exc} [{label}]") from None
    coef = rs.coefficient
    tau_c, f_z, tau_eff, tau_shared = _coefficient_arrays(coef, ctx, who["coefficient"])
    clock = DiffusionClock(
        lambda z: coef.tau(ctx, z),
        lambda z: coef.f(ctx, z),
        ctx.zeta_max,
        kinks=_spectrum_kinks(rs.psd),
    )
    if getattr(type(rs.boundary), "walls_per_load", True):
        walls = []
        for p0 in rs.p0:
            with _checks.calling(who["boundary"], f"walls() for p0 = {float(p0):g} Pa"):
                pair = rs.boundary.walls(ctx, float(p0), clock)
            walls.append(_checks.check_walls(pair, float(p0), who["boundary"]))
    else:  # the boundary declares walls that do not depend on the load: ask once
        walls = [_shared_walls(rs, ctx, clock, who["boundary"])] * rs.p0.size
    p_grid = _pressure_grid(rs, walls, tau_eff) if rs.pressure_pdf else None
    if p_grid is not None:
        ctx = dataclasses.replace(ctx, p=p_grid)

    memory.check_request(rs.p0.size, rs.zeta.size, None if p_grid is None else p_grid.size)
    # one engine call for the whole batch (loads sharing their walls are solved together)
    first = walls[0]
    shared = walls.count(first) == len(walls)  # identity first: cheap for shared walls
    # loads sharing tau(zeta) hand the engine one row (validated once, broadcast without copy)
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
    ds = _assemble(rs, ctx, results, tau_c, f_z, None if tau_shared else tau_eff, p_grid)
    core = _checks.check_core(ds)  # the engine's outputs, like every plugin's (load -> message)
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
    _attributes(ds, rs, reg, results, _diagnostics_notes(ds), core)
    if rs.p0_scalar and squeeze:
        ds = squeeze_p0(ds)  # = ds.isel(p0=0): p0 becomes a scalar coordinate
    return ds


def _spectrum_kinks(psd: Any) -> tuple[float, ...]:
    """The spectrum's nodes as magnifications q/q_L (where f may have kinks: a hint for the
    clock's inverse); none for a spectrum with very many nodes or without ``nodes()``."""
    try:
        nodes = np.asarray(psd.nodes(), dtype=float) / float(psd.q_L)
    except Exception:  # noqa: BLE001 - only a hint
        return ()
    if nodes.ndim != 1 or nodes.size > 4096:
        return ()
    return tuple(nodes.tolist())


def _shared_walls(rs: ResolvedScene, ctx: SceneContext, clock: Any, who: Any) -> tuple:
    """The walls of a boundary whose walls do not depend on the load, checked for every load.

    Asked once (at the first load) and checked as :func:`._checks.check_walls` checks each
    load, with the positions at ``tau = 0`` compared with all loads at once; the first load
    left outside (if any) is reported exactly as the per-load check reports it.
    """
    p_first = float(rs.p0[0])
    with _checks.calling(who, f"walls() for p0 = {p_first:g} Pa"):
        pair = rs.boundary.walls(ctx, p_first, clock)
    pair = _checks.check_walls(pair, p_first, who)
    if rs.p0.size > 1:
        lower, upper = pair
        zero = np.zeros(1)
        inside = rs.p0 > float(np.asarray(lower.at(zero), float)[0])
        if upper is not None:
            inside &= rs.p0 < float(np.asarray(upper.at(zero), float)[0])
        outside = np.flatnonzero(~inside)
        if outside.size:  # raises the per-load check's message for that load
            _checks.check_walls(pair, float(rs.p0[outside[0]]), who)
    return pair


def squeeze_p0(ds: xr.Dataset) -> xr.Dataset:
    """``ds.isel(p0=0)`` for a one-load Dataset, built directly from the variables.

    Every variable along ``p0`` (size 1) loses that dimension (a view of its data); ``p0``
    becomes a scalar coordinate without an index; the other indexes are kept as they are.
    Falls back to ``isel`` on an xarray without the direct constructor.
    """
    try:
        variables = {}
        for name, var in ds.variables.items():
            if "p0" in var.dims:
                axis = var.dims.index("p0")
                dims = var.dims[:axis] + var.dims[axis + 1 :]
                data = np.take(var.values, 0, axis=axis)
                variables[name] = xr.Variable(dims, data, var.attrs, var.encoding, fastpath=True)
            else:
                variables[name] = var
        indexes = {k: v for k, v in ds.xindexes.items() if k != "p0"}
        dims = {d: n for d, n in ds.sizes.items() if d != "p0"}
        out = xr.Dataset._construct_direct(  # noqa: SLF001 - see the docstring
            variables, set(ds.coords), dims, dict(ds.attrs), indexes
        )
    except (AttributeError, TypeError):  # pragma: no cover - other xarray versions
        return ds.isel(p0=0)
    return out


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
            engine.solve(
                tau_eff[k], float(rs.p0[i]), *walls[i], rtol=rs.rtol, atol=rs.atol, method=rs.method
            )
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


def _labels(rs: ResolvedScene, reg: Registry) -> dict[str, Any]:
    """Plugin labels (name + distribution) used in error messages."""
    return {
        section: _checks.plugin_label(
            section, getattr(rs, section), reg, rs.plugin_names.get(section)
        )
        for section in ("spectrum", "coefficient", "boundary")
    }


def _coefficient_arrays(
    coef: Any, ctx: SceneContext, who: Any
) -> tuple[np.ndarray, np.ndarray, np.ndarray, bool]:
    """tau(zeta), f(zeta) and the per-load effective tau [Pa^2], each checked; and whether
    every load's effective tau is tau(zeta) (then returned as a read-only broadcast)."""
    nz, nl = ctx.zeta.size, ctx.p0.size
    with _checks.calling(who, "tau(zeta)"):
        tau_c = coef.tau(ctx, ctx.zeta)
    tau_c = _checks.check_array(
        tau_c, who, "tau(zeta)", (nz,), nonnegative=True, nondecreasing_axis=0, unit="Pa2"
    )
    with _checks.calling(who, "f(zeta)"):
        f_z = coef.f(ctx, ctx.zeta)
    f_z = _checks.check_array(f_z, who, "f(zeta)", (nz,), nonnegative=True, unit="Pa2")
    if _default_effective_tau(coef):  # the base class broadcasts tau(zeta): nothing to ask
        return tau_c, f_z, np.broadcast_to(tau_c, (nl, nz)), True
    with _checks.calling(who, "effective_tau(zeta)"):
        tau_eff = coef.effective_tau(ctx, ctx.zeta)
    shared = _equals_rows(tau_eff, tau_c, (nl, nz))
    if shared:  # every row is the checked tau(zeta): the same checks hold, nothing to repeat
        tau_eff = np.broadcast_to(tau_c, (nl, nz))
    else:
        tau_eff = _checks.check_array(
            tau_eff,
            who,
            "effective_tau(zeta)",
            (nl, nz),
            nonnegative=True,
            nondecreasing_axis=1,
            unit="Pa2",
        )
    return tau_c, f_z, tau_eff, shared


def _default_effective_tau(coef: Any) -> bool:
    """Whether ``coef``'s effective tau is tau(zeta) for every load: it inherits
    :meth:`Coefficient.effective_tau` or declares ``tau_per_load = False``."""
    from .plugins import Coefficient

    cls = type(coef)
    if getattr(cls, "effective_tau", None) is Coefficient.effective_tau:
        return True

    def owner(attr: str) -> type | None:
        return next((c for c in cls.__mro__ if attr in vars(c)), None)

    # the declaration counts only from the class whose effective_tau it describes (a subclass
    # overriding effective_tau is asked as usual)
    return getattr(coef, "tau_per_load", True) is False and owner("tau_per_load") is owner(
        "effective_tau"
    )


def _equals_rows(value: Any, row: np.ndarray, shape: tuple[int, int]) -> bool:
    """Whether ``value`` is a ``shape`` float array whose every row equals ``row`` exactly."""
    if not isinstance(value, np.ndarray) or value.shape != shape or value.dtype != float:
        return False
    return bool(np.array_equal(value, np.broadcast_to(row, shape)))


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
    tau_eff: np.ndarray | None,
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
    if tau_eff is not None:  # None: every load's effective tau is tau(zeta)
        data["effective_diffusion_time"] = (pz, tau_eff)
    if p_grid is not None:
        coords["p"] = ("p", p_grid)
        data["P"] = (("p0", "zeta", "p"), stack("P"))
    ds = _dataset(data, coords)
    for name, note in _balance_notes(results).items():  # appended to the schema's comment
        attrs = ds.variables[name].attrs
        attrs["comment"] = "; ".join(c for c in (attrs.get("comment"), note) if c)
    return ds


def _balance_notes(results: Any) -> dict[str, str]:
    """A note for the ``comment`` of the balances where the engine reports them as identities
    (zeros by construction of the one-wall closed form, not evaluated): the reader knows they
    check nothing there."""
    exact = np.asarray(getattr(results, "exact_balances", False), dtype=bool)
    if not exact.any():
        return {}
    # one text for any mix of loads (and of the points of a sweep): true wherever it is copied
    text = (
        "exactly 0, not evaluated, for the loads solved by the one-wall closed form (an "
        "identity there: non_contact_fraction = erfc = 1 - erf and load = p0 - wall * "
        "non_contact_fraction); evaluated for every other solve"
    )
    return {name: text for name in ("load_balance", "probability_balance")}


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
                indexes[name], cvars[name] = _index(PandasIndex, name, var)
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


_INDEXES: dict[tuple[str, bytes, tuple], tuple[Any, xr.Variable]] = {}


def _index(cls: Any, name: str, var: xr.Variable) -> tuple[Any, xr.Variable]:
    """The index of a dimension coordinate and its index variable, reused for equal values.

    Solves of one scene share their zeta / q_psd (and often p0) coordinates; the pandas index
    is immutable, so Datasets may share it (as ``isel`` and ``copy`` do). The variable is a
    fresh shallow copy carrying ``var``'s attrs.
    """
    arr = np.asarray(var.values)
    key = (name, arr.tobytes(), tuple(sorted((k, str(v)) for k, v in var.attrs.items())))
    hit = _INDEXES.get(key)
    if hit is None or hit[1].dtype != arr.dtype:
        index = cls.from_variables({name: var}, options={})
        hit = (index, index.create_variables({name: var})[name])
        if len(_INDEXES) > 64:
            _INDEXES.clear()
        _INDEXES[key] = hit
    out = hit[1].copy(deep=False)
    out.attrs = dict(var.attrs)
    return hit[0], out


def _persson_G(tau_c: np.ndarray, p0: np.ndarray) -> np.ndarray:
    """``G = tau / p0^2`` per (p0, zeta); ``inf`` at a zero load (adhesive boundaries)."""
    p2 = p0 * p0
    with np.errstate(divide="ignore", invalid="ignore"):
        G = tau_c[None, :] / p2[:, None]
    if np.all(p2 != 0):  # no 0/0 possible: G is already final
        return G
    return np.where(np.isnan(G), np.inf, G)


def _add(
    ds: xr.Dataset, values: Mapping[str, Any], specs: Mapping[str, VarSpec], who: object
) -> None:
    """Check a plugin's contribution against its VarSpecs (see :mod:`._checks`), then add it."""
    checked = _checks.check_contributions(ds, values, specs, who)
    if not checked:
        return
    for name, da in checked.items():
        da.attrs.update(_spec_attrs(specs[name]))
    if _insert_direct(ds, checked):
        return
    try:  # one Dataset update for all of the plugin's variables (one merge, not one each)
        ds.update(checked)
        return
    except ValueError:  # conflicting sizes of a plugin's own dimension: find which variable
        pass
    for name, da in checked.items():
        try:
            ds[name] = da
        except ValueError as exc:
            raise _checks.PluginFailure(
                f"{who}: variable {name!r}: {exc}", plugin=who, variable=name
            ) from None


def _insert_direct(ds: xr.Dataset, checked: Mapping[str, Any]) -> bool:
    """Insert checked, coordinate-free variables whose dims the Dataset already has.

    Such an insertion has nothing to align (:func:`._checks.checked_variable` has checked the
    dims and sizes against ``ds``): the variables go into the Dataset as they are, which is
    what ``ds.update`` ends with, without its merge and alignment of every variable. Returns
    False (nothing inserted) when any variable carries coordinates or a new dimension, or on an
    xarray without the internal mapping; :meth:`xarray.Dataset.update` then does the work.
    """
    variables = getattr(ds, "_variables", None)
    if not isinstance(variables, dict):  # pragma: no cover - other xarray versions
        return False
    sizes = dict(ds.sizes)
    for da in checked.values():
        if not isinstance(da, xr.Variable) and da.coords:  # a DataArray with coordinates
            return False
        if any(d not in sizes or sizes[d] != n for d, n in zip(da.dims, da.shape, strict=True)):
            return False
    for name, da in checked.items():
        variables[name] = getattr(da, "variable", da)  # DataArray -> its Variable
    return True


_SPEC_ATTRS: dict[int, tuple[VarSpec, dict[str, Any]]] = {}


def _spec_attrs(spec: VarSpec) -> dict[str, Any]:
    """``spec.attrs()`` (computed once per VarSpec object; a fresh copy each call)."""
    hit = _SPEC_ATTRS.get(id(spec))
    if hit is None or hit[0] is not spec:
        if len(_SPEC_ATTRS) > 4096:
            _SPEC_ATTRS.clear()
        hit = (spec, spec.attrs())
        _SPEC_ATTRS[id(spec)] = hit
    return dict(hit[1])


def _diagnostics_notes(ds: xr.Dataset) -> list[str]:
    """Add the P-resolution diagnostics; collect them and the regime warnings as notes."""
    from . import _diagnostics

    notes = _diagnostics.regime_warnings(ds)
    ds.attrs["regime_warnings"] = json.dumps(notes)
    unresolved = _diagnostics.pdf_resolution(ds)
    return notes + ([unresolved] if unresolved else [])


def _attributes(
    ds: xr.Dataset,
    rs: ResolvedScene,
    reg: Registry,
    results: Any,
    notes: list[str],
    core: Mapping[int, str] | None = None,
) -> None:
    core = core or {}
    status_of = ds["solver_status"].values  # the engine's, or the core output check's verdict
    success = np.asarray(results.success, dtype=bool) & (status_of == "success")
    bad = [
        (
            float(rs.p0[i]),
            str(status_of[i]),
            results[int(i)].message if not results[int(i)].success else core.get(int(i), ""),
        )
        for i in np.flatnonzero(~success)[:5]
    ]
    status = "success" if not bad else bad[0][1]
    message = (
        "all loads met the requested tolerance"
        if not bad
        else "; ".join(f"p0 = {p:g} Pa: {s}: {m}" for p, s, m in bad)
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
    coef = rs.coefficient
    tau_eff = np.asarray(coef.effective_tau(ctx, rs.zeta), float).reshape(rs.p0.size, -1)
    clock = DiffusionClock(lambda z: coef.tau(ctx, z), lambda z: coef.f(ctx, z), ctx.zeta_max)
    walls = [rs.boundary.walls(ctx, float(p0), clock) for p0 in rs.p0]
    return _pressure_grid(rs, walls, tau_eff)
