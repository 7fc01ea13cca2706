"""A sweep's analyses after the fact (:func:`analyse_sweep`): every point with its own values.

The sweep's archive carries its scene with the swept lists and their order (``xpersson_scene``,
``xpersson_sweep``): :func:`xpersson.sweep.plan.expand` gives the same points again, each with
its swept values. Every point's Dataset is cut from the sweep's (its own spectrum nodes only,
as it was solved) and analysed as one solved scene (:mod:`._point`), or, where the sweep's run
solves a block of points stacked, the block at once as that run analyses it (:mod:`._stacked`).
The points' outputs are stacked as the sweep stacks them (:func:`xpersson.sweep.blocks.stack`)
and a sweep dimension along which an output never changes is dropped, as the sweep drops it:
the numbers and the layout of the analysis run inside the sweep.
"""

from __future__ import annotations

import dataclasses
import json
from typing import Any

import numpy as np
import xarray as xr

from .. import plugins
from ..cache import solve_scope
from ..errors import ArchiveError
from ..pipeline import model_error, squeeze_p0
from ..plugins import fast_paths_on, get_registry
from ..plugins.stored import spectrum_of
from ..scene import Scene
from ..sweep.blocks import POINT_STATUS, blocks_of, stack
from ..sweep.combine import constant_along
from ..sweep.parts import finalize
from ..sweep.plan import SweepPlan, expand
from ._point import (
    analyse_point,
    archived_scene,
    as_written,
    point_scene,
    run_point,
    with_p0,
    without,
)
from ._stacked import add_block_outputs, analyse_block, stacked_blocks

__all__ = ["analyse_sweep", "is_sweep"]


def is_sweep(ds: xr.Dataset) -> bool:
    """Whether ``ds`` is a sweep's Dataset (its ``xpersson_sweep`` attribute)."""
    return "xpersson_sweep" in ds.attrs


def analyse_sweep(ds: xr.Dataset, name: str, params: dict[str, Any]) -> xr.Dataset:
    """:func:`xpersson.analyse` of a sweep's Dataset (see its docstring)."""
    plan, data = _plan(ds)
    if plan is None:  # one point: its scalar coordinates are the swept values
        point = _own_nodes(ds.drop_vars([n for n in ("point_status",) if n in ds.variables]))
        attrs = {k: v for k, v in ds.attrs.items() if k != "xpersson_sweep"}
        point.attrs = attrs | {"xpersson_scene": json.dumps(data)}
        out = analyse_point(point, name, params)
        if "point_status" in ds.variables:
            out = out.assign(point_status=ds.variables["point_status"])
        out.attrs = dict(ds.attrs)
        return out
    status = _status(ds, plan).ravel()
    if np.all(status == _FAILED):
        raise ArchiveError("every point of the sweep failed: there is no solve to analyse")
    scenes = []
    for index in plan.indices():
        data = plan.point_data(index)
        data["analyses"] = {name: dict(params)}
        scenes.append(data)
    written = _written(scenes, name)
    points: list[Any] = [None] * plan.size
    spectra: dict[bytes, Any] = {}  # one spectrum object where points share it, as the sweep
    for k, index in enumerate(plan.indices()):
        if status[k] != _FAILED:
            point = _point_dataset(ds, plan, index)
            points[k] = (point_scene(scenes[k], point, _shared(spectra, point)), point)
    results: list[xr.Dataset | None] = [None] * plan.size
    ok = status != _FAILED
    for members in stacked_blocks(plan, written if written else [None]):
        if all(ok[k] for k in members):
            _block(members, points, results)
    for k in np.flatnonzero(ok):
        if results[k] is None:  # point by point, as the sweep's plain path
            rs, point = points[k]
            with plugins.time_limit(rs.plugin_time_limit), solve_scope():
                results[k] = _new(run_point(rs, point), point, rs)
    return _merged(ds, plan, results, status.reshape(plan.shape), written)


