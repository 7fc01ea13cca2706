"""The theory against boundary-element contact on the user's own scene.

:func:`crosscheck` synthesises ``realisations`` periodic maps of the scene's spectrum (or takes
the scene's measured map: :mod:`._surfaces`), solves
each with tamaas at the scene's loads, solves the scene with the theory on the same band of
wavevectors, and returns both with standard errors and theory/BEM ratios, under the theory's
variable names.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from ..scene import Scene
from ._errors import CrosscheckError
from ._gridcheck import add_grid_ratios
from ._plan import POINTS_PER_WAVELENGTH, STIFFNESS_STEP, Plan, make_plan
from ._realise import Task, run_all
from ._stats import mean_se
from .solve import TOL, TOL_GAP, require_tamaas
from .sphere import crosscheck_sphere, is_body

__all__ = ["crosscheck", "estimate_line"]

#: Compared outputs per BEM kind: (BEM name, theory name, theory reduced at zeta_max).
_PRESSURE = (
    ("area_fraction", "area_fraction"),
    ("mean_gap", "mean_gap"),
    ("contact_stiffness", "contact_stiffness"),
    ("gap_contact_weight", "gap_contact_weight"),
)
_PLASTIC = (
    ("area_fraction", "total_contact_fraction"),
    ("plastic_area_fraction", "plastic_area_fraction"),
    ("elastic_area_fraction", "elastic_area_fraction"),
    ("mean_gap", "mean_gap"),
    ("contact_stiffness", "contact_stiffness"),
)
_ADHESIVE = (("area_fraction", "area_fraction"), ("pull_off_stress", "pull_off_stress"))
_CONDUCTANCE = {
    "electrical": "electrical_constriction_conductance",
    "thermal": "thermal_constriction_conductance",
}


def estimate_line(plan: Plan) -> str:
    """One line: what will be solved and its memory and time estimate (the grid check's
    solves included)."""
    check = f" (+ grid check on {plan.fine_grid}^2)" if plan.grid_check else ""
    return (
        f"crosscheck: {plan.realisations} realisation(s) x {plan.grid}^2 grid x "
        f"{plan.solves} BEM solves ({plan.kind}){check}, cell {plan.L:.4g} m, band "
        f"q_L..q_max = {plan.q_L:.4g}..{plan.q_max:.4g} 1/m; estimate: about "
        f"{plan.memory / 2**20:.0f} MiB, {_human_s(plan.seconds)} CPU"
    )


def _human_s(s: float) -> str:
    return f"{s:.0f} s" if s < 120 else f"{s / 60:.0f} min"


def _edges(u: np.ndarray) -> np.ndarray:
    """Histogram bin edges [m] centred on the theory's gap coordinate ``u``."""
    mid = 0.5 * (u[1:] + u[:-1])
    return np.concatenate([[0.0], mid, [u[-1] + 0.5 * (u[-1] - u[-2])]])


def _theory_value(th: xr.Dataset, name: str) -> xr.DataArray:
    da = th[name]
    return da.isel(zeta=-1, drop=True) if "zeta" in da.dims else da


def _stack(results: list[dict[str, np.ndarray]], key: str) -> np.ndarray:
    return np.stack([np.asarray(r[key], dtype=float) for r in results])


def _bem_values(plan: Plan, results: list[dict[str, np.ndarray]]) -> dict[str, np.ndarray]:
    """Per-realisation BEM values under the BEM names (realisation first)."""
    if plan.kind == "adhesive":
        return {k: _stack(results, k) for k in ("area_fraction", "pull_off_stress")}
    keys = ("area_fraction", "mean_gap", "contact_stiffness", "gap_contact_weight",
            "plastic_area_fraction")  # fmt: skip
    out = {k: _stack(results, k) for k in keys}
    out["elastic_area_fraction"] = out["area_fraction"] - out["plastic_area_fraction"]
    for kind, c in plan.conductance.items():
        out[_CONDUCTANCE[kind]] = c * out["contact_stiffness"]
    if results[0]["gap_pdf"].size:
        out["gap_pdf"] = _stack(results, "gap_pdf")
    return out


