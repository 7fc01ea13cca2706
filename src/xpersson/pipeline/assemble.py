"""Dataset assembly of a run: the core variables with their CF attributes, the plugins'
checked contributions, the diagnostics and the global attributes."""

from __future__ import annotations

import json
import warnings
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np
import xarray as xr

from .. import checks
from ..cache import Cache, freeze
from ..errors import XperssonWarning
from ..physics.grids import persson_G
from ..physics.psd import segment_exponents
from ..plugins import SceneContext, VarSpec
from ..scene import ResolvedScene
from ..schema import COORDS, CORE_VARIABLES
from ._draft import Draft
from ._insert import insert_direct, new_variable
from .diagnostics import pdf_resolution, regime_warnings, theory_validity

__all__ = ["assemble", "add_outputs", "attributes", "diagnostics_notes", "squeeze_p0"]


def assemble(
    rs: ResolvedScene,
    ctx: SceneContext,
    results: Any,
    tau_c: np.ndarray,
    f_z: np.ndarray,
    tau_eff: np.ndarray | None,
    p_grid: np.ndarray | None,
    G: np.ndarray | None = None,
) -> Draft:
    """The core Dataset of a run (a :class:`~xpersson.pipeline._draft.Draft`: the Dataset is
    made once, by :meth:`~xpersson.pipeline._draft.Draft.dataset`): coordinates, the engine's
    results, the coefficient's arrays, the spectrum and material scalars, each with its CF
    attributes from the schema (``G``
    (p0, zeta): given where each load has its own ``tau`` row, a stacked run's; else
    :func:`~xpersson.physics.grids.persson_G` of ``tau_c``)."""

    def stack(attr: str) -> np.ndarray:
        return np.asarray(getattr(results, attr), float)  # EngineBatch: stacked arrays

    psd = rs.psd
    q_nodes, psd_c, psd_e, h_rms, slope = _spectrum_variables(psd)
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
        "G": (pz, persson_G(tau_c, rs.p0) if G is None else G),
        "diffusion_time": (("zeta",), tau_c),
        "diffusion_coefficient": (("zeta",), f_z),
        "psd_C": (("q_psd",), psd_c),
        "psd_exponent": (("q_psd",), psd_e),
        "E": ((), rs.E),
        "nu": ((), rs.nu),
        "E_star": ((), rs.E_star),
        "h_rms": ((), h_rms),
        "rms_slope": ((), slope),
        "load_balance": (pz, stack("load_balance")),
        "probability_balance": (pz, stack("probability_balance")),
        "error_estimate": (pz, stack("error_estimate")),
        "solver_status": (("p0",), np.array(results.status, dtype=object)),
    }
    record = getattr(psd, "map_record", None)  # a measured map: its own roughness
    if record:
        data.update({name: ((), float(value)) for name, value in record.items()})
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


_SPECTRUM_VARIABLES = Cache(
    "pipeline.spectrum_variables",
    scope="spectrum",
    maxsize=64,
    doc="a spectrum's Dataset variables: q_psd [1/m], psd_C [m^4], psd_exponent, h_rms [m], "
    "rms_slope",
)


def _spectrum_variables(psd: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray, float, float]:
    """The spectrum's nodes [1/m], C at them [m^4], the segments' exponents [1], the rms height
    [m] and slope [1]: computed once per spectrum (the arrays copied: they become the
    Dataset's data); each time for a spectrum without a content key."""

    def compute() -> tuple[np.ndarray, np.ndarray, np.ndarray, float, float]:
        q_nodes = np.array(psd.nodes(), float)  # a copy: the spectrum's own stays writable
        c = np.asarray(psd.C(q_nodes), float)
        return q_nodes, c, segment_exponents(psd), float(psd.h_rms()), float(psd.rms_slope())

    try:
        q_nodes, c, e, h_rms, slope = _SPECTRUM_VARIABLES.get(psd, compute)
    except TypeError:  # no content key (a spectrum plugin's own class without cache_key)
        return compute()
    return q_nodes.copy(), c.copy(), e.copy(), h_rms, slope


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


#: CF attrs of every coordinate and core variable of the schema (static: made at import; the
#: arrays in them read-only, as every Dataset shares them).
_CORE_ATTRS: dict[str, dict[str, Any]] = {
    name: freeze(spec.attrs()) for name, spec in {**CORE_VARIABLES, **COORDS}.items()
}


def _attrs_of(name: str) -> dict[str, Any]:
    """CF attrs of a core variable or coordinate (a copy; ``{}`` for another name)."""
    return dict(_CORE_ATTRS.get(name, ()))


