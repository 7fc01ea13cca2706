"""``jkr``: Persson's adhesive boundary condition, an absorbing wall at p = -sigma_a(zeta).

Contact spots carry tensile stress down to ``-sigma_a(zeta)`` and detach when they reach it
(physics.md §2.1): ``P(-sigma_a(zeta), zeta) = 0``, ``P(p, 1) = delta(p - p0)`` with
``p0 > -sigma_a(1)`` (tensile nominal loads allowed). In diffusion time tau [Pa^2] the core
engine solves the heat equation with the moving absorbing wall
``Wall.absorbing(tau -> -sigma_a(zeta(tau)))`` (closed form when the wall is fixed or linear in
tau, front-fixed Crank-Nicolson otherwise). The probability absorbed at the wall is the
detached area; what stays in the domain is the contact area, which carries

    int p P dp = p0 + int_1^zeta sigma_a |dA|      (physics.md §2.2),

more than p0: the tensile stress left behind by the detached patches.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from xpersson.cache import Cache
from xpersson.physics.interface import full_contact_energy
from xpersson.plugins import Boundary, FastPaths, ParamSpec, VarSpec, fast_paths_on

from ._detachment import (
    ModelLaw,
    TableLaw,
    detachment_stress,
    gamma_effective,
    true_area_ratio,
)
from ._tabor import tabor_parameter, warn_outside_limit
from ._wallpos import DetachmentWall, onset_times, starts_at_zero

if TYPE_CHECKING:  # pragma: no cover
    from xpersson.engine import EngineResult, Wall
    from xpersson.plugins import DiffusionClock, SceneContext

__all__ = ["JKRBoundary", "ADHESION_PARAMETERS", "stickiness"]

_PZ = ("p0", "zeta")

#: Parameters shared by ``jkr`` and ``dmt``.
ADHESION_PARAMETERS: dict[str, ParamSpec] = {
    "work_of_adhesion": ParamSpec(
        unit="J/m**2",
        bounds=(0.0, None),
        description="work of adhesion dgamma at the finest scale (0: no adhesion)",
        sweepable=True,
        example=0.05,
    ),
    "range": ParamSpec(
        unit="m",
        default=1e-9,
        bounds=(0.0, None),
        inclusive=(False, True),
        description="range dr of the attraction (Tabor parameter; dmt: traction-gap law)",
        sweepable=True,
    ),
}


_STICKINESS = Cache(
    "adhesion.stickiness", scope="spectrum", maxsize=64, doc="Persson-Tosatti w_eff [J/m^2]"
)
_SCENE = Cache(
    "adhesion.jkr_scene",
    scope="spectrum",
    maxsize=64,
    doc="jkr (the model law): a scene's scales (as _scales), sigma_a(1) [Pa] and w_eff [J/m^2]",
)
_SCALES = Cache(
    "adhesion.jkr_scales",
    scope="spectrum",
    maxsize=32,
    doc="jkr: gamma_eff, A*/A0, the finer scales' energy and the Tabor parameter per zeta",
)


def stickiness(psd: Any, E_star: float, work: float) -> float:
    """Persson-Tosatti stickiness ``w_eff = dgamma A*/A0 - U_el,full/A0`` [J/m^2] (§2.5)."""
    key = (psd, float(E_star), float(work))
    return _STICKINESS.get(key, lambda: _stickiness(psd, E_star, work))


def _stickiness(psd: Any, E_star: float, work: float) -> float:
    a_star = float(true_area_ratio(2.0 * math.pi * float(psd.I3(psd.q_1))))
    return work * a_star - float(full_contact_energy(psd, E_star))


class JKRBoundary(Boundary):
    """Adhesive contact: absorbing wall at ``p = -sigma_a(zeta)`` [Pa] (Persson 2002).

    ``sigma_a(zeta) = [c_a gamma_eff(zeta) E* q]^(1/2)``, ``q = zeta q_L``, with
    ``gamma_eff`` from the work of adhesion, the true-area enhancement and the full-contact
    elastic energy of the finer scales (clipped at 0); or a user table ``sigma_a(zeta)``.

    Parameters
    ----------
    work_of_adhesion : float
        Work of adhesion at the finest scale [J/m^2], >= 0.
    c_a : float
        Prefactor of the detachment stress [1], > 0 (1: Persson's form; 2, 8/pi, 16/pi^2 from
        other local energy balances, physics.md §2.1).
    sigma_a, sigma_a_zeta : array, optional
        A detachment table: stresses [Pa] (>= 0) at strictly increasing magnifications [1]
        covering the scene's range; replaces the model. One value: a constant wall.
    range : float
        Range of the attraction [m] (Tabor parameter only).
    pull_off_area : float
        Contact-area fraction at zeta_max that defines the pull-off stress [1].
    """

    summary = "adhesive contact: absorbing wall at p = -sigma_a(zeta) (Persson 2002, JKR-type)"
    references = (
        "10.1016/j.surfrep.2006.04.001",
        "10.1063/1.1398300",
        "10.1063/1.4895789",
        "arXiv:cond-mat/0603807",
    )
    tensile_loads = True
    #: one wall for every load (see :meth:`wall`): asked once per run; its table evaluated by
    #: the engine's compiled code (the wall protocol, :class:`xpersson.engine.WallTable`)
    fast_paths = FastPaths(shared_walls=True, wall_tables=True, reused=True)
    parameters = {
        **ADHESION_PARAMETERS,
        "c_a": ParamSpec(
            unit="1",
            default=1.0,
            bounds=(0.0, None),
            inclusive=(False, True),
            description="prefactor of sigma_a = [c_a gamma_eff E* q]^(1/2) (1, 2, 8/pi, 16/pi^2)",
            sweepable=True,
        ),
        "sigma_a": ParamSpec(
            unit="Pa",
            default=None,
            bounds=(0.0, None),
            array=True,
            description="detachment table: sigma_a at sigma_a_zeta (replaces the model)",
        ),
        "sigma_a_zeta": ParamSpec(
            unit="1",
            default=None,
            bounds=(1.0, None),
            array=True,
            description="magnifications of the sigma_a table (strictly increasing)",
        ),
        "pull_off_area": ParamSpec(
            unit="1",
            default=0.0,
            bounds=(0.0, 1.0),
            inclusive=(True, False),
            description="A/A0 at zeta_max defining pull-off (0: any contact; sigma_a(1))",
        ),
    }
    outputs = {
        "detached_fraction": VarSpec(
            _PZ,
            "1",
            "fraction of the nominal area detached at the adhesive wall",
            description="probability absorbed at p = -sigma_a(zeta) (cumulative)",
            valid_min=0.0,
            valid_max=1.0,
        ),
        "contact_stress": VarSpec(
            _PZ,
            "Pa",
            "stress carried by the remaining contact int p P dp",
            description="exceeds p0 by the tensile stress left behind by detached patches",
        ),
        "detached_stress": VarSpec(
            _PZ,
            "Pa",
            "tensile stress left behind by detached patches",
            description="int p P dp - p0 = int_1^zeta sigma_a |dA| (physics.md §2.2)",
            valid_min=0.0,
        ),
        "load_identity_residual": VarSpec(
            ("p0",),
            "1",
            "residual of int p P dp = p0 + int sigma_a |dA|",
            description="max over zeta of the engine's load balance (wall moment summed at "
            "every time step), relative to max(|p0|, sigma_a)",
            valid_min=0.0,
        ),
        "sigma_a": VarSpec(
            ("zeta",),
            "Pa",
            "detachment stress sigma_a",
            valid_min=0.0,
            description="the adhesive wall sits at p = -sigma_a(zeta)",
        ),
        "gamma_eff": VarSpec(
            ("zeta",),
            "J m-2",
            "effective interfacial energy gamma_eff",
            valid_min=0.0,
            description="clipped at 0; with a sigma_a table: sigma_a^2/(c_a E* q)",
        ),
        "true_area_ratio": VarSpec(
            ("zeta",),
            "1",
            "true (surface) area of the resolved roughness A*/A0",
            valid_min=1.0,
        ),
        "finer_scale_energy": VarSpec(
            ("zeta",),
            "J m-2",
            "full-contact elastic energy of the scales finer than zeta",
            valid_min=0.0,
        ),
        "tabor_parameter": VarSpec(
            ("zeta",),
            "1",
            "Tabor parameter mu_T per scale",
            valid_min=0.0,
            description="[R(q) dgamma^2/(E*^2 dr^3)]^(1/3); >> 1: JKR limit, << 1: DMT limit",
        ),
        "w_eff": VarSpec(
            (),
            "J m-2",
            "Persson-Tosatti stickiness w_eff = dgamma A*/A0 - U_el,full/A0",
            description="> 0: the interface is sticky (physics.md §2.5)",
        ),
        "pull_off_stress": VarSpec(
            (),
            "Pa",
            "pull-off stress",
            valid_min=0.0,
            description="-p0 at which A(zeta_max)/A0 = pull_off_area (root of the area over the "
            "load); pull_off_area = 0: sigma_a(zeta=1); 0 when even p0 = 0 leaves less contact",
        ),
    }

    def __init__(self, **params: Any) -> None:
        super().__init__(**params)
        p = self._params
        _check_scalar("work_of_adhesion", p["work_of_adhesion"], self.parameters, "J/m^2")
        _check_scalar("c_a", p["c_a"], self.parameters, "dimensionless")
        _check_scalar("range", p["range"], self.parameters, "m")
        _check_scalar("pull_off_area", p["pull_off_area"], self.parameters, "dimensionless")
        table, tz = p["sigma_a"], p["sigma_a_zeta"]
        if (table is None) != (tz is None) and not (tz is None and np.size(table) == 1):
            raise ValueError(
                "boundary.sigma_a [Pa] and boundary.sigma_a_zeta [1] go together (a table "
                "sigma_a(zeta)); a single sigma_a value without sigma_a_zeta is a constant wall"
            )
        self._table = None
        if table is not None:
            zeta = [1.0] if tz is None else tz
            self._table = TableLaw(zeta, table)
            p["sigma_a"] = self._table.sigma.copy()
            p["sigma_a_zeta"] = None if tz is None else self._table.zeta.copy()

    # -- detachment law --------------------------------------------------------------------
    def _model(self, ctx: SceneContext) -> ModelLaw:
        p = self._params
        return ModelLaw(ctx.psd, ctx.E_star, p["work_of_adhesion"], p["c_a"])

    def sigma_a_start(self, ctx: SceneContext) -> float:
        """sigma_a(zeta = 1) [Pa]: tensile loads must stay above -sigma_a(1)."""
        if self._table is not None:
            return float(self._table.sigma[0])
        scene = self._scene(ctx)
        return self._at(ctx, self._model(ctx), 1.0) if scene is None else scene[1]

    def _scene(self, ctx: SceneContext) -> tuple[tuple[np.ndarray, ...], float, float] | None:
        """What validate() and interpret() read of a scene under the model law, in one
        look-up (cached per spectrum): :meth:`_scales`, sigma_a(1) [Pa] (:meth:`_at`) and
        w_eff [J/m^2] (:func:`stickiness`), each as its own call gives it; None with a table
        or without a spectrum (then each is asked on its own)."""
        if self._table is not None or ctx.psd is None:
            return None
        law = self._model(ctx)
        p = self._params
        key = (ctx.psd, *law._key(), p["range"], ctx.zeta, float(ctx.q_L))

        def compute() -> tuple[tuple[np.ndarray, ...], float, float]:
            work = p["work_of_adhesion"]
            scales = self._scales(ctx)
            return scales, self._at(ctx, law, 1.0), stickiness(ctx.psd, ctx.E_star, work)

        return _SCENE.get(key, compute)

    def _at(self, ctx: SceneContext, law: ModelLaw, zeta: float) -> float:
        """``law([zeta])[0]``, sigma_a [Pa]: from the memoised gamma_eff of :meth:`_scales` when
        ``zeta`` is the first or last output magnification (the same element-wise operations
        on the same values: the same number), else from the law."""
        z = np.asarray(ctx.zeta, dtype=float)
        for i in (0, -1):
            if ctx.psd is not None and z.size and z[i] == zeta:
                gamma = np.maximum(self._scales(ctx)[0][[i]], 0.0)
                q = z[[i]] * float(ctx.psd.q_L)
                return float(detachment_stress(gamma, law.E_star, q, law.c_a)[0])
        return float(law(np.array([zeta]))[0])

    def _scales(self, ctx: SceneContext) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Unclipped gamma_eff [J/m^2], A*/A0 [1], the finer scales' energy [J/m^2] and the
        Tabor parameter [1] at the output magnifications (read-only; cached per spectrum)."""
        p = self._params
        zeta = np.asarray(ctx.zeta, dtype=float)
        work, rng = p["work_of_adhesion"], p["range"]

        def compute() -> tuple[np.ndarray, ...]:
            _, raw, a_star, energy = gamma_effective(ctx.psd, ctx.E_star, work, zeta)
            return raw, a_star, energy, tabor_parameter(ctx.psd, ctx.E_star, work, rng, zeta)

        key = (ctx.psd, float(ctx.E_star), work, rng, zeta)
        return _SCALES.get(key, compute)

    def validate(self, ctx: SceneContext) -> None:
        """Table coverage, p0 > -sigma_a(1), and the Tabor-parameter warning."""
        if self._table is not None:
            self._table.check_range(ctx.zeta_max)
        scene = self._scene(ctx)
        s1 = self.sigma_a_start(ctx) if scene is None else scene[1]
        bad = ctx.p0[ctx.p0 <= -s1]
        if bad.size:
            raise ValueError(
                f"load.p0 = {float(bad[0]):g} Pa is outside the allowed range p0 > "
                f"-sigma_a(zeta=1) = {0.0 - s1:g} Pa (the contact would detach at once"
                + (
                    "; gamma_eff(1) <= 0: roughness destroys macroscopic adhesion)"
                    if s1 == 0
                    else ")"
                )
            )
        work = self._params["work_of_adhesion"]
        if work > 0 and ctx.psd is not None:
            mu = (self._scales(ctx) if scene is None else scene[0])[3]
            warn_outside_limit(float(mu[-1]), "jkr", stacklevel=4)

    def wall(self, ctx: SceneContext, clock: DiffusionClock) -> Wall:
        """The adhesive wall for a clock (the same for every load: the pipeline asks once,
        ``FastPaths(shared_walls=True)``, and the engine solves the loads together)."""
        from xpersson.engine import Wall

        if self._table is not None:
            if self._table.is_constant:
                return Wall.absorbing(-float(self._table.sigma[0]))
            sig, key = self._table.table_and_key(clock.tau_of_zeta)
        else:
            law = self._model(ctx)
            if law.is_constant(ctx.zeta_max, lambda: self._at(ctx, law, ctx.zeta_max)):
                return Wall.absorbing(0.0)
            sig, key = law.table_and_key(clock)
        # equal content, equal walls: the loads are solved together on either path
        onsets = onset_times(sig)
        # sigma_a = 0 up to the first onset (gamma_eff <= 0 there): the wall rests at p = 0
        still = float(onsets[0]) if onsets.size and starts_at_zero(sig) else 0.0
        pos = DetachmentWall(sig, key=key)
        table = pos.wall_table() if fast_paths_on() else None  # (FastPaths(wall_tables=True))
        return Wall.absorbing(pos, breakpoints=onsets, still_until=still, table=table)

    def walls(self, ctx: SceneContext, p0: float, clock: DiffusionClock) -> tuple[Wall, None]:
        """Absorbing wall at ``-sigma_a(zeta(tau))`` [Pa]; no upper wall."""
        return self.wall(ctx, clock), None

    # -- outputs ---------------------------------------------------------------------------
    def interpret(
        self, ctx: SceneContext, results: list[EngineResult]
    ) -> dict[str, tuple[tuple[str, ...], np.ndarray]]:
        """Detached area, contact stress, identity residual, sigma_a, gamma_eff, pull-off (which
        solves the scene's wall on the run's clock, ``ctx.clock``, when ``pull_off_area > 0``)."""
        zeta = np.asarray(ctx.zeta, dtype=float)
        p0 = np.asarray(ctx.p0, dtype=float)
        detached = _stack(results, "absorbed_lower", zeta.size)
        load = _stack(results, "load", zeta.size)
        balance = _stack(results, "load_balance", zeta.size)
        sigma = np.maximum(-np.asarray(_row0(results, "wall_lower"), dtype=float), 0.0)
        q = zeta * ctx.q_L
        p = self._params
        scene = self._scene(ctx)
        scales = self._scales(ctx) if scene is None else scene[0]
        raw, a_star, energy, mu = (a.copy() for a in scales)  # copies: data of ds
        if scene is None:
            w_eff = stickiness(ctx.psd, ctx.E_star, p["work_of_adhesion"])
            s1 = self.sigma_a_start(ctx)
        else:
            w_eff, s1 = scene[2], scene[1]
        tau_end = float(_row0(results, "tau")[-1])
        if self._table is None:
            gamma = np.maximum(raw, 0.0)
        else:
            gamma = sigma**2 / (p["c_a"] * ctx.E_star * q)
        return {
            "detached_fraction": (_PZ, np.clip(detached, 0.0, 1.0)),
            "contact_stress": (_PZ, load),
            "detached_stress": (_PZ, np.maximum(load - p0[:, None], 0.0)),
            "load_identity_residual": (("p0",), np.max(np.abs(balance), axis=1)),
            "sigma_a": (("zeta",), sigma),
            "gamma_eff": (("zeta",), gamma),
            "true_area_ratio": (("zeta",), a_star),
            "finer_scale_energy": (("zeta",), energy),
            "tabor_parameter": (("zeta",), mu),
            "w_eff": ((), np.asarray(w_eff)),
            "pull_off_stress": ((), np.asarray(self._pull_off(ctx, tau_end, ctx.clock, s1))),
        }

    def pull_off(
        self, ctx: SceneContext, tau_end: float, clock: DiffusionClock | None = None
    ) -> float:
        """Pull-off stress [Pa] (documented policy).

        ``pull_off_area = 0`` (default): the most tensile load that keeps contact at zeta_max.
        The heat equation with an absorbing wall keeps a positive mass at every finite tau, so
        ``A(zeta_max)/A0 > 0`` for every ``p0 > -sigma_a(1)``: the pull-off stress is
        ``sigma_a(zeta = 1)`` exactly (no solve).

        ``pull_off_area = a > 0``: ``-p0`` at which ``A(zeta_max)/A0 = a``, bracketed on
        ``p0 = -sigma_a(1) (1 - 10^-k)`` and polished by ``scipy.optimize.brentq`` with the core
        engine at the final diffusion time ``tau_end`` [Pa^2] (``rtol = max(rtol, 1e-4)``;
        relative accuracy about 1e-6 of sigma_a(1)); 0 when even ``p0 = 0`` leaves less contact.
        That needs the scene's wall, hence its diffusion ``clock``.

        Raises
        ------
        ValueError
            For ``pull_off_area > 0`` without a ``clock``.
        """
        return self._pull_off(ctx, tau_end, clock, self.sigma_a_start(ctx))

    def _pull_off(
        self, ctx: SceneContext, tau_end: float, clock: DiffusionClock | None, s1: float
    ) -> float:
        """:meth:`pull_off` given sigma_a(1) [Pa] ``s1`` (:meth:`sigma_a_start`)."""
        target = self._params["pull_off_area"]
        if s1 <= 0:
            return 0.0
        if target == 0.0 or tau_end <= 0:
            return s1
        if clock is None:
            raise ValueError(
                f"boundary 'jkr': the pull-off at pull_off_area = {target:g} solves the scene's "
                "detachment wall, which needs its diffusion clock: pass clock= (interpret() "
                "passes ctx.clock, the clock walls() received, which the pipeline sets)"
            )
        from scipy.optimize import brentq

        from xpersson.engine import solve

        wall = self.wall(ctx, clock)
        rtol = max(ctx.rtol, 1e-4)

        def excess(load: float) -> float:
            res = solve([tau_end], load, wall, rtol=rtol, method=ctx.method)
            return float(res.area[-1]) - target

        hi, f_hi = 0.0, excess(0.0)
        if f_hi <= 0:
            return 0.0
        for k in range(1, 13):
            lo = -s1 * (1.0 - 10.0**-k)
            if excess(lo) < 0:
                return -brentq(excess, lo, hi, xtol=1e-6 * s1, rtol=1e-10)
            hi = lo
        return -hi


