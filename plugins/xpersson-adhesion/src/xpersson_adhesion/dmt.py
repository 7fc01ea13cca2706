"""``dmt``: repulsive contact plus attraction in the gaps (physics.md §2.3, DMT scheme).

The contact is Persson's elastic contact (absorbing wall at ``p = 0``) under the repulsive
nominal pressure ``p_rep = p0 + p_att``; the attraction ``p_att = int_0^inf sigma(u) rho(u) du``
integrates a traction-gap law (:mod:`._traction`) over the gap distribution ``rho`` of that
solved contact (:func:`xpersson.physics.interface.detachment`, physics.md §5.5a). ``p_rep`` is
solved self-consistently, ``g(p_rep) = p_rep - p0 - p_att(p_rep) = 0``, to the scene's ``rtol``
(the largest root, i.e. the branch reached from high loads).

``p_att(p_rep)`` does not depend on the load: the boundary solves all loads of a scene at once
(:mod:`._dmt_batch`): exact evaluations of ``p_att`` on load-independent pressures (powers of
two, then Chebyshev points of the octave holding a root), one vectorised call for many
pressures, a root per load on the octave's interpolant, and an exact check at every root
(Brent's method on the exact map where the check fails). A load's result does not depend on
the loads solved with it. :func:`._dmt_reference.solve_dmt` is the per-load reference (Brent's
method on the engine's map, as before the batched path; used by the tests).

Each evaluation of ``p_att`` solves the elastic contact at the trial ``p_rep`` (the core
engine's exact path for ``Wall.absorbing(0.0)``: ``A = erf(p_rep / (2 sqrt(tau)))``) on a
dense magnification grid. The final contact
is handed to the engine as the elastic problem shifted by ``p_att``: the delta at ``p0`` and the
absorbing wall at ``p = -p_att`` (translation invariance), so that the core's ``area_fraction``
is the contact area at ``p_rep`` and its pressure axis is the local repulsive stress minus the
(mean-field) attraction ``p_att``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from xpersson.cache import Cache
from xpersson.plugins import Boundary, FastPaths, ParamSpec, VarSpec

from ._curves import curve_grid, increasing
from ._dmt_batch import AttractionMap, solve_loads
from ._tabor import tabor_parameter, warn_outside_limit
from ._traction import LAWS
from .jkr import ADHESION_PARAMETERS, _check_scalar, stickiness

if TYPE_CHECKING:  # pragma: no cover
    from xpersson.engine import EngineResult, Wall
    from xpersson.plugins import DiffusionClock, SceneContext

__all__ = ["DMTAccuracyWarning", "DMTBoundary", "DMTState"]


class DMTAccuracyWarning(UserWarning):
    """The attraction in the gaps depends on the sampling of the area curve (see
    ``p_att_discretization_error``)."""


@dataclass(frozen=True)
class DMTState:
    """Self-consistent DMT state of one load (SI units).

    Attributes
    ----------
    p0, p_rep, p_att : float
        Nominal, repulsive and attractive nominal stresses [Pa], ``p_rep = p0 + p_att``.
    residual : float
        ``|p_rep - p0 - p_att(p_rep)| / max(|p0|, p_rep)`` at the solution [1].
    iterations : int
        Evaluations of the fixed-point map ``p_att(p_rep)``.
    mean_gap : float
        Persson's mean separation at ``p_rep`` [m].
    mass_error : float
        Quadrature diagnostic ``int rho du - (1 - A)`` of the gap integral [1].
    discretization_error : float
        ``|p_att(half density) - p_att| / p_att`` at ``p_rep``: the sensitivity of the gap
        distribution's small-gap tail to the area curve's magnification grid [1].
    area : float
        Contact area fraction at the largest magnification [1].
    """

    p0: float
    p_rep: float
    p_att: float
    residual: float
    iterations: int
    mean_gap: float
    mass_error: float
    area: float
    discretization_error: float = 0.0


_STATES = Cache(
    "adhesion.dmt_states",
    scope="solve",
    maxsize=8,
    doc="dmt: the self-consistent states of a scene's loads on a clock's area curves",
)


class DMTBoundary(Boundary):
    """DMT adhesion: elastic contact at ``p_rep = p0 + p_att``, attraction in the gaps.

    Parameters
    ----------
    work_of_adhesion : float
        Work of adhesion ``dgamma`` [J/m^2], >= 0 (the integral of the law).
    range : float
        Range ``dr`` of the law [m], > 0.
    law : {"dugdale", "lj93", "exponential"}
        Traction-gap law (see :mod:`xpersson_adhesion._traction`).
    """

    summary = "DMT adhesion: elastic contact at p0 + p_att, traction-gap law over the gaps"
    references = (
        "10.1063/1.4895789",
        "10.1016/0021-9797(75)90018-1",
        "10.1016/j.surfrep.2006.04.001",
    )
    tensile_loads = True
    #: an instance gives what its parameters say (its tables: caches keyed on content)
    fast_paths = FastPaths(reused=True)
    parameters = {
        **ADHESION_PARAMETERS,
        "law": ParamSpec(
            unit="1",
            kind="choice",
            choices=LAWS,
            default="lj93",
            description="attractive traction-gap law (integral = work_of_adhesion)",
        ),
    }
    outputs = {
        "p_rep": VarSpec(
            ("p0",), "Pa", "repulsive nominal pressure p_rep = p0 + p_att", valid_min=0.0
        ),
        "p_att": VarSpec(
            ("p0",),
            "Pa",
            "attractive nominal stress in the gaps",
            valid_min=0.0,
            description="int_0^inf sigma(u) rho(u) du over the gap distribution",
        ),
        "mean_gap": VarSpec(
            ("p0",),
            "m",
            "mean interfacial separation at p_rep",
            valid_min=0.0,
            description="Persson's u(p_rep) of the solved contact (§5.2)",
        ),
        "dmt_residual": VarSpec(
            ("p0",), "1", "relative residual of p_rep = p0 + p_att(p_rep)", valid_min=0.0
        ),
        "dmt_iterations": VarSpec(
            ("p0",),
            "1",
            "exact evaluations of p_att the root rests on",
            valid_min=0.0,
            description="shared ones included (the scan, the octave's interpolant, the check at "
            "the root); 1 without adhesion (the check at p0)",
        ),
        "p_att_discretization_error": VarSpec(
            ("p0",),
            "1",
            "relative change of p_att on a magnification grid of half density",
            valid_min=0.0,
            description="sensitivity of the small-gap tail of the gap distribution to the "
            "area curve's sampling; a DMTAccuracyWarning is issued above 0.05",
        ),
        "gap_quadrature_error": VarSpec(
            ("p0",),
            "1",
            "mass error of the gap-integral quadrature",
            description="int rho du - (1 - A) on the rule used for p_att (0: closed form)",
        ),
        "tabor_parameter": VarSpec(("zeta",), "1", "Tabor parameter mu_T per scale", valid_min=0.0),
        "w_eff": VarSpec((), "J m-2", "Persson-Tosatti stickiness w_eff"),
    }

    def __init__(self, **params: Any) -> None:
        super().__init__(**params)
        _check_scalar(
            "work_of_adhesion", self._params["work_of_adhesion"], self.parameters, "J/m^2"
        )
        _check_scalar("range", self._params["range"], self.parameters, "m")
        if self._params["law"] not in LAWS:
            raise ValueError(f"boundary.law = {self._params['law']!r}: one of {', '.join(LAWS)}")

    def validate(self, ctx: SceneContext) -> None:
        """The Tabor-parameter warning (tensile loads are checked when solved)."""
        work = self._params["work_of_adhesion"]
        if work > 0 and ctx.psd is not None:
            mu = tabor_parameter(ctx.psd, ctx.E_star, work, self._params["range"], ctx.zeta)
            warn_outside_limit(float(mu[-1]), "dmt", stacklevel=4)

    def state(self, ctx: SceneContext, p0: float, clock: DiffusionClock) -> DMTState:
        """The self-consistent state of load ``p0`` [Pa] on ``clock``.

        Every load of ``ctx.p0`` (and ``p0``) is solved at once, sharing the exact evaluations
        of ``p_att`` (:func:`._dmt_batch.solve_loads`; the result of a load does not depend on
        the others), kept for the solve (cache ``"adhesion.dmt_states"``).
        """
        loads = tuple(dict.fromkeys([float(q) for q in np.atleast_1d(ctx.p0)] + [float(p0)]))
        return self._states(ctx, clock, loads)[float(p0)]

    def _states(
        self, ctx: SceneContext, clock: DiffusionClock, loads: tuple[float, ...]
    ) -> dict[float, DMTState]:
        """The states of ``loads`` [Pa], keyed on the scene's content and the clock's samples."""
        p = self._params
        zeta = np.asarray(ctx.zeta, dtype=float)
        curves = tuple(
            increasing(z, np.asarray(clock.tau_of_zeta(z), dtype=float))
            for z in (curve_grid(zeta), curve_grid(zeta, per_decade=16))
        )
        scene = (p["law"], p["work_of_adhesion"], p["range"], float(ctx.rtol))

        def solve() -> dict[float, DMTState]:
            amap = AttractionMap(ctx.psd, ctx.E_star, curves, *scene)  # type: ignore[arg-type]
            cols = solve_loads(amap, np.array(loads))
            out = {}
            for i, q in enumerate(loads):
                p_rep = float(cols["p_rep"][i])
                out[q] = DMTState(
                    q,
                    p_rep,
                    p_rep - q,
                    float(cols["residual"][i]),
                    int(cols["iterations"][i]),
                    float(cols["mean_gap"][i]),
                    float(cols["mass_error"][i]),
                    float(cols["area"][i]),
                    float(cols["discretization_error"][i]),
                )
            return out

        return _STATES.get((ctx.psd, float(ctx.E_star), curves, scene, loads), solve)

    def walls(self, ctx: SceneContext, p0: float, clock: DiffusionClock) -> tuple[Wall, None]:
        """Absorbing wall at ``-p_att`` [Pa]: the elastic contact at ``p_rep`` shifted."""
        from xpersson.engine import Wall

        st = self.state(ctx, p0, clock)
        return Wall.absorbing(-st.p_att), None

    def interpret(
        self, ctx: SceneContext, results: list[EngineResult]
    ) -> dict[str, tuple[tuple[str, ...], np.ndarray]]:
        """p_rep, p_att, mean gap and the fixed-point diagnostics per load (the states that
        :meth:`walls` solved, on the run's clock ``ctx.clock``)."""
        if ctx.clock is None:
            raise ValueError(
                "boundary 'dmt': interpret() reads the states solved on the scene's diffusion "
                "clock, ctx.clock, which the pipeline sets for interpret(); got a context "
                "without a clock"
            )
        loads = tuple(dict.fromkeys(float(q) for q in np.atleast_1d(ctx.p0)))
        found = self._states(ctx, ctx.clock, loads)
        states = [found[float(p0)] for p0 in ctx.p0]
        p = self._params

        def col(name: str) -> np.ndarray:
            return np.array([getattr(s, name) for s in states], dtype=float)

        disc = col("discretization_error")
        if np.any(disc > 0.05):
            import warnings

            warnings.warn(
                f"boundary 'dmt': p_att changes by up to {100 * float(np.max(disc)):.0f}% when "
                "the area curve's magnification grid is halved (the gap distribution's small-gap "
                "tail is not resolved for this range); see p_att_discretization_error",
                DMTAccuracyWarning,
                stacklevel=4,
            )
        mu = tabor_parameter(ctx.psd, ctx.E_star, p["work_of_adhesion"], p["range"], ctx.zeta)
        return {
            "p_rep": (("p0",), col("p_rep")),
            "p_att": (("p0",), np.maximum(col("p_att"), 0.0)),
            "mean_gap": (("p0",), np.maximum(col("mean_gap"), 0.0)),
            "dmt_residual": (("p0",), col("residual")),
            "dmt_iterations": (("p0",), col("iterations")),
            "p_att_discretization_error": (("p0",), col("discretization_error")),
            "gap_quadrature_error": (("p0",), col("mass_error")),
            "tabor_parameter": (("zeta",), mu),
            "w_eff": ((), np.asarray(stickiness(ctx.psd, ctx.E_star, p["work_of_adhesion"]))),
        }
