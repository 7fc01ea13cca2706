"""What a cross-check will do, checked before any work: the physics the BEM can solve, the
band of the spectrum a grid resolves, the theory's scene on that band, memory and time.

Every refusal is one :class:`CrosscheckError` line (a :class:`~xpersson.SceneError`, so the
CLI exits with status 2).
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import SceneError
from ..scene import Scene
from ._errors import CrosscheckError
from ._errors import refuse as _refuse

__all__ = [
    "CrosscheckError",
    "Plan",
    "make_plan",
    "POINTS_PER_WAVELENGTH",
    "STIFFNESS_STEP",
]

#: Grid points per shortest synthesised wavelength: the BEM band ends at
#: ``q_max = q_L n / POINTS_PER_WAVELENGTH`` (or the scene's ``q_1`` when that is lower).
POINTS_PER_WAVELENGTH = 8
#: The stiffness is ``-dp0/du`` from loads ``p0 exp(+-STIFFNESS_STEP)`` [1].
STIFFNESS_STEP = 0.05
#: Analyses the cross-check adds to the theory's scene when their plugin is installed and
#: supports the boundary (their outputs are compared).
ADDED_ANALYSES = ("contact_area", "mean_gap", "contact_stiffness", "gap_pdf")
#: Analyses whose conductance is compared through Barber's analogy.
CONDUCTANCE = {"electrical_contact": "electrical", "thermal_contact": "thermal"}
#: Boundaries the BEM solves, by the law they use there.
ADHESIVE = ("adhesive", "dmt", "jkr")
#: Physics the BEM cannot do, named in the refusal.
CANNOT = {
    "plastic_scale_dependent": "scale-dependent yield (the BEM's hardness is one constant)",
    "friction": "viscoelastic friction (the BEM here is frictionless and elastic)",
}
#: Grid spacings the adhesive cohesive zone ``E* rho^2 / w`` should span (a note below it).
ZONE_PIXELS = 4
#: Bytes per grid point of one realisation's solves (tamaas model, solver work arrays, FFT
#: buffers, the gap maps read back): peak RSS above the imports at 512^2 (98 MB measured).
BYTES_PER_POINT = 400
#: Resident memory of the process before any solve (python, numpy, xarray, tamaas) [bytes].
BASELINE_BYTES = 128 * 2**20
#: Resident memory SurfaceTopography adds when the scene reads scans [bytes] (its import with
#: netCDF and its readers: 118 MB measured).
READER_BYTES = 120 * 2**20
#: CPU seconds of one tamaas solve per ``n^2.5`` grid points (FFTs and iteration count both
#: grow with n; measured 256^2 and 512^2, OPENBLAS_NUM_THREADS=1, upper end).
SECONDS_PER_SOLVE = 6.5e-7


@dataclass
class Plan:
    """A checked cross-check request (SI)."""

    scene: Scene
    theory_scene: Scene
    grid: int
    realisations: int
    seed: int
    L: float
    q_L: float
    q_max: float
    q_1: float
    E_star: float
    p0: np.ndarray
    kind: str  # "elastic", "plastic" or "adhesive"
    hardness: float | None = None
    work: float = 0.0
    rho: float | None = None
    conductance: dict[str, float] = field(default_factory=dict)
    not_compared: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    memory: int = 0
    seconds: float = 0.0
    psd: Any = None
    source: Any = None  # _surfaces.Source: synthesis or the measured map
    grid_check: bool = False  # also solve every realisation on a grid twice as fine

    @property
    def fine_grid(self) -> int:
        """The grid check's grid (twice as fine: 16 points on the shortest wavelength)."""
        return 2 * self.grid

    @property
    def solves(self) -> int:
        """tamaas solves per realisation (3 per load: the stiffness's neighbours)."""
        if self.kind == "adhesive":
            return 30
        return 3 * self.p0.size


def _physics(rs: Any, data: dict[str, Any]) -> dict[str, Any]:
    """The BEM's physics for this scene (kind, hardness, adhesion), or a refusal."""
    names = rs.plugin_names
    if names["coefficient"] != "elastic":
        raise _refuse(
            f"the BEM cannot do the coefficient {names['coefficient']!r} "
            "(viscoelastic, rate-dependent modulus and friction); only 'elastic' is checked"
        )
    for name in data.get("analyses", {}):
        if name in CANNOT:
            raise _refuse(f"the BEM cannot do analyses.{name}: {CANNOT[name]}")
    b = names["boundary"]
    params = dict(getattr(rs.boundary, "params", {}) or {})
    if b == "elastic":
        return {"kind": "elastic"}
    if b == "plastic":
        return {"kind": "plastic", "hardness": float(params["sigma_Y"])}
    if b in CANNOT:
        raise _refuse(f"the BEM cannot do boundary {b!r}: {CANNOT[b]}")
    if b in ADHESIVE:
        law = params.get("law", "exponential")
        if law != "exponential" or not params.get("range"):
            raise _refuse(
                f"the BEM's adhesion is tamaas' exponential law -w exp(-g/rho); boundary {b!r} "
                f"with law {law!r} and range {params.get('range')!r} m has no BEM counterpart "
                "(give law = 'exponential' and a range)"
            )
        return {"kind": "adhesive", "work": float(params["work_of_adhesion"]),
                "rho": float(params["range"])}  # fmt: skip
    raise _refuse(f"the BEM cannot do boundary {b!r} (elastic, plastic, adhesive, dmt, jkr)")


