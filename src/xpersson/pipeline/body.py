"""A finite body on the solved rough flat: the per-force outputs of a ``[geometry]`` scene.

The run has solved the rough interface at a grid of nominal pressures ``p0`` in one batch
(:func:`xpersson.scene` chose the grid). Here the separation ``u(p0)`` and its slope
(virtual work on the solved area curve, :class:`xpersson.physics.SolvedContact`, the curve read
by :func:`xpersson.plugins.solved.solved_curve` as the interface analyses read it) and the
load-bearing area ``A/A0(p0)`` become the interfacial spring of the body, and
:func:`xpersson.physics.body.solve_body` solves the nominal pressure of every force: a coarse
pass finds the extent of the nominal contact, then the grid of ``N`` and ``2N`` cells gives the
result (the finer) and its error estimate (their difference).
"""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np
import xarray as xr

from .. import physics
from ..errors import SceneError, XperssonWarning
from ..physics.body import BodySolution, Separation, force_radius, solve_body, start_at_area
from ..plugins.solved import solved_curve
from ..plugins.stored import contact_modulus, spectrum_of
from ..scene import ResolvedScene
from ..specs import VarSpec
from ._body_local import local_outputs
from ._body_model_error import attach_body

__all__ = ["ASYMPTOTE", "CELLS", "FORCE_FRACTION", "OUTPUTS", "body_dataset"]

FORCE_FRACTION = 0.99
"""The nominal contact radius holds this fraction of the force [1]."""
ASYMPTOTE = 1e-3
"""Contact area fraction [1] below which the separation follows Persson's asymptotic law."""
CELLS = 96
"""Cells of the radial grid of the result (the error estimate compares with half as many)."""
ITERATION_SHARE = 0.01
"""A solve whose Newton iteration stalled is flagged (``status`` tolerance_not_met) when its
gap residual, relative to the approach it solved, exceeds this fraction of its grid error
estimate ``body_grid_error`` [1]."""
_COARSE = 32  # cells of the pass that finds the extent of the nominal contact
_R_POINTS = 201
_PER_DECADE = 40  # dense magnifications of the area curve (as the interface analyses)


def separation(rs: ResolvedScene, ctx: Any, ds: xr.Dataset) -> Separation:
    """``u(p0)``, ``du/dln p0`` and ``A/A0(p0)`` of the solved interface (the flat's Dataset
    ``ds``: its area curve, its stored spectrum and contact modulus, as the analyses read them).

    Below the pressure where the contact area is :data:`ASYMPTOTE` of the nominal one the
    separation is continued by Persson's asymptotic law ``u = u0 ln(p*/p)`` with its slope
    there (Persson 2007): at smaller areas only the highest asperities of a finite body touch,
    and the curve of the infinite flat (whose separation grows without bound) no longer
    describes them.
    """
    solved = solved_curve(ctx, ds, separation_form(ctx), per_decade=_PER_DECADE)
    p = np.asarray(solved.p0, float)
    area = solved.contact[:, -1]
    if not area[-1] >= ASYMPTOTE:  # no start for the continuation (NaN too)
        raise SceneError(_too_light(rs, float(p[-1]), float(area[-1])))
    # from the node below A/A0 = ASYMPTOTE: the continuation starts there exactly
    keep = slice(max(0, min(int(np.searchsorted(area, ASYMPTOTE)) - 1, p.size - 4)), None)
    # the separation of the kept loads only (a load's u(p) and slope use its own row alone)
    zeta, *rows = solved.curve
    rows = [None if r is None else np.broadcast_to(r, (p.size, zeta.size))[keep] for r in rows]
    sc = physics.SolvedContact(spectrum_of(ds), contact_modulus(ds), p[keep], zeta, *rows)
    arrays = (p[keep], sc.mean_gap(), sc.mean_gap_slope() * p[keep], area[keep])
    return Separation(*start_at_area(*arrays, ASYMPTOTE))


def _too_light(rs: ResolvedScene, p_top: float, area: float) -> str:
    """The message of a body whose rough contact stays below :data:`ASYMPTOTE` everywhere."""
    force = float(np.max(np.asarray(rs.force, float)))
    return (
        f"load.force: at {force:.4g} N the rough interface's contact area stays below "
        f"{ASYMPTOTE:g} of the nominal area up to {p_top:.4g} Pa, twice the body's peak Hertz "
        f"pressure (A/A0 = {area:.3g} there); the finite body starts Persson's asymptotic "
        "separation where A/A0 reaches that fraction, so it needs a larger force, a larger body "
        "or a smoother or softer surface"
    )


