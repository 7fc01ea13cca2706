"""Stacked points: a block of sweep points solved by one run (issue 25).

Points whose plugins all declare a stacked path (``fast_paths.stacked_params``,
:class:`xpersson.plugins.FastPaths`) and that differ only in those parameters (same classes,
material, loads count, output grid, spectrum nodes, accuracy) are solved together: the
coefficient is asked once for the block (:meth:`~xpersson.plugins.Coefficient.tau_stacked`),
the engine once for every (point, load) with each load's own ``tau(zeta)`` row, the
boundary's walls per point, the coefficient's
:meth:`~xpersson.plugins.Coefficient.interpret_stacked` and each analysis's
:meth:`~xpersson.plugins.Analysis.compute_stacked` once, on one Dataset whose variables carry a
leading ``point`` dimension. :func:`run_stacked` returns that Dataset's variables as
``name -> (dims, array)``; the sweep (:mod:`xpersson.sweep.fast`) reads its rows per point.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from typing import Any

import numpy as np
import xarray as xr

from .. import checks, plugins, provenance
from ..cache import solve_scope
from ..physics.psd import segment_exponents, stacked_C
from ..scene import ResolvedScene
from ._draft import Draft
from ._insert import direct_dataset
from .assemble import add_outputs, assemble, attributes, diagnostics_notes
from .diagnostics import validity_flags
from .frontend import diffusion_clock, replaced, scene_context, spectrum_kinks
from .solve_at import make_solve_at
from .stages import coefficient_arrays, load_walls, shared_tau, validate

__all__ = ["POINT", "StackedRun", "stack_reason", "run_stacked", "rows_of"]

#: The leading dimension of a stacked block's variables.
POINT = "point"


def _roles(rs: ResolvedScene) -> list[tuple[str, Any]]:
    return [
        ("spectrum", rs.spectrum),
        ("coefficient", rs.coefficient),
        ("boundary", rs.boundary),
        *((f"analyses.{n}", a) for n, a in rs.analyses),
    ]


def _equal(a: Any, b: Any) -> bool:
    try:
        return bool(a == b)
    except ValueError:  # arrays
        return bool(np.array_equal(np.asarray(a), np.asarray(b)))


def _differs(rs: ResolvedScene, rs0: ResolvedScene) -> str | None:
    """What makes ``rs`` differ from ``rs0`` beyond declared plugin parameters (or None)."""
    if (rs.E, rs.nu, rs.rtol, rs.atol, rs.method) != (
        rs0.E,
        rs0.nu,
        rs0.rtol,
        rs0.atol,
        rs0.method,
    ):
        return "material or accuracy"
    if rs.p0.shape != rs0.p0.shape or not np.array_equal(rs.zeta, rs0.zeta):
        return "loads count or output grid"
    if rs.solver_options != rs0.solver_options or rs.plugin_time_limit != rs0.plugin_time_limit:
        return "solver options"
    if rs0.analyses and not np.array_equal(rs.p0, rs0.p0):
        return "loads (with analyses)"
    if rs.psd is not rs0.psd and not np.array_equal(rs.psd.nodes(), rs0.psd.nodes()):
        return "spectrum nodes"
    first, other = _roles(rs0), _roles(rs)
    if [r for r, _ in first] != [r for r, _ in other]:
        return "analyses"
    for (role, a), (_, b) in zip(first, other, strict=True):
        if type(a) is not type(b):
            return f"{role}: plugin"
        if a is b:
            continue
        stacks = type(a).fast_paths.stacked_params or frozenset()
        pa, pb = a.params, b.params  # (one mapping view each, not one per parameter)
        if any(k not in stacks and not _equal(v, pb[k]) for k, v in pa.items()):
            return f"{role}: a parameter not declared in fast_paths.stacked_params"
    return None


#: Engine methods whose result for a load does not depend on the other loads of its batch:
#: the closed forms (``auto`` takes them wherever the walls allow; ``exact``) and the ``sine``
#: series. ``cn`` plans one time schedule for the loads that share their walls, so a stacked
#: run of points with a shared wall (a fixed one) solves each point on another schedule than
#: its own run: within the tolerance, beyond round-off (``benchmarks/fuzz.py --methods 1
#: --sweeps 1 --seed 197``: 3.5e-6 of the area at rtol 9e-4).
LOAD_WISE_METHODS = ("auto", "exact", "sine")


def stack_reason(points: Sequence[ResolvedScene]) -> str | None:
    """Why a block of resolved points cannot be solved stacked (``None``: it can)."""
    rs0 = points[0]
    if len(points) < 2:
        return "one point"
    if rs0.pressure_pdf or rs0.p0.size == 0:
        return "pressure grid"
    if rs0.method not in LOAD_WISE_METHODS:
        return f"method {rs0.method!r} (its loads' results depend on the batch)"
    if not type(rs0.boundary).fast_paths.shared_walls:
        return "walls per load"
    for role, plugin in _roles(rs0):
        if type(plugin).fast_paths.stacked_params is None:
            return f"{role}: {type(plugin).__name__} does not declare a stacked path"
    for rs in points[1:]:
        why = _differs(rs, rs0)
        if why:
            return why
    return None


class StackedRun(dict[str, tuple[tuple[str, ...], Any]]):
    """``name -> (dims, array)`` of a stacked run, which also keeps what the first point's own
    Dataset is assembled from (:meth:`point_dataset`)."""

    def __init__(self, out: dict[str, Any], parts: dict[str, Any]) -> None:
        super().__init__(out)
        self._parts = parts

    def point_dataset(self) -> xr.Dataset | None:
        """The first point's Dataset as :func:`~xpersson.pipeline.run.run` (``squeeze=False``)
        assembles it, from this run's values (no solving): its variables, their attributes and
        the global attributes; ``None`` unless its status is ``"success"`` or for a finite body
        (its nominal pressure is solved on the plain path only). The sweep takes a block's
        coordinates and attributes from it instead of solving its first point again."""
        p = self._parts
        rs, results = p["rs"], p["results"]
        if rs.geometry is not None:
            return None
        labels = rs.labels
        ds = assemble(rs, p["ctx"], results, p["tau"], p["f"], p["eff"], None)
        core = checks.check_core(ds)
        coef = rs.coefficient
        add_outputs(ds, p["coefficient"], type(coef).outputs, labels["coefficient"])
        add_outputs(ds, p["boundary"], type(rs.boundary).outputs, labels["boundary"])
        for (name, analysis), got in zip(rs.analyses, p["analyses"], strict=True):
            add_outputs(ds, got, type(analysis).outputs, labels[f"analyses.{name}"])
        notes = diagnostics_notes(ds)
        # warns as the point's own run does: the sweep silences the points' warnings
        attributes(ds, rs, lambda: provenance.global_attributes(rs), results, notes, core)
        return ds.dataset() if ds.attrs.get("status") == "success" else None


def run_stacked(points: Sequence[ResolvedScene]) -> StackedRun | None:
    """Solve a block of points (see :func:`stack_reason`) as one run.

    Returns ``name -> (dims, array)`` of every variable of the points' Datasets (a leading
    ``point`` dimension where it differs between points), or ``None`` where a load did not
    meet its tolerance (the caller then solves point by point, recording each status).
    """
    with plugins.time_limit(points[0].plugin_time_limit), solve_scope():
        return _run(points)


def _coefficient(
    points: Sequence[ResolvedScene], ctxs: list[Any], declared: bool
) -> tuple[Any, Any, Any, Any]:
    """tau (K, nz), f (K, nz), the per-load effective tau (K, nl, nz) and the first point's as
    its own run has it: both None where every coefficient declares a shared tau
    (:func:`~.stages.declares_shared_tau`), else arrays, also where they equal tau."""
    rs0 = points[0]
    who = rs0.labels["coefficient"]
    coefs = [rs.coefficient for rs in points]
    K, nz = len(points), rs0.zeta.size
    if declared:  # every point's coefficient declares a shared tau (shared_tau)
        with checks.calling(who, "tau(zeta)"):
            tau, f = rs0.coefficient.tau_stacked(ctxs, coefs, rs0.zeta)
        kw: dict[str, Any] = dict(nonnegative=True, unit="Pa2")
        tau = checks.check_array(tau, who, "tau(zeta)", (K, nz), nondecreasing_axis=1, **kw)
        f = checks.check_array(f, who, "f(zeta)", (K, nz), **kw)
        return tau, f, None, None
    got = [coefficient_arrays(c, x, who) for c, x in zip(coefs, ctxs, strict=True)]
    tau = np.stack([g[0] for g in got])
    f = np.stack([g[1] for g in got])
    # not declared shared: the variable at every point, also where it equals tau (run.py's)
    return tau, f, np.stack([g[2] for g in got]), np.array(got[0][2])


def _run(points: Sequence[ResolvedScene]) -> StackedRun | None:
    from .. import engine

    rs0 = points[0]
    who = rs0.labels
    labels = [who[f"analyses.{name}"] for name, _ in rs0.analyses]
    ctxs = [scene_context(rs) for rs in points]
    for rs, ctx in zip(points, ctxs, strict=True):
        if rs is rs0 or not _validated_as_first(rs, ctx, rs0, ctxs[0]):
            validate(rs, ctx, who["boundary"], labels)
    declared = all(shared_tau(rs.coefficient) for rs in points)
    tau, f, eff, eff0 = _coefficient(points, ctxs, declared)
    K, nl, nz = len(points), rs0.p0.size, rs0.zeta.size
    walls, clocks = [], []  # each point's walls on its own clock
    for rs, ctx in zip(points, ctxs, strict=True):
        coef = rs.coefficient
        clocks.append(diffusion_clock(ctx, coef, kinks=spectrum_kinks(rs.psd)))
        walls.append(load_walls(rs, ctx, clocks[-1], who["boundary"])[0])
    shared = all(w == walls[0] for w in walls)
    loads = np.concatenate([rs.p0 for rs in points])
    rows = np.repeat(tau, nl, axis=0) if eff is None else eff.reshape(K * nl, nz)
    results = engine.solve_batch(
        rows,
        loads,
        walls[0] if shared else [w for w in walls for _ in range(nl)],
        rtol=rs0.rtol,
        atol=rs0.atol,
        method=rs0.method,
        options=rs0.solver_options or None,
    )
    if not np.all(results.success):  # (success: status "success", per load; no loop over them)
        return None
    flat = dataclasses.replace(rs0, p0=loads, p0_scalar=False)
    p2 = (loads * loads).reshape(K, nl)
    with np.errstate(divide="ignore", invalid="ignore"):
        G = tau[:, None, :] / p2[:, :, None]  # each point's own tau (the flat run has tau[0])
    if not np.all(p2 != 0):
        G = np.where(np.isnan(G), np.inf, G)
    ctx0 = dataclasses.replace(ctxs[0], p0=loads)
    ds = assemble(flat, ctx0, results, tau[0], f[0], None, None, G.reshape(K * nl, nz))
    if checks.check_core(ds):  # a load outside the core ranges: its status is recorded per point
        return None
    out = _unflatten(ds, K, nl)  # G among them: (point, p0, zeta)
    out["diffusion_time"] = ((POINT, "zeta"), tau)
    out["diffusion_coefficient"] = ((POINT, "zeta"), f)
    if eff is not None:
        out["effective_diffusion_time"] = ((POINT, "p0", "zeta"), eff)
    _spectra(points, ds, out)
    coef_out = rs0.coefficient.interpret_stacked(ctxs, [rs.coefficient for rs in points])
    for name, (dims, arr) in coef_out.items():
        out[name] = ((POINT, *dims), np.asarray(arr))
    first = _Loads(results, 0, nl)  # the first point's Dataset (StackedRun.point_dataset)
    parts = {"rs": rs0, "ctx": ctxs[0], "results": first, "tau": tau[0], "f": f[0], "eff": eff0}
    parts["coefficient"] = {n: (dims, np.asarray(arr)[0]) for n, (dims, arr) in coef_out.items()}
    for k, (rs, ctx, clock) in enumerate(zip(points, ctxs, clocks, strict=True)):
        at_clock = replaced(ctx, clock=clock)  # interpret reads its point's clock
        extra = rs.boundary.interpret(at_clock, _Loads(results, k * nl, nl))
        if k == 0:
            parts["boundary"] = extra
        for name, value in (extra or {}).items():
            out.setdefault(name, [])  # type: ignore[arg-type]
            out[name].append(value)  # type: ignore[union-attr]
    for name, value in list(out.items()):
        if isinstance(value, list):  # the boundary's per-point values
            da = [_as_dataarray(v) for v in value]
            out[name] = ((POINT, *da[0].dims), np.stack([d.values for d in da]))
    parts["analyses"] = (
        _analyses(points, ctxs, (walls, clocks, declared), out, ds) if rs0.analyses else []
    )
    out["theory_validity"] = ((POINT, "p0"), _validity(out, K))
    return StackedRun(out, parts)


def _validated_as_first(rs: ResolvedScene, ctx: Any, rs0: ResolvedScene, ctx0: Any) -> bool:
    """Whether point ``rs`` asks its boundary's and analyses' ``validate(ctx)`` exactly what
    the first point asked: the same plugin objects (a sweep over the coefficient's
    parameters shares them) with the same context (spectrum object, material, loads, grid,
    accuracy); its validation is then the first point's."""
    if rs.boundary is not rs0.boundary or any(
        a is not b for (_, a), (_, b) in zip(rs.analyses, rs0.analyses, strict=True)
    ):
        return False
    same = (ctx.E, ctx.nu, ctx.E_star, ctx.rtol, ctx.atol, ctx.method) == (
        ctx0.E,
        ctx0.nu,
        ctx0.E_star,
        ctx0.rtol,
        ctx0.atol,
        ctx0.method,
    )
    return bool(
        same
        and ctx.psd is ctx0.psd
        and np.array_equal(ctx.p0, ctx0.p0)
        and np.array_equal(ctx.zeta, ctx0.zeta)
    )


