"""Analyses of a solved Dataset after the fact: :func:`analyse` (``xpersson.analyse``).

An archive reopened years later (``xpersson.open_dataset``, ``xarray.open_dataset``) carries
what the analyses compute from: the solved area curves, the spectrum the solve used
(``psd_C``, ``psd_exponent`` on ``q_psd``: :func:`xpersson.plugins.stored.spectrum_of`), the
contact modulus ``E_star``, and the resolved scene (attribute ``xpersson_scene``), which names
the coefficient and the boundary whose declarations the analyses read. :func:`analyse` runs an
analysis on that Dataset as the solving process ran it: the same context, and the same
``ctx.solve_at`` (the scene's solve at denser magnifications where the output grid is too
coarse for the integrals over zeta), with the spectrum taken from the Dataset, never from a
file or a spectrum plugin. The numbers equal those of the analysis run inside the solve.
"""

from __future__ import annotations

import dataclasses
import json
from typing import Any

import numpy as np
import xarray as xr

from . import plugins
from .cache import solve_scope
from .checks import CORE_DIMS
from .errors import ArchiveError
from .pipeline import scene_context, squeeze_p0
from .pipeline.assemble import add_analyses
from .pipeline.frontend import diffusion_clock, spectrum_kinks
from .pipeline.solve_at import make_solve_at
from .pipeline.stages import coefficient_arrays, load_walls, validate
from .plugins.stored import contact_modulus, spectrum_of
from .scene import ResolvedScene, Scene
from .schema import CORE_VARIABLES

__all__ = ["analyse"]


def analyse(ds: xr.Dataset, name: str, /, **params: Any) -> xr.Dataset:
    """Run the analysis ``name`` on a solved Dataset and return a new Dataset with its outputs.

    Parameters
    ----------
    ds : xarray.Dataset
        One solved scene (not a sweep): the Dataset :func:`xpersson.solve` returned, or an
        archive reopened with :func:`xpersson.open_dataset` or :func:`xarray.open_dataset`.
    name : str
        An installed analysis (``xpersson plugins list analyses``), e.g. ``"gap_pdf"``,
        ``"leakage"``, ``"elastic_energy"``, ``"thermal_contact"``.
    **params
        The analysis's parameters, as in a scene's ``[analyses.NAME]`` table (numbers in SI,
        or strings with units: ``u_max="2 um"``).

    Returns
    -------
    xarray.Dataset
        ``ds`` (not modified) with the analysis's variables (and those of the analyses it
        requires that ``ds`` lacks) added; variables of the same names are replaced.

    Raises
    ------
    ArchiveError
        ``ds`` lacks what the analyses compute from (the spectrum ``psd_C``/``q_psd``,
        ``E_star``, the scene attribute ``xpersson_scene``: the message names it), or holds a
        sweep or a finite body.
    SceneError
        An unknown analysis or parameter (as in a scene).
    """
    _one_scene(ds)
    spectrum_of(ds)  # what is missing is named before any work
    contact_modulus(ds)
    data = _scene(ds)
    data["analyses"] = {name: dict(params)}
    psd = spectrum_of(ds)  # the scene's spectrum section: the Dataset's table, no file read
    q = psd.nodes()
    data["spectrum"] = {
        "model": "tabulated",
        "q": _quantities(q, "1/m"),
        "C": _quantities(psd.C(q), "m**4"),
    }
    rs = Scene(data, source=None).resolve()
    rs = dataclasses.replace(rs, psd=psd)  # the solve's own segments, bit for bit
    _check_grid(rs, ds)
    with plugins.time_limit(rs.plugin_time_limit), solve_scope():
        return _run(rs, ds)


def _one_scene(ds: xr.Dataset) -> None:
    """Refuse a sweep's Dataset (a point of it has its own scene, which the archive's
    ``xpersson_scene`` with the swept lists does not give)."""
    swept = [d for n in ("area_fraction", "psd_C") if n in ds.variables for d in ds[n].dims]
    swept = [d for d in swept if d not in CORE_DIMS]
    if "xpersson_sweep" in ds.attrs or swept:
        raise ArchiveError(
            f"analyse runs on one solved scene; this Dataset holds a sweep (dims {swept}): add "
            "the analysis to the sweep's scene instead (xpersson.solve(scene, "
            "analyses__NAME={...}))"
        )


def _scene(ds: xr.Dataset) -> dict[str, Any]:
    """The archive's resolved scene (its ``xpersson_scene`` attribute), checked."""
    text = ds.attrs.get("xpersson_scene")
    if not text:
        raise ArchiveError(
            "the Dataset has no attribute 'xpersson_scene' (the resolved scene, which names the "
            "coefficient and boundary the analyses read): analyse needs an archive written by "
            "xpersson (xpersson.to_netcdf, xpersson run) with its global attributes"
        )
    data = json.loads(text)
    if data.get("geometry"):
        raise ArchiveError(
            "analyse runs on a flat's solve; this Dataset holds a finite body ([geometry]): "
            "add the analysis to its scene and solve it again"
        )
    return dict(data)


def _quantities(values: Any, unit: str) -> list[str]:
    """An inline table's column as the scene writes it (exact decimal floats with a unit)."""
    return [f"{float(v)!r} {unit}" for v in np.asarray(values, dtype=float)]


def _check_grid(rs: ResolvedScene, ds: xr.Dataset) -> None:
    """The archive's scene must give the Dataset's loads and magnifications."""
    p0 = np.atleast_1d(np.asarray(ds["p0"].values, dtype=float))
    zeta = np.asarray(ds["zeta"].values, dtype=float)
    if not (np.array_equal(rs.p0, p0) and np.array_equal(rs.zeta, zeta)):
        raise ArchiveError(
            "the Dataset's p0 and zeta are not those of its scene (xpersson_scene): was it "
            "subset (sel/isel)? analyse the whole solved Dataset"
        )


def _with_p0(ds: xr.Dataset, rs: ResolvedScene) -> xr.Dataset:
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


def _without(ds: xr.Dataset, names: list[str]) -> xr.Dataset:
    """``ds`` without ``names`` and the plugin dimensions only they used."""
    out = ds.drop_vars([n for n in names if n in ds.variables])
    used = {d for v in out.data_vars.values() for d in v.dims}
    stale = [d for d in out.dims if d not in used and d not in CORE_DIMS and d in out.variables]
    return out.drop_vars(stale)


def _run(rs: ResolvedScene, ds: xr.Dataset) -> xr.Dataset:
    """The analyses of ``rs`` on ``ds``, in the context the pipeline gives them."""
    who = rs.labels
    labels = [who[f"analyses.{n}"] for n, _ in rs.analyses]
    provided = [v for _, a in rs.analyses for v in type(a).provides]
    squeezed = "p0" not in ds.dims
    out = _without(_with_p0(ds, rs), provided)
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
    return squeeze_p0(out) if squeezed else out