def _dataset(data: dict[str, Any], coords: dict[str, Any]) -> Draft:
    """The run's Dataset, as a :class:`~xpersson.pipeline._draft.Draft` (made once, at the
    run's end): variables carry their CF attrs from the schema table.

    Its Dataset equals ``xr.Dataset(data, coords=coords)`` followed by :func:`stamp` (the
    variables, then the coordinates); nothing is merged or aligned (one set of coordinates).
    """

    def var(name: str, dims: Any, val: Any) -> xr.Variable:
        arr = np.asarray(val)
        if arr.dtype.kind in "fiub" or (arr.dtype == object and arr.ndim == 1):
            dims = (dims,) if type(dims) is str else tuple(dims)
            return new_variable(dims, arr, _attrs_of(name))  # already an ndarray
        return xr.Variable(dims, val, _attrs_of(name))

    variables = {name: var(name, dims, val) for name, (dims, val) in data.items()}
    variables.update((name, var(name, dims, val)) for name, (dims, val) in coords.items())
    return Draft(variables, set(coords))


def add_outputs(
    ds: xr.Dataset, values: Mapping[str, Any], specs: Mapping[str, VarSpec], who: object
) -> None:
    """Check a plugin's contribution against its VarSpecs (see :mod:`xpersson.checks`), then
    add it."""
    if type(values) is dict and not values:  # nothing to check or add (e.g. elastic's)
        return
    checked = checks.check_contributions(ds, values, specs, who)
    if not checked:
        return
    aligned = True  # every value a checked pair: on the Dataset's dims and sizes
    for name, da in checked.items():
        if type(da) is tuple:  # a checked (dims, ndarray) pair: its Variable, with its attrs
            checked[name] = new_variable(*da, specs[name].attrs())
        else:
            da.attrs.update(specs[name].attrs())
            aligned = False
    if insert_direct(ds, checked, aligned=aligned):
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
            raise checks.PluginFailure(
                f"{who}: variable {name!r}: {exc}", plugin=who, variable=name
            ) from None


def add_analyses(rs: ResolvedScene, ctx: SceneContext, ds: xr.Dataset, labels: list[str]) -> None:
    """Run the scene's analyses on ``ds`` in order (each sees the Dataset through
    :func:`xpersson.checks.guard_dataset`), check that each provides what it declares and add
    its outputs (:func:`add_outputs`); ``labels``: the analyses' labels, in the same order."""
    for (_, analysis), label in zip(rs.analyses, labels, strict=True):
        with checks.guard_dataset(ds, label) as view, checks.calling(label, "compute()"):
            out = analysis.compute(ctx, view)
        missing = [v for v in type(analysis).provides if v not in (out or {})]
        if missing:
            raise checks.PluginFailure(f"{label} did not provide {missing}", plugin=label)
        add_outputs(ds, out, type(analysis).outputs, label)


def diagnostics_notes(ds: xr.Dataset) -> list[str]:
    """Add the P-resolution diagnostics and the per-load ``theory_validity``; collect the
    regime warnings and the unresolved P as notes."""
    theory_validity(ds)
    notes = regime_warnings(ds)
    ds.attrs["regime_warnings"] = json.dumps(notes) if notes else "[]"  # (json.dumps([]))
    unresolved = pdf_resolution(ds)
    return notes + ([unresolved] if unresolved else [])


def attributes(
    ds: xr.Dataset,
    rs: ResolvedScene,
    provenance: Callable[[], Mapping[str, str]],
    results: Any,
    notes: list[str],
    core: Mapping[int, str] | None = None,
) -> None:
    """Set the run's global attributes: provenance (``provenance()``: the CF/ACDD attributes
    and the JSON provenance of the run), status, status message and solver summary; warn with
    an :class:`XperssonWarning` when a load failed or ``notes`` are given."""
    core = core or {}
    # the engine's, or the core output check's verdict (the Variable: no DataArray to build)
    status_of = ds.variables["solver_status"].values
    success = np.asarray(results.success, dtype=bool) & (status_of == "success")
    bad = [
        (
            float(rs.p0[i]),
            str(status_of[i]),
            results[int(i)].message if not results[int(i)].success else core.get(int(i), ""),
        )
        for i in (() if success.all() else np.flatnonzero(~success)[:5])
    ]
    status = "success" if not bad else bad[0][1]
    message = (
        "all loads met the requested tolerance"
        if not bad
        else "; ".join(f"p0 = {p:g} Pa: {s}: {m}" for p, s, m in bad)
    )
    if notes:
        message = "; ".join([message, *notes])
    ds.attrs.update(provenance())
    ds.attrs["status"] = status
    ds.attrs["status_message"] = message
    ds.attrs["xpersson_solver"] = json.dumps(
        {
            "method": rs.resolved["solver"]["method"],
            "methods_used": sorted(set(results.method)),
            "rtol": rs.rtol,
            "atol": rs.atol,
            "max_error_estimate": float(np.asarray(results.error_estimate).max()),
            "work": {
                "nsteps": int(np.asarray(results.nsteps).sum()),
                "wall_time_s": float(results.wall_time),
            },
        }
    )
    if bad or notes:
        warnings.warn(f"xpersson: {message}", XperssonWarning, stacklevel=4)


def squeeze_p0(ds: xr.Dataset) -> xr.Dataset:
    """``ds.isel(p0=0)`` for a one-load Dataset, built directly from the variables.

    Every variable along ``p0`` (size 1) loses that dimension (a view of its data); ``p0``
    becomes a scalar coordinate without an index; the other indexes are kept as they are.
    """
    return Draft.of(ds).squeeze().dataset()