def _validity(out: dict[str, Any], K: int) -> np.ndarray:
    """``theory_validity`` (K, n_load) of the block, as
    :func:`~xpersson.pipeline.diagnostics.theory_validity` gives each point."""
    p0 = rows_of(out, "p0", ("p0",), K)
    area = rows_of(out, "area_fraction", ("p0", "zeta"), K)[..., -1]
    if "non_contact_fraction" in out:
        non = rows_of(out, "non_contact_fraction", ("p0", "zeta"), K)[..., -1]
    else:
        non = 1.0 - area
    slope = rows_of(out, "rms_slope", (), K)
    e_star = float(np.asarray(out["E_star"][1]))
    return validity_flags(p0, e_star, slope, area, non)


class _Loads(Sequence[Any]):
    """Point k's engine results: a view of the block's batch (each built on access only)."""

    def __init__(self, results: Any, start: int, n: int) -> None:
        self._results, self._start, self._n = results, start, n

    def __len__(self) -> int:
        return self._n

    def __getitem__(self, i: Any) -> Any:
        if isinstance(i, slice):
            return [self[j] for j in range(*i.indices(self._n))]
        i = int(i) + (self._n if int(i) < 0 else 0)
        if not 0 <= i < self._n:
            raise IndexError(i)
        return self._results[self._start + i]

    def __getattr__(self, name: str) -> Any:  # the stacked arrays of the point's loads
        value = getattr(self._results, name)
        if isinstance(value, np.ndarray) and value.ndim and value.shape[0] == len(self._results):
            return value[self._start : self._start + self._n]
        if isinstance(value, list) and len(value) == len(self._results):
            return value[self._start : self._start + self._n]
        return value


