"""One solved scene's analyses after the fact (:func:`analyse_point`; the package's
docstring says what the archive carries and what the numbers equal)."""

from __future__ import annotations

import dataclasses
import json
import warnings
from typing import Any

import numpy as np
import xarray as xr

from .. import plugins
from ..cache import solve_scope
from ..checks import CORE_DIMS
from ..errors import ArchiveError, XperssonWarning
from ..pipeline import model_error, scene_context, squeeze_p0
from ..pipeline.assemble import add_analyses
from ..pipeline.frontend import diffusion_clock, spectrum_kinks
from ..pipeline.solve_at import make_solve_at
from ..pipeline.stages import coefficient_arrays, load_walls, validate
from ..plugins.stored import contact_modulus, spectrum_of
from ..scene import ResolvedScene, Scene, SceneError
from ..schema import CORE_VARIABLES

__all__ = [
    "analyse_point",
    "analysed",
    "archived_scene",
    "as_written",
    "attach_model_error",
    "point_scene",
    "run_point",
    "with_p0",
    "without",
]


def analyse_point(ds: xr.Dataset, name: str, params: dict[str, Any]) -> xr.Dataset:
    """:func:`xpersson.analyse` of one solved scene (not a sweep): see its docstring."""
    spectrum_of(ds)  # what is missing is named before any work
    contact_modulus(ds)
    data = archived_scene(ds)
    data["analyses"] = {name: dict(params)}
    rs = point_scene(data, ds)
    with plugins.time_limit(rs.plugin_time_limit), solve_scope():
        out = run_point(rs, ds)
    out = squeeze_p0(out) if "p0" not in ds.dims else out
    attach_model_error(out, ds, data)
    return out


def attach_model_error(out: xr.Dataset, ds: xr.Dataset, data: dict[str, Any]) -> None:
    """The model-error bands of the outputs ``out`` adds to ``ds`` (in place), from the
    features of the scene ``data`` as written, as :func:`xpersson.solve` attaches them."""
    new = [n for n in out.data_vars if n not in ds.data_vars]
    if model_error.covered(out[new]):
        written = as_written(data)
        if written is not None:
            model_error.attach(out, written)


def as_written(data: dict[str, Any]) -> ResolvedScene | None:
    """The scene ``data`` resolved with its own spectrum section (the spectrum model and its
    parameters are features of the model-error bands, :mod:`xpersson.pipeline.model_error`);
    ``None``, with a warning, where it no longer resolves (a spectrum file moved)."""
    try:
        return Scene({k: v for k, v in data.items() if k != "sweep"}, source=None).resolve()
    except (SceneError, OSError) as exc:
        warnings.warn(
            f"the archive's scene no longer resolves with its own spectrum ({exc}): the "
            "model-error variables (X_exact_low, X_exact_high, X_model_error_status) of the "
            "analysis's outputs are not added",
            XperssonWarning,
            stacklevel=4,
        )
        return None


def point_scene(data: dict[str, Any], ds: xr.Dataset, psd: Any = None) -> ResolvedScene:
    """The resolved scene ``data`` of one solved point ``ds`` with the Dataset's spectrum: the
    scene's spectrum section becomes the Dataset's table (no file read, no spectrum plugin)
    and the resolved spectrum the Dataset's own segments, bit for bit. A Dataset of some of
    the scene's loads (``sel``/``isel`` along ``p0``) is analysed as the scene of those loads;
    its magnifications must be the scene's (checked). ``psd``: ``ds``'s spectrum rebuilt
    already (a sweep's points share one object where their spectra are equal)."""
    psd = spectrum_of(ds) if psd is None else psd
    q = psd.nodes()
    data = {k: v for k, v in data.items() if k != "sweep"}
    data["spectrum"] = {
        "model": "tabulated",
        "q": _quantities(q, "1/m"),
        "C": _quantities(psd.C(q), "m**4"),
    }
    rs = Scene(data, source=None).resolve()
    p0 = np.asarray(ds["p0"].values, dtype=float)
    if not np.array_equal(rs.p0, np.atleast_1d(p0)) and rs.geometry is None:
        loads = _quantities(p0, "Pa")  # the subset's loads (each solved as in the batch)
        data["load"] = {**data.get("load", {}), "p0": loads if p0.ndim else loads[0]}
        rs = Scene(data, source=None).resolve()
    rs = dataclasses.replace(rs, psd=psd)  # the solve's own segments, bit for bit
    _check_grid(rs, ds)
    return rs