def _written(scenes: list[dict[str, Any]], name: str) -> list[Any]:
    """Every point's scene resolved as written (its own spectrum section): what decides the
    sweep's stacked blocks and the model-error bands; ``[]`` where neither needs it. For the
    bands alone, points that differ only in the material share one (E and nu are not among
    their features)."""
    cls = get_registry().load("analyses", name)
    if fast_paths_on() and cls.fast_paths.stacked_params is not None:
        return [as_written(data) for data in scenes]
    if not set(cls.provides) & set(model_error.covered_names(model_error.band_table())):
        return []
    resolved: dict[str, Any] = {}
    out = []
    for data in scenes:
        key = json.dumps({k: v for k, v in data.items() if k != "material"}, sort_keys=True)
        if key not in resolved:
            resolved[key] = as_written(data)
        out.append(resolved[key])
    return out


def _shared(spectra: dict[bytes, Any], point: xr.Dataset) -> Any:
    """``point``'s stored spectrum, the same object for every point with the same one."""
    psd = spectrum_of(point)
    key = b"".join(np.asarray(a, dtype=float).tobytes() for a in (psd.nodes(), psd.C(psd.nodes())))
    return spectra.setdefault(key, psd)


def _new(got: xr.Dataset, point: xr.Dataset, rs: Any) -> xr.Dataset:
    """The analysis's variables of a point's result (and those it replaced)."""
    provided = {v for _, a in rs.analyses for v in type(a).provides}
    return got[[v for v in got.data_vars if v not in point.data_vars or v in provided]]


def _block(members: list[int], points: list[Any], results: list[Any]) -> None:
    """The points ``members`` analysed as the sweep's stacked run analyses its block."""
    rss = [points[k][0] for k in members]
    provided = [v for _, a in rss[0].analyses for v in type(a).provides]
    dsets = [
        without(with_p0(points[k][1], rs), provided) for k, rs in zip(members, rss, strict=True)
    ]
    with plugins.time_limit(rss[0].plugin_time_limit), solve_scope():
        outs = analyse_block(rss, dsets)
    for k, rs, out, ds in zip(members, rss, outs, dsets, strict=True):
        add_block_outputs(rs, ds, out)
        results[k] = _new(ds, points[k][1], rs)


_FAILED = POINT_STATUS["failed"]


def _plan(ds: xr.Dataset) -> tuple[SweepPlan | None, dict[str, Any]]:
    """The sweep's plan from its archived scene, checked against the Dataset's dimensions and
    coordinates. A subset of the sweep (``sel``/``isel`` along its dimensions) is the sweep of
    the values it holds: each swept list becomes the Dataset's coordinate (a value selected
    alone, its dimension dropped, a scalar of the scene; ``None`` and the point's scene where
    every one was)."""
    meta = json.loads(ds.attrs["xpersson_sweep"])
    data = archived_scene(ds)
    plan = expand(Scene(data, source=None))
    if plan is None or list(plan.dims) != list(meta.get("dims", [])):
        raise ArchiveError(
            f"the Dataset's sweep dimensions {meta.get('dims')} are not those of its scene "
            "(xpersson_scene): analyse needs the archive of a sweep written by xpersson"
        )
    subset = False
    for param in plan.params:
        have = ds.variables.get(param.name)
        if have is None or have.ndim > 1:
            raise ArchiveError(
                f"the Dataset has no sweep coordinate {param.name!r} ({param.path}), which "
                "gives each point its swept value: keep the sweep's coordinates"
            )
        values = np.atleast_1d(np.asarray(have.values, dtype=float))
        if have.ndim == 0 or not np.array_equal(values, param.values):
            subset = True
            param = dataclasses.replace(param, values=values)
            listed = [param.scene_value(i) for i in range(values.size)]
            _set(data, param.path, listed if have.ndim else listed[0])
    if subset:
        kept = [p.path for g in plan.groups if g[0].name in ds.dims for p in g]
        data["sweep"] = {**data.get("sweep", {}), "order": kept}
        if not kept:  # one point of the sweep, every swept value selected alone
            data.pop("sweep")
            return None, data
        plan = expand(Scene(data, source=None))
    return plan, data