def _spectra(points: Sequence[ResolvedScene], ds: Draft, out: dict[str, Any]) -> None:
    """The spectrum's variables per point (one spectrum may serve every point)."""
    psds = [rs.psd for rs in points]
    if all(p is psds[0] for p in psds):
        return
    q_nodes = np.asarray(ds.variables["q_psd"].values, float)
    C = stacked_C(psds, q_nodes)  # None: spectra of other kinds, asked each
    if C is None:
        C = np.stack([np.asarray(p.C(q_nodes), float) for p in psds])
    out["psd_C"] = ((POINT, "q_psd"), C)
    out["psd_exponent"] = ((POINT, "q_psd"), np.stack([segment_exponents(p) for p in psds]))
    out["h_rms"] = ((POINT,), np.array([float(p.h_rms()) for p in psds]))
    out["rms_slope"] = ((POINT,), np.array([float(p.rms_slope()) for p in psds]))


def _unflatten(ds: Draft, K: int, nl: int) -> dict[str, tuple[tuple[str, ...], Any]]:
    """The variables of the flat (K * nl loads) Dataset, the loads split as (point, p0)."""
    out = {}
    for name, var in ds.variables.items():
        arr = np.asarray(var.values)
        if "p0" not in var.dims:
            out[name] = (var.dims, arr)
            continue
        axis = var.dims.index("p0")
        arr = np.moveaxis(arr, axis, 0).reshape((K, nl, *arr.shape[:axis], *arr.shape[axis + 1 :]))
        out[name] = ((POINT, *var.dims), np.moveaxis(arr, 1, axis + 1))
    return out


