"""A rough sphere by the boundary-element method: the finite body's reference solution.

A smooth sphere of radius ``R`` pressed by a force ``F`` on a rough flat is a periodic map:
the rough heights plus the cap ``-r^2/(2R)`` about the cell centre, solved at the mean pressure
``F/L^2`` (:func:`xpersson.bem.solve`, Polonsky-Keer-Rey). From the traction and gap maps:

* the real contact area ``A = (contact fraction) L^2`` [m^2];
* the nominal contact radius holding :data:`FORCE_FRACTION` of the force about the centre [m]
  (the same definition as the theory's ``nominal_contact_radius``);
* the nominal pressure ``p(r)`` [Pa]: the traction averaged over rings about the centre;
* the approach ``delta`` [m] of the mean planes, as the theory defines it
  (``u(r) = r^2/(2R) - delta + w(r)``, ``w`` the displacement of an *isolated* half-space):
  the periodic solution's own rigid-body position (the gap's cell mean) corrected by the
  difference between the isolated and the periodic displacement at the centre, computed for
  the ring-averaged pressure (a smooth field: the images and the periodic zero mode, with no
  discretisation of the asperity-scale kernel).

The cell must hold the nominal contact with room (:data:`CELL_FACTOR` times its radius, so the
periodic images change the local pressure little) and resolve the shortest wavelength with
:data:`~xpersson.bem._plan.POINTS_PER_WAVELENGTH` points. :func:`crosscheck_sphere` runs it
against :func:`xpersson.solve` of a ``[geometry] model = "sphere"`` scene on the same band.
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import xarray as xr

from ._stats import mean_se

__all__ = [
    "CELL_FACTOR",
    "FORCE_FRACTION",
    "SphereState",
    "approach",
    "cap",
    "crosscheck_sphere",
    "force_radius",
    "is_body",
    "ring_average",
    "ring_means",
    "solve_sphere",
    "table_lines",
]

#: Fraction of the force inside the nominal contact radius [1] (the theory's).
FORCE_FRACTION = 0.99
#: Side of the BEM cell per nominal contact radius (the theory's largest) [1]: the contact's
#: diameter stays below half the cell.
CELL_FACTOR = 4.5
_SELF = 4.0 * math.log(1.0 + math.sqrt(2.0))  # uniform square, displacement at its centre


def cap(L: float, n: int, R: float) -> np.ndarray:
    """The sphere's heights ``-r^2/(2R)`` [m] about the cell centre (index ``n // 2``)."""
    x = (np.arange(n) - n // 2) * (L / n)
    return -(x[:, None] ** 2 + x[None, :] ** 2) / (2.0 * R)


def _radii(L: float, n: int) -> np.ndarray:
    x = (np.arange(n) - n // 2) * (L / n)
    return np.hypot(x[:, None], x[None, :])


def force_radius(pressure: np.ndarray, L: float, fraction: float = FORCE_FRACTION) -> float:
    """Radius [m] about the cell centre holding ``fraction`` of the force of a traction map
    ``pressure`` [Pa] on a cell of side ``L`` [m]."""
    r = _radii(L, pressure.shape[0]).ravel()
    order = np.argsort(r)
    cum = np.cumsum(np.clip(pressure.ravel()[order], 0.0, None))
    return float(r[order][np.searchsorted(cum, fraction * cum[-1])])


def ring_average(pressure: np.ndarray, L: float, edges: np.ndarray) -> np.ndarray:
    """Traction [Pa] averaged over the rings ``edges[i] <= r < edges[i+1]`` [m] about the
    centre (NaN for a ring without grid points)."""
    r = _radii(L, pressure.shape[0]).ravel()
    k = np.digitize(r, edges) - 1
    ok = (k >= 0) & (k < edges.size - 1)
    total = np.bincount(k[ok], pressure.ravel()[ok], minlength=edges.size - 1)
    count = np.bincount(k[ok], minlength=edges.size - 1)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(count > 0, total / count, np.nan)


def approach(
    pressure: np.ndarray, gap: np.ndarray, surface: np.ndarray, L: float, E_star: float
) -> float:
    """Approach [m] of the mean planes of a solved sphere map, referred to an isolated
    half-space (the theory's ``delta``).

    ``surface`` [m] is the rigid map solved (rough heights plus :func:`cap`), ``gap`` [m] and
    ``pressure`` [Pa] its solution. The periodic solution's gap is ``c + w_per - surface``
    (``w_per`` of zero cell mean), so ``c`` is the cell mean of ``gap + surface``; the approach
    is ``w_iso(0) - w_per(0) - c``, the first two for the ring-averaged pressure.
    """
    n = pressure.shape[0]
    d = L / n
    r = _radii(L, n)
    ring = np.floor(r / d).astype(int)  # rings one grid step wide
    mean = np.bincount(ring.ravel(), pressure.ravel()) / np.bincount(ring.ravel())
    smooth = mean[ring]
    k = 2.0 * math.pi * np.fft.fftfreq(n, d=d)
    kk = np.hypot(k[:, None], k[None, :])
    kk[0, 0] = np.inf  # the periodic zero mode: none
    w_per = np.fft.ifft2(2.0 * np.fft.fft2(smooth) / (E_star * kk)).real
    c = n // 2
    with np.errstate(divide="ignore"):
        inv = np.where(r > 0, d * d / np.where(r > 0, r, 1.0), _SELF * d)
    w_iso = float(np.sum(smooth * inv)) / (math.pi * E_star)
    offset = float(np.mean(gap + surface))
    return w_iso - float(w_per[c, c]) - offset


@dataclass(frozen=True)
class SphereState:
    """One solved rough sphere (SI): ``real_area`` [m^2], ``radius`` [m] (holding
    :data:`FORCE_FRACTION` of the force), ``approach`` [m], ``profile`` [Pa] (ring-averaged
    traction on the requested edges), ``converged``."""

    real_area: float
    radius: float
    approach: float
    profile: np.ndarray
    converged: bool


def solve_sphere(
    rough: np.ndarray,
    L: float,
    R: float,
    E_star: float,
    forces: Any,
    edges: np.ndarray | None = None,
) -> list[SphereState]:
    """A rough map ``rough`` [m] (``n x n`` on a cell of side ``L`` [m]) under a sphere of
    radius ``R`` [m] on a half-space of contact modulus ``E_star`` [Pa], at ``forces`` [N]
    (increasing; each solve starts from the previous). ``edges`` [m]: rings of ``profile``.
    A solve that does not converge is NaN and flagged."""
    from .solve import solve

    n = rough.shape[0]
    surface = rough + cap(L, n, R)
    forces = np.atleast_1d(np.asarray(forces, float))
    edges = np.linspace(0.0, L / 2, 65) if edges is None else np.asarray(edges, float)
    states = solve(surface, L, E_star, forces / L**2, strict=False, keep_fields=True)
    out = []
    for st in states:
        if not st.converged:
            nan = np.full(edges.size - 1, np.nan)
            out.append(SphereState(math.nan, math.nan, math.nan, nan, False))
            continue
        out.append(
            SphereState(
                st.area_fraction * L * L,
                force_radius(st.pressure, L),
                approach(st.pressure, st.gap, surface, L, E_star),
                ring_average(st.pressure, L, edges),
                True,
            )
        )
    return out


def is_body(scene: Any) -> bool:
    """Whether a scene (a :class:`~xpersson.scene.Scene`) is a finite body (not ``flat``)."""
    return str(scene.data.get("geometry", {}).get("model", "flat")) != "flat"


# ---------------------------------------------------------------------------------------------
# the cross-check of a sphere scene


def _refuse(what: str) -> Exception:
    from ._plan import CrosscheckError

    return CrosscheckError(f"crosscheck: {what}")


def _theory_scene(data: dict[str, Any], q_max: float, rs: Any) -> dict[str, Any]:
    """The scene with its spectrum cut at the BEM's ``q_max`` (same C(q))."""
    out = copy.deepcopy(data)
    sp = out["spectrum"]
    for key in ("h_rms", "rms_slope", "C_r"):
        sp.pop(key, None)
    sp["C_r"] = f"{float(rs.psd.C_r)!r} m**4"
    sp["q_1"] = f"{q_max!r} 1/m"
    if float(rs.psd.q_r) >= q_max:
        sp["q_r"] = f"{q_max / (1 + 1e-9)!r} 1/m"
    for key in ("output", "title", "analyses"):
        out.pop(key, None)
    return out


@dataclass
class _SpherePlan:
    L: float
    q_L: float
    q_max: float
    q_1: float
    R: float
    E_star: float
    forces: np.ndarray
    theory: Any
    psd: Any
    notes: list[str]


def _plan(scene: Any, grid: int, realisations: int) -> _SpherePlan:
    """Check the request (one line on refusal) and choose the cell and band."""
    from ..api import solve
    from ..scene import Scene
    from ..sweep import expand
    from ._plan import POINTS_PER_WAVELENGTH, _physics

    model = scene.data.get("geometry", {}).get("model")
    if model != "sphere":
        raise _refuse(
            f"geometry model {model!r}: the boundary-element cross-check does a sphere only "
            "(a cylinder's line contact needs a 2-D periodic strip solver, not built)"
        )
    if not (isinstance(grid, int) and grid >= 64 and grid % 2 == 0):
        raise _refuse(f"grid [1] must be an even integer >= 64 for a sphere; got {grid!r}")
    if not (isinstance(realisations, int) and realisations >= 1):
        raise _refuse(f"realisations [1] must be an integer >= 1; got {realisations!r}")
    if expand(scene) is not None:
        raise _refuse("the scene sweeps parameters; cross-check one scene (lists only in force)")
    rs = scene.resolve()
    if _physics(rs, scene.data)["kind"] != "elastic":
        raise _refuse("a sphere is cross-checked on an elastic boundary only")
    if rs.plugin_names["spectrum"] != "self_affine":
        raise _refuse("the cross-check synthesises 'self_affine' spectra only")
    q_L, q_1 = float(rs.psd.q_L), float(rs.psd.q_1)
    full = solve(_theory_scene(scene.data, q_1, rs))
    radius = float(np.max(full["nominal_contact_radius"].values))
    L = CELL_FACTOR * radius
    q_max = min(q_1, (2.0 * math.pi / L) * grid / POINTS_PER_WAVELENGTH)
    if q_max <= 1.5 * q_L:
        need = math.ceil(1.5 * q_L * L * POINTS_PER_WAVELENGTH / (2.0 * math.pi))
        raise _refuse(
            f"grid {grid}^2 on the cell {L:.4g} m (= {CELL_FACTOR} x the nominal radius) "
            f"resolves q up to {q_max:.4g} 1/m, not above 1.5 q_L = {1.5 * q_L:.4g} 1/m: use "
            f"--grid {need + need % 2} or more"
        )
    notes = []
    if q_max < q_1:
        notes.append(
            f"the {grid}^2 grid resolves q_L..{q_max:.4g} 1/m of the scene's q_L..{q_1:.4g} "
            "1/m; theory and BEM are compared on that band"
        )
    return _SpherePlan(
        L,
        q_L,
        q_max,
        q_1,
        float(rs.geometry.params["radius"]),
        float(rs.E_star),
        np.atleast_1d(np.asarray(rs.force, float)),
        Scene(_theory_scene(scene.data, q_max, rs)),
        rs.psd,
        notes,
    )


def crosscheck_sphere(
    scene: Any, realisations: int = 4, grid: int = 512, seed: int = 0, echo: Any = None
) -> xr.Dataset:
    """A ``[geometry] model = "sphere"`` scene by the theory and by the BEM (see
    :func:`xpersson.crosscheck`): per force, ``real_contact_area``, ``nominal_contact_radius``,
    and ``approach`` (BEM mean, ``_se``, ``_theory``, ``_ratio`` =
    theory/BEM, ``_realisations``), ``nominal_pressure`` (BEM) and ``nominal_pressure_theory``
    averaged over :data:`RINGS` rings (coordinate ``ring``), and ``nominal_pressure_l1``
    (``int |p_theory - p_BEM| dA / F``)."""
    from ..api import solve
    from .solve import require_tamaas
    from .synthesis import synthesise

    version = str(require_tamaas().__version__)
    plan = _plan(scene, grid, realisations)
    if echo is not None:
        echo(
            f"crosscheck: sphere, {realisations} realisation(s) x {grid}^2 grid x "
            f"{plan.forces.size} force(s), cell {plan.L:.4g} m, band q_L..q_max = "
            f"{plan.q_L:.4g}..{plan.q_max:.4g} 1/m"
        )
        for note in plan.notes:
            echo(f"crosscheck: {note}")
    th = solve(plan.theory)
    th = th.expand_dims("force") if "force" not in th.dims else th
    edges = np.linspace(0.0, float(th["r"].values[-1]), RINGS + 1)
    maps = synthesise(
        plan.psd.C,
        plan.L,
        grid,
        seed=seed,
        realisations=realisations,
        q_min=plan.q_L,
        q_max=plan.q_max,
    )
    runs = [solve_sphere(h, plan.L, plan.R, plan.E_star, plan.forces, edges) for h in maps]
    ring = xr.Variable(("ring",), 0.5 * (edges[1:] + edges[:-1]), _RING_ATTRS)
    ds = xr.Dataset(
        coords={"force": th["force"], "ring": ring, "realisation": np.arange(realisations)}
    )
    for name in ("real_contact_area", "nominal_contact_radius", "approach"):
        vals = np.array([[getattr(s, _FIELD[name]) for s in run] for run in runs])
        _compare(ds, th, name, vals)
    prof = np.array([[s.profile for s in run] for run in runs])
    _profile(ds, th, prof, edges)
    conv = np.array([[s.converged for s in run] for run in runs], dtype="i1")
    ds["bem_converged"] = (
        ("realisation", "force"),
        conv,
        {"units": "1", "long_name": "1: the tamaas solve converged"},
    )
    ds.attrs = _sphere_attrs(plan, grid, realisations, seed, version)
    return ds


def _compare(ds: xr.Dataset, th: xr.Dataset, name: str, values: np.ndarray) -> None:
    """``name`` (BEM mean over realisations), ``_se``, ``_theory``, ``_ratio`` (theory/BEM)
    and ``_realisations`` over ``force`` (NaN values, not converged, left out)."""
    ref = th[name]
    mean, se = mean_se(values)
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = ref.values / mean
    units, long = ref.attrs.get("units", "1"), ref.attrs.get("long_name", name)
    rows = {
        name: (mean, units, f"BEM (tamaas), mean over realisations: {long}"),
        f"{name}_se": (se, units, f"standard error of the BEM mean of {name}"),
        f"{name}_theory": (ref.values, units, f"theory: {long}"),
        f"{name}_ratio": (ratio, "1", f"theory / BEM of {name}"),
    }
    for key, (val, unit, text) in rows.items():
        ds[key] = (("force",), val, {"units": unit, "long_name": text})
    ds[f"{name}_realisations"] = (
        ("realisation", "force"),
        values,
        {"units": units, "long_name": f"BEM {name} per realisation"},
    )
    ds[name].attrs["ancillary_variables"] = " ".join(
        f"{name}_{s}" for s in ("se", "theory", "ratio", "realisations")
    )


_FIELD = {
    "real_contact_area": "real_area",
    "nominal_contact_radius": "radius",
    "approach": "approach",
}


#: Rings of the compared nominal pressure (equal widths out to the theory's outer radius).
RINGS = 40
_RING_ATTRS = {"units": "m", "long_name": "centre radius of the ring of the compared p(r)"}


def ring_means(r: np.ndarray, p: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """Area-weighted means [Pa] over the rings ``edges`` [m] of pressures ``p`` [Pa] given at
    radii ``r`` [m] (rows of ``p``: one profile each; zero beyond ``r``)."""
    fine = np.linspace(0.0, edges[-1], 40 * (edges.size - 1) + 1)
    k = np.minimum(np.searchsorted(edges, fine, side="right") - 1, edges.size - 2)
    rows = np.atleast_2d(p)
    sums = [np.bincount(k, np.interp(fine, r, row, right=0.0) * fine) for row in rows]
    return np.array(sums).reshape(np.shape(p)[:-1] + (edges.size - 1,)) / np.bincount(k, fine)


def _profile(ds: xr.Dataset, th: xr.Dataset, prof: np.ndarray, edges: np.ndarray) -> None:
    """The nominal pressure averaged over the rings ``edges``: the BEM's traction, the
    theory's p(r), and their L1 distance per force (``int |p_th - p_BEM| dA / F``)."""
    p_th = ring_means(th["r"].values, th["nominal_pressure"].values, edges)
    mean = np.nanmean(prof, axis=0)
    area = math.pi * np.diff(edges**2)
    l1 = np.nansum(np.abs(p_th - mean) * area, axis=1) / th["force"].values
    unit = {"units": "Pa"}
    ds["nominal_pressure"] = (
        ("force", "ring"),
        mean,
        unit | {"long_name": "BEM (tamaas): traction averaged over rings"},
    )
    ds["nominal_pressure_theory"] = (
        ("force", "ring"),
        p_th,
        unit | {"long_name": "theory: nominal pressure p(r), ring means"},
    )
    ds["nominal_pressure_l1"] = (
        ("force",),
        l1,
        {"units": "1", "long_name": "int |p_theory - p_BEM| 2 pi r dr / force"},
    )


def _sphere_attrs(plan: _SpherePlan, grid: int, n: int, seed: int, version: str) -> dict:
    from ..provenance import version as xp_version
    from ._plan import POINTS_PER_WAVELENGTH

    return {
        "title": "xpersson crosscheck: rough sphere, theory against boundary-element contact",
        "Conventions": "CF-1.8",
        "source": f"xpersson {xp_version()} crosscheck; tamaas {version}",
        "tamaas_version": version,
        "crosscheck_kind": "sphere",
        "crosscheck_seed": seed,
        "crosscheck_grid": grid,
        "crosscheck_realisations": n,
        "cell_side_m": plan.L,
        "cell_per_nominal_radius": CELL_FACTOR,
        "q_L_per_m": plan.q_L,
        "q_max_per_m": plan.q_max,
        "scene_q_1_per_m": plan.q_1,
        "points_per_wavelength": POINTS_PER_WAVELENGTH,
        "nominal_contact_radius_force_fraction": FORCE_FRACTION,
        "approach_definition": "mean-plane approach referred to an isolated half-space "
        "(periodic solution corrected at the centre for the ring-averaged pressure)",
        "notes": "; ".join(plan.notes) or "none",
    }


def table_lines(ds: xr.Dataset) -> list[str]:
    """The CLI's table of a sphere cross-check: theory/BEM per force."""
    names = ("real_contact_area", "nominal_contact_radius", "approach")
    lines = [
        "theory / BEM (+- relative standard error of the BEM mean); p(r): L1 / force",
        f"{'force [N]':>12}  " + "  ".join(f"{n:>24}" for n in names) + f"  {'p(r) L1':>8}",
    ]
    for i, f in enumerate(ds["force"].values):
        cells = []
        for n in names:
            bem = float(ds[n].values[i])
            rel = abs(float(ds[f"{n}_se"].values[i]) / bem) if bem else math.nan
            cells.append(f"{float(ds[f'{n}_ratio'].values[i]):>13.3f} +- {rel:>7.3f}")
        lines.append(
            f"{f:>12.4g}  "
            + "  ".join(f"{c:>24}" for c in cells)
            + f"  {float(ds['nominal_pressure_l1'].values[i]):>8.3f}"
        )
    bad = int((ds["bem_converged"].values == 0).sum())
    if bad:
        lines.append(f"{bad} realisation x force point(s) did not converge: NaN, not averaged")
    return lines