def _process_zone(plan: Plan) -> None:
    """Refuse an adhesive law whose cohesive zone ``E* rho^2 / w`` (Maugis) is below one grid
    spacing: the BEM cannot resolve it and turns into a sticky-contact artefact; note it below
    :data:`ZONE_PIXELS` spacings."""
    if plan.kind != "adhesive":
        return
    zone = plan.E_star * plan.rho**2 / plan.work
    pixel = plan.L / plan.grid
    if zone < pixel:
        need = math.sqrt(plan.work * pixel / plan.E_star)
        raise _refuse(
            f"the adhesive law's cohesive zone E* rho^2 / w = {zone:.3g} m is below the grid "
            f"spacing {pixel:.3g} m: the BEM cannot resolve this adhesion (range >= "
            f"{need:.3g} m or a grid of {math.ceil(plan.L / zone)}^2 would); the short-range "
            "(JKR-like) limit is not checked"
        )
    if zone < ZONE_PIXELS * pixel:
        plan.notes.append(
            f"the adhesive cohesive zone E* rho^2 / w = {zone:.3g} m spans fewer than "
            f"{ZONE_PIXELS} grid spacings: the BEM's adhesion is under-resolved"
        )


def _band(source: Any, grid: int) -> tuple[float, float, float]:
    """(q_L, q_max, q_1) [1/m]: the cell is ``2 pi / q_L``, the grid resolves up to q_max."""
    q_L = source.q_L
    return q_L, min(source.top, q_L * grid / POINTS_PER_WAVELENGTH), source.top


def _theory_data(data: dict[str, Any], rs: Any, q_max: float, kind: str) -> dict[str, Any]:
    """The scene with its spectrum cut at the BEM's ``q_max`` (same C(q)), and the analyses
    whose outputs are compared."""
    out = copy.deepcopy(data)
    if rs.plugin_names["spectrum"] == "self_affine":
        sp = out["spectrum"]
        for key in ("h_rms", "rms_slope", "C_r"):
            sp.pop(key, None)
        sp["C_r"] = f"{float(rs.psd.C_r)!r} m**4"
        sp["q_1"] = f"{q_max!r} 1/m"
        if float(rs.psd.q_r) >= q_max:  # the band holds the plateau only (q_r < q_1 required)
            sp["q_r"] = f"{q_max / (1 + 1e-9)!r} 1/m"
    else:
        out["spectrum"] = _table_spectrum(rs.psd, q_max)
    out.pop("output", None)
    out.pop("title", None)
    analyses = dict(out.get("analyses", {}))
    if kind != "adhesive":
        for name in ADDED_ANALYSES:
            analyses.setdefault(name, {})
    out["analyses"] = analyses
    return out


def _table_spectrum(psd: Any, q_max: float) -> dict[str, Any]:
    """The scene's table (Persson, SI, as resolved: truncations applied) inline, cut at
    ``q_max`` [1/m]: the same ``C(q)`` on the BEM's band."""
    q, C = np.asarray(psd.q_table, float), np.asarray(psd.C_table, float)
    out: dict[str, Any] = {
        "model": "tabulated",
        "q": [f"{float(x)!r} 1/m" for x in q],
        "C": [f"{float(x)!r} m**4" for x in C],
    }
    if q_max < q[-1]:
        out["q_1"] = f"{q_max!r} 1/m"
    return out


def _supported(theory: dict[str, Any], user: set[str]) -> tuple[dict[str, Any], list[str]]:
    """Drop the added analyses (not the user's own) that no installed plugin provides or that
    the boundary does not support: each is tried on top of those already kept."""
    from ..plugins import get_registry

    installed = set(get_registry().names("analyses"))
    kept = {k: v for k, v in theory["analyses"].items() if k in user}
    dropped = []
    for name in ADDED_ANALYSES:
        if name in user:
            continue
        if name not in installed:
            dropped.append(f"{name} (no installed plugin provides it)")
            continue
        trial = copy.deepcopy(theory) | {"analyses": kept | {name: {}}}
        try:
            Scene(trial).resolve()
        except SceneError:
            dropped.append(f"{name} (not supported for this boundary)")
            continue
        kept[name] = {}
    theory["analyses"] = kept
    return theory, dropped