def _as_dataarray(value: Any) -> xr.DataArray:
    return value if isinstance(value, xr.DataArray) else xr.DataArray(value[1], dims=value[0])


def _analyses(
    points: Sequence[ResolvedScene],
    ctxs: list[Any],
    solved: tuple[list[Any], list[Any], bool],
    out: dict[str, Any],
    flat: Draft,
) -> list[dict[str, Any]]:
    """Each analysis once for the block, on the stacked Dataset (loads shared by every point);
    returns each analysis's outputs of the first point. ``solved``: each point's walls and
    clock, and whether every coefficient declares a shared tau (:class:`_PointContexts`)."""
    rs0 = points[0]
    fv = flat.variables
    coords = {n: xr.Variable(fv[n].dims, fv[n].values, dict(fv[n].attrs)) for n in ("zeta", "q")}
    coords["q_psd"] = xr.Variable(fv["q_psd"].dims, fv["q_psd"].values, dict(fv["q_psd"].attrs))
    coords["p0"] = xr.Variable(("p0",), rs0.p0, dict(fv["p0"].attrs))
    data = {
        n: xr.Variable(dims, arr, dict(fv[n].attrs) if n in fv else {})
        for n, (dims, arr) in out.items()
        if n not in coords
    }
    sds = direct_dataset(data, coords)
    if sds is None:  # pragma: no cover - other xarray versions
        sds = xr.Dataset(data, coords=coords)
    ctx_of = _PointContexts(points, ctxs, *solved)
    last = len(rs0.analyses) - 1
    firsts = []
    for i, (name, analysis) in enumerate(rs0.analyses):
        label = rs0.labels[f"analyses.{name}"]
        with checks.calling(label, "compute_stacked()"):
            got = analysis.compute_stacked(ctx_of, sds)
        missing = [v for v in type(analysis).provides if v not in (got or {})]
        if missing:
            raise checks.PluginFailure(f"{label} did not provide {missing}", plugin=label)
        firsts.append({})
        for vname, value in got.items():
            dims, arr = out[vname] = _point_first(value)
            stacked = POINT in dims
            firsts[-1][vname] = (dims[1:], arr[0]) if stacked else (dims, arr)
            if i < last:  # the next analyses may read it
                sds[vname] = xr.Variable(dims, arr)
    return firsts