def _check_scalar(name: str, value: Any, specs: dict[str, ParamSpec], unit: str) -> None:
    spec = specs[name]
    if (
        not isinstance(value, int | float)
        or isinstance(value, bool)
        or not math.isfinite(value)
        or not spec.in_bounds(float(value))
    ):
        raise ValueError(
            f"boundary.{name} = {value!r} [{unit}] is outside the allowed range {spec.range_text()}"
        )


def _row0(results: Any, name: str) -> Any:
    """Field ``name`` of the first load: a row of the batch's stacked array when it has one
    (no per-load result built), else of ``results[0]``."""
    stacked = getattr(results, name, None) if not isinstance(results, list | tuple) else None
    if isinstance(stacked, np.ndarray) and stacked.ndim == 2 and len(stacked) == len(results):
        return stacked[0]
    return getattr(results[0], name)


def _stack(results: Any, name: str, n_zeta: int) -> np.ndarray:
    """Field ``name`` of every load, ``(n_load, n_zeta)`` (a fresh float array)."""
    stacked = getattr(results, name, None) if not isinstance(results, list | tuple) else None
    if isinstance(stacked, np.ndarray) and stacked.shape == (len(results), n_zeta):
        return np.array(stacked, dtype=float)  # an EngineBatch's stacked array (a copy)
    rows = [np.asarray(getattr(r, name), dtype=float).reshape(-1) for r in results]
    for row in rows:
        if row.size != n_zeta:
            raise ValueError(
                f"engine result field {name!r} has {row.size} values, expected one per output "
                f"magnification ({n_zeta})"
            )
    return np.vstack(rows)