def _conductance(rs: Any) -> dict[str, float]:
    """Barber's constant c [S m^-1 Pa^-1 or W K^-1 Pa^-1] of each conductance analysis."""
    from .derived import electrical_factor, thermal_factor

    out = {}
    for name, a in rs.analyses:
        p = getattr(a, "params", {}) or {}
        if name == "electrical_contact":
            out["electrical"] = electrical_factor(p["resistivity_1"], p["resistivity_2"], rs.E_star)
        elif name == "thermal_contact":
            out["thermal"] = thermal_factor(p["conductivity_1"], p["conductivity_2"], rs.E_star)
    return out


def _roughness_in_band(plan: Plan, band: float, scene: float) -> None:
    """Refuse a band that holds no roughness (``band`` and ``scene`` rms heights [m]): e.g. the
    first rings of a line scan's table, which carry (almost) nothing, on a small grid."""
    if not band > 1e-6 * scene:
        raise _refuse(
            f"the band q_L..q_max = {plan.q_L:.4g}..{plan.q_max:.4g} 1/m that a {plan.grid}^2 "
            f"grid resolves holds no roughness of the spectrum (h_rms {band:.3g} m of the "
            f"scene's {scene:.3g} m): give a larger --grid"
        )


def _estimate(plan: Plan, workers: int) -> None:
    """Memory [bytes] and serial CPU time [s] of the BEM part (the grid check's finer solves
    included), checked against the budget."""
    from .. import memory

    largest = plan.fine_grid if plan.grid_check else plan.grid
    plan.memory = (
        BASELINE_BYTES
        + (READER_BYTES if plan.source is not None and plan.source.reads_files else 0)
        + int(BYTES_PER_POINT * largest**2 * max(1, workers))
        + memory.estimate(max(1, plan.p0.size), 200)
    )
    grids = (plan.grid, plan.fine_grid) if plan.grid_check else (plan.grid,)
    plan.seconds = sum(SECONDS_PER_SOLVE * g**2.5 for g in grids) * plan.solves * plan.realisations
    have = memory.budget()
    if plan.memory > have:
        check = f" (the grid check solves {largest}^2)" if plan.grid_check else ""
        raise _refuse(
            f"grid {plan.grid}^2{check} needs about {plan.memory / 2**20:.0f} MiB "
            f"({max(1, workers)} worker(s)), above the memory budget of {have / 2**20:.0f} MiB: "
            "use a smaller --grid, fewer workers, or raise XPERSSON_MEMORY_BUDGET"
        )


def make_plan(
    scene: Scene,
    grid: int,
    realisations: int,
    seed: int,
    workers: int = 1,
    grid_check: bool = False,
) -> Plan:
    """Check the request and build the :class:`Plan` (no solve; raises CrosscheckError)."""
    from ..sweep import expand
    from ._surfaces import source_of

    if not (isinstance(grid, int) and grid >= 16 and grid % 2 == 0):
        raise _refuse(f"grid [1] must be an even integer >= 16; got {grid!r}")
    if not (isinstance(realisations, int) and realisations >= 1):
        raise _refuse(f"realisations [1] must be an integer >= 1; got {realisations!r}")
    if expand(scene) is not None:
        raise _refuse("the scene sweeps parameters; cross-check one scene (lists only in p0)")
    rs = scene.resolve()
    phys = _physics(rs, scene.data)
    p0 = np.atleast_1d(np.asarray(rs.p0, dtype=float))
    if phys["kind"] != "adhesive" and np.any(p0 <= 0):
        raise _refuse("load.p0 [Pa] must be > 0 for a non-adhesive BEM solve")
    if phys.get("hardness") and np.any(p0 >= phys["hardness"]):
        raise _refuse("load.p0 [Pa] must stay below boundary.sigma_Y for the plastic BEM")
    source = source_of(rs)
    q_L, q_max, q_1 = _band(source, grid)
    user = set(scene.data.get("analyses", {}))
    theory, dropped = _supported(_theory_data(scene.data, rs, q_max, phys["kind"]), user)
    plan = Plan(
        scene=scene, theory_scene=Scene(theory), grid=grid, realisations=realisations,
        seed=int(seed), L=2 * math.pi / q_L, q_L=q_L, q_max=q_max, q_1=q_1,
        E_star=float(rs.E_star), p0=p0, psd=rs.psd, source=source,
        grid_check=bool(grid_check), **phys,
    )  # fmt: skip
    plan.notes.extend(source.notes)
    theory_rs = plan.theory_scene.resolve()
    _roughness_in_band(plan, float(theory_rs.psd.h_rms()), float(rs.psd.h_rms()))
    plan.conductance = _conductance(theory_rs)
    plan.not_compared = dropped + [
        f"analyses.{a} (no BEM counterpart)"
        for a in scene.data.get("analyses", {})
        if a not in ADDED_ANALYSES and a not in CONDUCTANCE
    ]
    if q_max < q_1:
        plan.notes.append(
            f"the {grid}^2 grid resolves q_L..{q_max:.4g} 1/m (zeta = {q_max / q_L:.4g}) of the "
            f"scene's q_L..{q_1:.4g} 1/m; theory and BEM are compared on that band"
        )
    _process_zone(plan)
    _estimate(plan, workers)
    return plan