def _point_first(value: Any) -> tuple[tuple[Any, ...], np.ndarray]:
    """``(dims, values)`` of an analysis's output (a DataArray or a ``(dims, array)`` pair)
    with the ``point`` dimension first where it has one."""
    if isinstance(value, xr.DataArray):
        da = value.transpose(POINT, ...) if POINT in value.dims else value
        return da.dims, np.asarray(da.values)
    dims, arr = tuple(value[0]), np.asarray(value[1])
    if POINT in dims and dims[0] != POINT:
        k = dims.index(POINT)
        dims, arr = (POINT, *dims[:k], *dims[k + 1 :]), np.moveaxis(arr, k, 0)
    return dims, arr


class _PointContexts:
    """``ctx_of(k)``: point k's analysis context (with its ``solve_at``), built on first use;
    :meth:`solve_rows` solves (point, load) rows of given ``tau`` in one engine call."""

    def __init__(
        self,
        points: Sequence[ResolvedScene],
        ctxs: list[Any],
        walls: list[Any],
        clocks: list[Any],
        declared: bool,
    ) -> None:
        self._points, self._ctxs, self._walls, self._clocks = points, ctxs, walls, clocks
        self._declared = declared  # every point's coefficient declares a shared tau
        self._built: list[Any] = [None] * len(points)  # each point's context, once made
        self._light: list[Any] = [None] * len(points)  # the same without solve_at

    def __call__(self, k: int) -> Any:
        if self._built[k] is None:
            rs, ctx = self._points[k], self._ctxs[k]
            self._built[k] = dataclasses.replace(
                ctx,
                coefficient=rs.coefficient,
                boundary=rs.boundary,
                solve_at=make_solve_at(rs, ctx, [self._walls[k]] * rs.p0.size, self._clocks[k]),
            )
        return self._built[k]

    def light(self, k: int) -> Any:
        """Point k's context with its coefficient and boundary but no ``solve_at`` (cheaper
        than ``self(k)`` where only the spectrum, material and plugins are read)."""
        if self._built[k] is not None:
            return self._built[k]
        if self._light[k] is None:
            rs = self._points[k]
            self._light[k] = dataclasses.replace(
                self._ctxs[k], coefficient=rs.coefficient, boundary=rs.boundary
            )
        return self._light[k]

    def solve_rows(self, point: np.ndarray, load: np.ndarray, tau: np.ndarray) -> Any:
        """``A/A0`` (n_row, n_tau) of load ``load[i]`` of point ``point[i]`` at the diffusion
        times ``tau[i]`` [Pa^2] (each row strictly increasing): what point k's
        ``solve_at(zeta, loads, tau)`` gives each row, in one engine call. ``None`` where a
        coefficient's effective tau differs per load (``solve_at`` then computes it)."""
        from .. import engine

        if not self._declared:
            pts = [self._points[int(k)] for k in np.unique(point)]
            if not all(shared_tau(rs.coefficient) for rs in pts):
                return None
        rs0 = self._points[0]
        p0 = rs0.p0[np.asarray(load, dtype=np.intp)]  # a block with analyses: the same loads
        first = self._walls[int(point[0])]
        shared = all(self._walls[int(k)] is first for k in np.unique(point))
        res = engine.solve_batch(
            np.asarray(tau, float),
            p0,
            first if shared else [self._walls[int(k)] for k in point],
            rtol=rs0.rtol,
            atol=rs0.atol,
            method=rs0.method,
            options=rs0.solver_options or None,
        )
        return np.asarray(res.area, float).reshape(len(p0), -1)


def rows_of(
    stacked: dict[str, tuple[tuple[str, ...], Any]], name: str, dims: tuple[str, ...], K: int
) -> np.ndarray:
    """Point ``k``'s values of ``name`` in ``dims`` order, stacked: ``(K, *shape)``."""
    sdims, arr = stacked[name]
    arr = np.asarray(arr)
    if POINT not in sdims:
        order = [sdims.index(d) for d in dims]
        arr = np.transpose(arr, order) if order != list(range(len(order))) else arr
        return np.broadcast_to(arr, (K, *arr.shape))
    order = [0] + [sdims.index(d) for d in dims]
    return np.transpose(arr, order) if order != list(range(len(order))) else arr


#: :func:`_analyses` by a public name: ``xpersson.analyse`` runs the analyses of a stored sweep's
#: stacked blocks as this run runs them (:mod:`xpersson.reanalysis._stacked`).
block_analyses = _analyses