def separation_form(ctx: Any) -> str:
    """The ``s_factor`` form of ``u(p)``: mean_gap's ``"auto"`` (chosen by accuracy in the flat
    campaign), ``"closure"`` on a coefficient whose closure corrects the area, else
    ``"yang_persson"`` (default gamma)."""
    coefficient = getattr(ctx, "coefficient", None)
    corrected = coefficient is not None and coefficient.corrects_variance()
    return "closure" if corrected else "yang_persson"


def _interpolated(sols: list[BodySolution]) -> Any:
    """A starting pressure [Pa] at radii ``(n_load, n)`` from solutions on other grids."""

    def guess(r: np.ndarray) -> np.ndarray:
        return np.exp(
            [
                np.interp(rk, s.r, np.log(np.maximum(s.p, 1e-300)))
                for rk, s in zip(r, sols, strict=True)
            ]
        )

    return guess


def _solve_forces(
    rs: ResolvedScene, sep: Separation, loads: np.ndarray, E_star: float, h_rms: float
) -> tuple[list[BodySolution], np.ndarray, list[BodySolution]]:
    """The solutions on ``CELLS`` cells, their relative change from ``CELLS // 2`` [1] and the
    solutions on ``CELLS // 2`` cells (contact modulus ``E_star`` [Pa], rms height ``h_rms``
    [m] of the solved Dataset)."""
    geo = rs.geometry
    assert geo is not None
    sym = geo.symmetry
    ref = np.array([geo.reference(float(f), E_star) for f in loads])  # a, delta, peak
    a, delta_h, peak = ref.T
    alpha = np.array([geo.roughness_parameter(h_rms, f, E_star) for f in loads])
    alpha = np.where(np.isfinite(alpha), alpha, 1.0)
    datum = float(geo.params.get("radius", a[0]))

    def run(k: np.ndarray, r_max: np.ndarray, n: int, guess: Any) -> list[BodySolution]:
        return solve_body(
            sym, geo.profile, loads[k], E_star, sep, r_max[k], n, scale=delta_h[k],
            guess=guess, datum=datum,
        )  # fmt: skip

    def hertz(k: np.ndarray) -> Any:
        return lambda r: peak[k, None] * np.sqrt(np.clip(1 - (r / a[k, None]) ** 2, 1e-6, None))

    r_max = a * (1.3 + 4.0 * np.sqrt(alpha))  # wide enough for the example's alpha <= 0.3 at once
    coarse: list[Any] = [None] * loads.size
    outer = np.zeros(loads.size)
    todo = np.arange(loads.size)
    for _ in range(6):  # the coarse pass: where the force acts (wider where it does not fit)
        sols = run(todo, r_max, _COARSE, hertz(todo))
        outer[todo] = force_radius(sols, 0.9999, sym)
        for k, sol in zip(todo, sols, strict=True):
            coarse[k] = sol
        todo = todo[outer[todo] >= 0.9 * r_max[todo]]
        if todo.size == 0:
            break
        r_max[todo] *= 2.0
    every = np.arange(loads.size)
    r_max = 1.2 * outer
    half = run(every, r_max, CELLS // 2, _interpolated(coarse))
    full = run(every, r_max, CELLS, _interpolated(half))
    err = np.zeros(loads.size)
    for fn in (lambda s: force_radius(s, FORCE_FRACTION, sym), lambda s: _real_area(s, sep)):
        x1, x2 = fn(half), fn(full)
        err = np.maximum(err, np.abs(x2 - x1) / np.maximum(np.abs(x2), 1e-300))
    return full, err, half


def _stalled(
    forces: np.ndarray,
    full: list[BodySolution],
    half: list[BodySolution],
    errs: np.ndarray,
    hertz: np.ndarray,
) -> list[str]:
    """One line per force whose Newton iteration (on either grid of the error estimate)
    stalled at a gap residual, relative to the approach solved, above
    :data:`ITERATION_SHARE` of its grid error ``errs``.

    The residual is measured in the Hertz approach ``hertz`` [m] (``body_residual``); under a
    light force on a rough surface the approach is many decades larger (1e-5 m against
    1e-16 m), and the gaps' round-off alone is then 1e-4 - 1e-2 of the Hertz approach: the
    iteration stalls there converged, ~1e-16 of the approach (the fuzz campaign's stalls)."""
    lines = []
    for f, a, b, err, h in zip(forces, full, half, errs, hertz, strict=True):
        res = max(_relative_residual(a, h), _relative_residual(b, h))
        if res > ITERATION_SHARE * err:
            lines.append(
                f"force = {f:g} N: the body's nominal pressure did not converge (gap residual "
                f"{res:.3g} of the approach against a grid error of {err:.3g}; "
                "body_residual, body_grid_error)"
            )
    return lines


def _relative_residual(sol: BodySolution, hertz: float) -> float:
    """A stalled solution's gap residual per the approach it solved (0 when converged)."""
    if sol.converged:
        return 0.0
    return sol.residual * hertz / max(abs(sol.delta), hertz)


def _not_met(out: xr.Dataset, lines: list[str]) -> None:
    """Status ``tolerance_not_met`` with the body's ``lines`` added to the message, and a
    warning."""
    message = "; ".join(lines[:5])
    out.attrs["status"] = "tolerance_not_met"
    if out.attrs.get("status_message", "").startswith("all loads met"):
        out.attrs["status_message"] = message
    else:
        out.attrs["status_message"] = "; ".join([out.attrs.get("status_message", ""), message])
    warnings.warn(message, XperssonWarning, stacklevel=3)


def _real_area(sols: list[BodySolution], sep: Separation) -> np.ndarray:
    """``int A/A0(p) dA`` [m^2] over the cells (per length of a line contact [m]), one per
    solution (of one grid size)."""
    p = np.array([sol.p for sol in sols])
    return np.sum(sep.area_fraction(p) * np.array([sol.cell for sol in sols]), axis=1)


def body_dataset(rs: ResolvedScene, ctx: Any, ds: xr.Dataset) -> xr.Dataset:
    """The solved flat ``ds`` with the body's per-force variables (dimension ``force``).

    The body computes from ``ds`` as the analyses do: its area curve, its stored spectrum
    (:func:`~xpersson.plugins.stored.spectrum_of`) and contact modulus ``E_star``; the scene
    ``rs`` gives the geometry, the forces and the load grid only.
    """
    geo = rs.geometry
    assert geo is not None and rs.force is not None
    E_star, h_rms = contact_modulus(ds), float(spectrum_of(ds).h_rms())
    sep = separation(rs, ctx, ds)
    length = 1.0 if geo.symmetry == "axisymmetric" else float(geo.params["length"])
    loads = np.array([geo.solver_load(float(f)) for f in rs.force])
    sols, errs, half = _solve_forces(rs, sep, loads, E_star, h_rms)
    rows = []
    for load, sol in zip(loads, sols, strict=True):
        a, delta_h, _ = geo.reference(float(load), E_star)
        rows.append(
            (
                sol.delta,
                float(sol.p.max()),
                geo.roughness_parameter(h_rms, float(load), E_star),
                sol.stiffness * length,
                a,
                delta_h,
                sol.residual,
            )
        )
    hertz = np.array([row[5] for row in rows])  # the Hertz approach per force [m]
    stalled = _stalled(np.asarray(rs.force, float), sols, half, errs, hertz)
    area, radius = _real_area(sols, sep) * length, force_radius(sols, FORCE_FRACTION, geo.symmetry)
    cols = np.vstack([area, radius, np.array(rows, dtype=float).T, errs])
    r_out = np.linspace(0.0, max(s.edges[-1] for s in sols), _R_POINTS)
    p_r = np.array([np.interp(r_out, s.r, s.p, right=0.0) for s in sols])
    u_r = sep(np.log(np.maximum(p_r, 1e-300)))[0]
    values = dict(zip(_SCALARS, cols, strict=True))
    values |= {
        "nominal_pressure": p_r,
        "local_area_fraction": sep.area_fraction(p_r),
        "interfacial_separation": np.where(p_r > 0, u_r, np.nan),
        "separation_of_pressure": sep(np.log(np.asarray(rs.p0, float)))[0],
    }
    body = {n: xr.Variable(OUTPUTS[n].dims, v, OUTPUTS[n].attrs()) for n, v in values.items()}
    body["force"] = xr.Variable(("force",), np.asarray(rs.force, float), _FORCE_ATTRS)
    body["r"] = xr.Variable(("r",), r_out, _R_ATTRS[geo.symmetry])
    body |= local_outputs(rs, ds, sols, half, length)  # the analyses' declared local quantities
    out = ds.assign(body)  # one merge for every variable (a dim's namesake is its coordinate)
    _attributes(out, rs, cols)
    out.attrs["geometry_separation_s_factor"] = separation_form(ctx)
    if stalled:  # the body's own verdict joins the flat's
        _not_met(out, stalled)
    attach_body(out, rs)  # the campaign's band of the body outputs
    if rs.force_scalar:
        out = out.isel(force=0)
    return out


_FORCE_ATTRS = {"units": "N", "long_name": "total force on the body"}
_R_ATTRS = {
    "axisymmetric": {"units": "m", "long_name": "radial distance from the axis of the body"},
    "plane": {"units": "m", "long_name": "distance from the line of the contact"},
}
_QUALITY = {"coverage_content_type": "qualityInformation"}
OUTPUTS: dict[str, VarSpec] = {
    "real_contact_area": VarSpec(
        ("force",), "m^2", "real contact area",
        description="int A/A0(p(r)) dA over the nominal contact (a cylinder: over its length)",
    ),
    "nominal_contact_radius": VarSpec(
        ("force",), "m", "nominal contact radius holding 99 % of the force",
        description="a cylinder: the half-width",
    ),
    "approach": VarSpec(
        ("force",), "m", "rigid-body approach of the mean planes",
        description="a cylinder: the displacement referred to the distance R from the line",
    ),
    "peak_pressure": VarSpec(("force",), "Pa", "largest nominal pressure"),
    "johnson_parameter": VarSpec(
        ("force",), "1", "Johnson's roughness parameter sigma R / a0^2",
        nan_meaning="not defined for this geometry",
    ),
    "normal_stiffness": VarSpec(("force",), "N/m", "normal contact stiffness dF/d(approach)"),
    "hertz_radius": VarSpec(("force",), "m", "Hertz contact radius of the smooth body"),
    "hertz_approach": VarSpec(("force",), "m", "Hertz approach of the smooth body"),
    "body_residual": VarSpec(
        ("force",), "1", "gap residual of the nominal pressure per Hertz approach", extra=_QUALITY
    ),
    "body_grid_error": VarSpec(
        ("force",), "1", "relative change of radius and real area from half the cells",
        extra=_QUALITY,
    ),
    "nominal_pressure": VarSpec(("force", "r"), "Pa", "nominal pressure p(r) on the body"),
    "local_area_fraction": VarSpec(
        ("force", "r"), "1", "real contact area fraction A/A0 at the nominal pressure"
    ),
    "interfacial_separation": VarSpec(
        ("force", "r"), "m", "mean interfacial separation u(p(r))",
        nan_meaning="no nominal pressure (outside the solved domain)",
    ),
    "separation_of_pressure": VarSpec(
        ("p0",), "m", "interfacial separation u(p0) the body couples to"
    ),
}  # fmt: skip
"""The variables a finite body adds to the Dataset."""
_SCALARS = tuple(n for n, spec in OUTPUTS.items() if spec.dims == ("force",))


def _attributes(out: xr.Dataset, rs: ResolvedScene, cols: np.ndarray) -> None:
    """Global attributes of the body and the warnings of a contact beyond the theory."""
    geo = rs.geometry
    assert geo is not None
    out.attrs["geometry"] = type(geo).__name__.lower()
    out.attrs["geometry_parameters"] = str(dict(geo.params))
    out.attrs["nominal_contact_radius_force_fraction"] = FORCE_FRACTION
    out.attrs["geometry_cells"] = CELLS
    radius = cols[1]
    if np.any(radius > geo.extent()):
        warnings.warn(
            f"the nominal contact radius reaches {radius.max():.4g} m, beyond "
            f"{geo.extent():.4g} m where the body's small-slope profile holds",
            XperssonWarning,
            stacklevel=3,
        )
    if np.any(cols[3] > float(rs.p0[-1])):
        warnings.warn(
            "the peak nominal pressure exceeds the solved pressure grid; u(p) extrapolated",
            XperssonWarning,
            stacklevel=3,
        )