def _pairs(plan: Plan) -> list[tuple[str, str]]:
    base = {"adhesive": _ADHESIVE, "plastic": _PLASTIC}.get(plan.kind, _PRESSURE)
    extra = [(_CONDUCTANCE[k], _CONDUCTANCE[k]) for k in plan.conductance]
    return list(base) + extra


def _compare(ds: xr.Dataset, th: xr.Dataset, theory_name: str, values: np.ndarray) -> None:
    """Add ``name`` (BEM mean), its standard error, the theory and the ratio to ``ds``."""
    ref = _theory_value(th, theory_name)
    dims = ("realisation", *ref.dims)
    mean, se = mean_se(values)
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = ref.values / mean
    ratio = np.where(np.isfinite(mean) & (mean != 0), ratio, np.nan)  # full contact: no ratio
    units = ref.attrs.get("units", "1")
    long = ref.attrs.get("long_name", theory_name)
    n_ = theory_name
    rows = {
        n_: (mean, units, f"BEM (tamaas), mean over realisations: {long}"),
        f"{n_}_se": (se, units, f"standard error of the BEM mean of {n_} across realisations"),
        f"{n_}_theory": (ref.values, units, f"theory: {long}"),
        f"{n_}_ratio": (ratio, "1", f"theory / BEM of {n_}"),
    }
    for key, (val, unit, text) in rows.items():
        ds[key] = (ref.dims, val, {"units": unit, "long_name": text})
    ds[n_].attrs["ancillary_variables"] = f"{n_}_se {n_}_theory {n_}_ratio {n_}_realisations"
    ds[f"{n_}_realisations"] = (
        dims,
        values,
        {"units": units, "long_name": f"BEM {n_} per realisation (NaN: not converged)"},
    )


def _gap(ds: xr.Dataset, th: xr.Dataset, values: np.ndarray) -> None:
    """The BEM gap pdf on the theory's ``u`` and the L1 distance of the two distributions."""
    ref = th["gap_pdf"]
    mean, _ = mean_se(values)
    du = np.diff(_edges(th["u"].values))
    w_bem = ds["gap_contact_weight"].values
    w_th = th["gap_contact_weight"].values
    l1 = np.sum(np.abs(ref.values - mean) * du, axis=-1) + np.abs(w_th - w_bem)
    unit, long = ref.attrs.get("units", "m-1"), ref.attrs.get("long_name", "gap pdf")
    ds["gap_pdf"] = (ref.dims, mean, _meta(unit, f"BEM (tamaas), mean over realisations: {long}"))
    ds["gap_pdf"].attrs["ancillary_variables"] = "gap_pdf_theory gap_pdf_l1"
    ds["gap_pdf_theory"] = (ref.dims, ref.values, _meta(unit, f"theory: {long}"))
    ds["gap_pdf_l1"] = (
        ("p0",),
        l1,
        _meta(
            "1",
            "L1 distance of the theory's gap distribution (pdf and contact weight) to the BEM's",
        ),
    )


def _meta(units: str, long_name: str) -> dict[str, str]:
    return {"units": units, "long_name": long_name}