def archived_scene(ds: xr.Dataset, *, body: bool = False) -> dict[str, Any]:
    """The archive's resolved scene (its ``xpersson_scene`` attribute), checked (a finite
    body's refused unless ``body``)."""
    text = ds.attrs.get("xpersson_scene")
    if not text:
        raise ArchiveError(
            "the Dataset has no attribute 'xpersson_scene' (the resolved scene, which names the "
            "coefficient and boundary the analyses read): analyse needs an archive written by "
            "xpersson (xpersson.to_netcdf, xpersson run) with its global attributes"
        )
    data = json.loads(text)
    if data.get("geometry") and not body:
        raise ArchiveError(
            "analyse runs on a flat's solve; this Dataset holds a finite body ([geometry]): "
            "add the analysis to its scene and solve it again"
        )
    return dict(data)


def _quantities(values: Any, unit: str) -> list[str]:
    """An inline table's column as the scene writes it (exact decimal floats with a unit)."""
    return [f"{float(v)!r} {unit}" for v in np.atleast_1d(np.asarray(values, dtype=float))]


def _check_grid(rs: ResolvedScene, ds: xr.Dataset) -> None:
    """The archive's scene must give the Dataset's loads and magnifications."""
    p0 = np.atleast_1d(np.asarray(ds["p0"].values, dtype=float))
    if not np.array_equal(rs.zeta, np.asarray(ds["zeta"].values, dtype=float)):
        raise ArchiveError(
            "the Dataset's zeta is not its scene's grid of magnifications (was it subset along "
            "zeta with sel/isel?): the analyses integrate over zeta on the solve's own grid; "
            "analyse the Dataset before selecting magnifications"
        )
    if not np.array_equal(rs.p0, p0):
        raise ArchiveError(
            "the Dataset's p0 is not its scene's (a finite body's grid of loads subset with "
            "sel/isel?): analyse the whole solved Dataset"
        )


def with_p0(ds: xr.Dataset, rs: ResolvedScene) -> xr.Dataset:
    """A one-load Dataset (``p0`` squeezed to a scalar) given its ``p0`` dimension back on the
    variables declared along it (the core's and the scene's coefficient and boundary's)."""
    if "p0" in ds.dims:
        return ds
    specs: dict[str, Any] = dict(CORE_VARIABLES)
    for plugin in (rs.coefficient, rs.boundary):
        specs.update(getattr(type(plugin), "outputs", {}) or {})
    variables = {}
    for n, var in ds.data_vars.items():
        spec = specs.get(str(n))
        if spec is not None and "p0" in spec.dims and "p0" not in var.dims:
            variables[n] = var.expand_dims("p0", axis=spec.dims.index("p0"))
    out = ds.drop_vars("p0").assign(variables)
    return out.assign_coords(p0=("p0", rs.p0, dict(ds["p0"].attrs)))


def without(ds: xr.Dataset, names: list[str]) -> xr.Dataset:
    """``ds`` without ``names`` and the plugin dimensions only they used."""
    out = ds.drop_vars([n for n in names if n in ds.variables])
    used = {d for v in out.data_vars.values() for d in v.dims}
    stale = [d for d in out.dims if d not in used and d not in CORE_DIMS and d in out.variables]
    return out.drop_vars(stale)


def run_point(rs: ResolvedScene, ds: xr.Dataset) -> xr.Dataset:
    """The analyses of ``rs`` on one point's ``ds``, in the context the pipeline gives them
    (``ds`` with its ``p0`` dimension, a single load's given back: :func:`squeeze_p0` it)."""
    return analysed(rs, ds)[0]


def analysed(rs: ResolvedScene, ds: xr.Dataset) -> tuple[xr.Dataset, Any]:
    """:func:`run_point` and the analyses' context (what a finite body's outputs read)."""
    who = rs.labels
    labels = [who[f"analyses.{n}"] for n, _ in rs.analyses]
    provided = [v for _, a in rs.analyses for v in type(a).provides]
    out = without(with_p0(ds, rs), provided)
    ctx = scene_context(rs)
    if "p" in out.dims:
        ctx = dataclasses.replace(ctx, p=np.asarray(out["p"].values, dtype=float))
    validate(rs, ctx, who["boundary"], labels)
    coef = rs.coefficient
    coefficient_arrays(coef, ctx, who["coefficient"])  # checked, as the solve checked them
    clock = diffusion_clock(ctx, coef, kinks=spectrum_kinks(rs.psd))
    walls = load_walls(rs, ctx, clock, who["boundary"])
    ctx = dataclasses.replace(
        ctx, coefficient=coef, boundary=rs.boundary, solve_at=make_solve_at(rs, ctx, walls, clock)
    )
    add_analyses(rs, ctx, out, labels)
    return out, ctx