def _set(data: dict[str, Any], path: str, value: Any) -> None:
    """Set the dotted ``path`` of the scene ``data`` (its tables copied on the way)."""
    *tables, key = path.split(".")
    node = data
    for part in tables:
        node[part] = dict(node.get(part) or {})
        node = node[part]
    node[key] = value


def _status(ds: xr.Dataset, plan: SweepPlan) -> np.ndarray:
    """Every point's status (``point_status`` over the sweep grid; 0 where not stored)."""
    var = ds.variables.get("point_status")
    if var is None:
        return np.zeros(plan.shape, dtype=np.int8)
    full = var.set_dims(dict(zip(plan.dims, plan.shape, strict=True)))
    return np.asarray(full.transpose(*plan.dims).values)


def _point_dataset(ds: xr.Dataset, plan: SweepPlan, index: tuple[int, ...]) -> xr.Dataset:
    """Point ``index``'s Dataset as its solve gave it: the sweep dimensions selected (their
    coordinates dropped), ``point_status`` dropped, and the spectrum cut to its own nodes."""
    at = {d: i for d, i in zip(plan.dims, index, strict=True) if d in ds.dims}
    point = ds.isel(at, drop=True)
    drop = [n for n in (*plan.coords(), "point_status") if n in point.variables]
    return _own_nodes(point.drop_vars(drop))


def _own_nodes(point: xr.Dataset) -> xr.Dataset:
    """One point's Dataset cut to its own spectrum nodes (a sweep stores the union of its
    points' nodes, ``psd_C`` NaN where a node is another point's)."""
    if "q_psd" in point.dims:
        own = np.isfinite(np.asarray(point.variables["psd_C"].values, dtype=float))
        if not own.all():
            point = point.isel(q_psd=np.flatnonzero(own))
    return point


def _merged(
    ds: xr.Dataset,
    plan: SweepPlan,
    results: list[xr.Dataset | None],
    status: np.ndarray,
    written: list[Any],
) -> xr.Dataset:
    """``ds`` with the points' outputs stacked over the sweep grid as the sweep stacks them
    (:func:`~xpersson.sweep.blocks.stack`, one load squeezed), every output without the sweep
    dimensions along which it never changes (:func:`_constant`,
    :func:`~xpersson.sweep.parts.finalize`)."""
    (block,) = blocks_of(plan, plan.size)
    stacked = stack(results, block, status)
    if "p0" not in ds.dims:  # single-load points: p0 a scalar coordinate, as in the sweep
        stacked = squeeze_p0(stacked)
    if model_error.covered(stacked):  # the bands, as the sweep attaches them to a block
        if written and all(p is not None for p in written):
            model_error.attach(stacked, written, plan.dims)
    stacked = finalize(stacked, _constant(stacked, plan, status), {})
    new = [n for n in stacked.data_vars if n != "point_status"]
    out = ds.drop_vars([n for n in new if n in ds.variables])
    coords = {c: stacked.variables[c] for c in stacked.coords if c not in out.variables}
    return out.assign_coords(coords).assign({n: stacked.variables[n] for n in new})


def _constant(ds: xr.Dataset, plan: SweepPlan, status: np.ndarray) -> dict[str, list[str]]:
    """For each stacked variable, the sweep dimensions (of at least two values) along which it
    never changes at the solved points, bit for bit: the sweep's rule (its per-point
    fingerprints, :mod:`xpersson.sweep.combine`) on the values themselves."""
    n = len(plan.dims)
    out: dict[str, list[str]] = {}
    for name, var in ds.data_vars.items():
        if name == "point_status" or tuple(var.dims[:n]) != plan.dims:
            continue
        rows = np.asarray(var.values).reshape(plan.size, -1)
        grid = np.empty(plan.size, dtype=object)
        for k, row in enumerate(rows):  # a point's bytes (failed points: None)
            if status.flat[k] != _FAILED:
                grid[k] = repr(row.tolist()) if row.dtype.kind == "O" else row.tobytes()
        dims = constant_along(grid.reshape(plan.shape), plan)
        if dims:
            out[str(name)] = dims
    return out