def _attrs(plan: Plan, th: xr.Dataset, version: str) -> dict[str, Any]:
    from ..provenance import version as xp_version

    return {
        "title": "xpersson crosscheck: theory against boundary-element contact (tamaas)",
        "Conventions": "CF-1.8",
        "source": f"xpersson {xp_version()} crosscheck; tamaas {version}",
        "tamaas_version": version,
        "crosscheck_seed": plan.seed,
        "crosscheck_grid": plan.grid,
        "crosscheck_realisations": plan.realisations,
        "crosscheck_kind": plan.kind,
        "cell_side_m": plan.L,
        "q_L_per_m": plan.q_L,
        "q_max_per_m": plan.q_max,
        "scene_q_1_per_m": plan.q_1,
        "zeta_bem": plan.q_max / plan.q_L,
        "points_per_wavelength": POINTS_PER_WAVELENGTH,
        "stiffness_step": f"p0 exp(+-{STIFFNESS_STEP}) central difference",
        "solver": "tamaas PolonskyKeerRey (elastic), KatoSaturated (plastic, pressure capped "
        f"at the hardness), gap-controlled PolonskyKeerRey with ExponentialAdhesionFunctional "
        f"(adhesive); tolerance {TOL:g} ({TOL_GAP:g} gap control); non-converged solves are "
        "NaN and counted in bem_converged",
        "surfaces": plan.source.text(plan.realisations),
        "crosscheck_grid_check": int(plan.grid_check),
        "theory_band": "the theory is solved on the scene's spectrum cut at q_max (same C(q))",
        "theory_status": str(th.attrs.get("status", "success")),
        "theory_h_rms_m": float(th["h_rms"]),
        "theory_rms_slope": float(th["rms_slope"]),
        "not_compared": "; ".join(plan.not_compared) or "none",
        "notes": "; ".join(plan.notes) or "none",
    }


def _grid_check(ds: xr.Dataset, plan: Plan, th: xr.Dataset, results: list[dict[str, Any]],
                coarse: dict[str, np.ndarray]) -> None:  # fmt: skip
    fine = [r["fine"] for r in results]
    du = np.diff(_edges(th["u"].values)) if "gap_pdf" in th else None
    add_grid_ratios(ds, coarse, _bem_values(plan, fine), _pairs(plan), plan.fine_grid, du)
    conv = _stack(fine, "converged").astype("i1")
    ds["bem_converged_fine"] = (
        ("realisation", "p0")[: conv.ndim],
        conv,
        _meta("1", f"bem_converged of the grid check's {plan.fine_grid}^2 solves"),
    )


def _assemble(plan: Plan, th: xr.Dataset, results: list[dict[str, np.ndarray]]) -> xr.Dataset:
    ds = xr.Dataset(coords={"p0": th["p0"], "realisation": np.arange(plan.realisations)})
    ds["realisation"].attrs = {"units": "1", "long_name": "index of the BEM's map (bem_surface)"}
    values = _bem_values(plan, results)
    for bem_name, th_name in _pairs(plan):
        if th_name in th and bem_name in values:
            _compare(ds, th, th_name, values[bem_name])
    if "gap_pdf" in values and "gap_pdf" in th:
        ds = ds.assign_coords(u=th["u"])
        _gap(ds, th, values["gap_pdf"])
    conv = _stack(results, "converged").astype("i1")
    ds["bem_converged"] = (
        ("realisation", "p0")[: conv.ndim],
        conv,
        _meta("1", "1: every tamaas solve of this point reached its tolerance; 0: not (NaN)"),
    )
    if plan.kind != "adhesive":
        ds["bem_full_contact"] = (
            ("realisation", "p0"),
            _stack(results, "full_contact").astype("i1"),
            _meta(
                "1",
                "1: the whole cell is in contact at p0 exp(+step) in the BEM (gap, "
                "stiffness and conductance not compared there)",
            ),
        )
    ds["bem_h_rms"] = (
        ("realisation",),
        _stack(results, "h_rms"),
        _meta("m", "rms height of the BEM's map (band-limited to q_max)"),
    )
    ds["bem_rms_slope"] = (
        ("realisation",),
        _stack(results, "rms_slope"),
        _meta("1", "rms slope of the BEM's map (band-limited to q_max)"),
    )
    ds["bem_surface"] = plan.source.flags(plan.realisations)
    if plan.grid_check:
        _grid_check(ds, plan, th, results, values)
    return ds


def crosscheck(
    scene: str | Path | Mapping[str, Any] | Scene,
    realisations: int = 4,
    grid: int = 256,
    scheduler: Any = None,
    seed: int = 0,
    *,
    grid_check: bool = False,
    workers: int | None = None,
    echo: Callable[[str], None] | None = None,
) -> xr.Dataset:
    """Solve a scene with the theory and with a boundary-element solver; compare.

    Parameters
    ----------
    scene : path, dict or Scene
        One scene (lists only in ``load.p0``); elastic coefficient; boundary ``elastic``,
        ``plastic`` (constant hardness) or an adhesive one with the exponential law;
        spectrum ``self_affine``, ``tabulated`` (synthesised from the table) or
        ``topography`` (one 2-D map: the map itself is realisation 0; a line scan or several
        scans: synthesised from the table).
    realisations : int
        Number of maps (their scatter gives the standard errors); for a measured map, the
        map and ``realisations - 1`` syntheses of its spectrum table.
    grid : int
        Grid points per side of each map (even). The cell is ``2 pi / q_L``; the BEM resolves
        wavevectors up to ``q_L grid / 8``, and the theory is solved on the same band.
    scheduler : None, str or distributed.Client
        ``None``/``"serial"``, ``"threads"``, ``"processes"``, ``"synchronous"`` (dask local
        schedulers), a scheduler address or a ``Client``; the numbers do not depend on it.
    seed : int
        Base seed of the maps (realisation ``i`` uses ``[seed, i]``).
    grid_check : bool
        Also solve every realisation on a grid twice as fine (16 points on the shortest
        wavelength, same surfaces and band) and add ``X_grid_ratio`` = fine/coarse for every
        BEM output (its cost is in the estimate).
    workers : int, optional
        Concurrent realisations assumed by the memory check (default: the number of cores
        for ``"threads"``/``"processes"``, else 1).
    echo : callable, optional
        Receives the estimate line (and notes) before any work, e.g. ``print``.

    Returns
    -------
    xarray.Dataset
        For each compared output ``X`` (the theory's name and units): ``X`` the BEM mean over
        the realisations, ``X_se`` its standard error, ``X_theory``, ``X_ratio`` = theory/BEM,
        ``X_realisations``; ``gap_pdf`` with ``gap_pdf_l1``; ``bem_converged``; provenance in
        the attributes (seed, grid, realisations, tamaas version, band).

    Raises
    ------
    MissingTamaasError
        tamaas is not installed (``pip install "xpersson[bem]"``).
    CrosscheckError
        Physics the BEM cannot do, a sweep, a spectrum it cannot synthesise, or a grid above
        the memory budget (a :class:`~xpersson.SceneError`, before any work).
    """
    from ..api import solve
    from ..pipeline import as_scene

    version = str(require_tamaas().__version__)
    if workers is None:
        workers = (os.cpu_count() or 1) if scheduler in ("threads", "processes") else 1
    scene = as_scene(scene)
    if is_body(scene):  # a finite body: its own plan and solves (serial)
        if grid_check:
            raise CrosscheckError(
                "grid_check: not available for a [geometry] scene (the rough sphere's cell is "
                "set by its nominal radius); run the cross-check with a larger grid instead"
            )
        return crosscheck_sphere(scene, realisations, grid, seed, echo)
    plan = make_plan(scene, grid, realisations, seed, workers, grid_check)
    if echo is not None:
        echo(estimate_line(plan))
        for note in plan.notes + [f"not compared: {x}" for x in plan.not_compared]:
            echo(f"crosscheck: {note}")
    th = solve(plan.theory_scene)
    if th.attrs.get("status", "success") != "success":
        plan.notes.append(f"the theory's solve reports status {th.attrs.get('status')!r}")
        if echo is not None:
            echo(f"crosscheck: {plan.notes[-1]}")
    edges = _edges(th["u"].values) if "gap_pdf" in th else None
    tasks = [Task(plan, i, edges) for i in range(realisations)]
    ds = _assemble(plan, th, run_all(tasks, scheduler))
    ds.attrs = _attrs(plan, th, version)
    return ds
