"""``plastic``: constant penetration hardness, absorbing walls at 0 and sigma_Y (physics.md §3.1).

Contact spots whose pressure reaches the penetration hardness ``sigma_Y`` yield: the probability
reaching ``p = sigma_Y`` is absorbed and counted as plastic contact area, which carries the
pressure ``sigma_Y`` at every larger magnification. With the diffusion time ``tau`` [Pa^2] the
problem is the heat equation between two absorbing walls, solved exactly by the engine's
``"auto"`` method (image / sine series); this plugin only sets the walls and gives the absorbed
fluxes their meaning.
"""

from __future__ import annotations

import warnings
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from xpersson.plugins import Boundary, FastPaths, ParamSpec, VarSpec

from ._outputs import AREA_OUTPUTS, assemble, stack
from ._series import three_gaussian_areas

if TYPE_CHECKING:  # pragma: no cover
    from xpersson.engine import EngineResult, Wall
    from xpersson.plugins import DiffusionClock, SceneContext

__all__ = ["PlasticBoundary", "ApproximationValidityWarning", "check_below_hardness"]


def _exact(tau: np.ndarray, p0: np.ndarray, y: float) -> tuple[np.ndarray, ...]:
    """Exact (elastic, plastic, non-contact) fractions from ``xpersson.engine.exact``."""
    from xpersson.engine import exact

    area, lower, upper = exact.two_wall(tau, p0, 0.0, y)
    return area, upper, lower


class ApproximationValidityWarning(UserWarning):
    """A named approximation is used outside its range of validity."""


def check_below_hardness(name: str, hardness: float, p0: np.ndarray, what: str) -> None:
    """Raise ``ValueError`` unless every nominal pressure lies below the hardness.

    Parameters
    ----------
    name : str
        Scene parameter name (``"sigma_Y"``, ``"Y1"``), reported as ``boundary.<name>``.
    hardness : float
        Its value [Pa].
    p0 : numpy.ndarray
        Nominal pressures [Pa].
    what : str
        What the parameter is, for the message.
    """
    p_max = float(np.max(np.asarray(p0, dtype=float), initial=0.0))
    if not (np.isfinite(hardness) and hardness > p_max):
        raise ValueError(
            f"boundary.{name} = {hardness:g} Pa ({what}) must exceed the largest nominal "
            f"pressure: allowed range {name} > {p_max:g} Pa (max p0). A load at or above the "
            "hardness is fully plastic from the first magnification."
        )


class PlasticBoundary(Boundary):
    """Elastoplastic contact with a constant penetration hardness ``sigma_Y`` [Pa].

    Walls: absorbing at ``p = 0`` (loss of contact) and at ``p = sigma_Y`` (yield). Outputs per
    (p0, zeta): elastic, plastic, non-contact and total contact area fractions, the load shares,
    the force-balance residual and the deviation from the exact two-wall series.

    Parameters
    ----------
    sigma_Y : float
        Penetration hardness [Pa], larger than every nominal pressure p0.
    approximation : {"none", "three_gaussian"}
        ``"none"``: the engine's exact/numerical solution. ``"three_gaussian"``: the truncation
        ``N(p;p0) - N(p;-p0) - N(p;2 sigma_Y - p0)`` of Xu, Li & Mulvihill (arXiv:2208.02665),
        valid only while ``sqrt(2 tau) << sigma_Y - p0``; a warning is raised where its area
        fractions deviate from the exact series by more than :attr:`approximation_tolerance`.
    """

    summary = "Elastoplastic contact with constant penetration hardness (walls at 0 and sigma_Y)"
    references = (
        "10.1063/1.1388626",
        "10.1016/j.surfrep.2006.04.001",
        "arXiv:2208.02665",
    )
    parameters = {
        "sigma_Y": ParamSpec(
            unit="Pa",
            bounds=(0.0, None),
            inclusive=(False, True),
            description="penetration hardness (yield wall); must exceed every p0",
            sweepable=True,
            example=3.0e6,
        ),
        "approximation": ParamSpec(
            unit="1",
            kind="choice",
            choices=("none", "three_gaussian"),
            default="none",
            description="'none' (exact engine) or 'three_gaussian' (Xu, Li & Mulvihill 2022)",
        ),
    }
    outputs = {
        **AREA_OUTPUTS,
        "exact_series_deviation": VarSpec(
            ("p0", "zeta"),
            "1",
            "deviation of the area fractions from the exact two-wall series",
            description="max of |A - A_exact| over elastic, plastic and non-contact fractions: "
            "the engine's error for approximation='none', the truncation error for "
            "'three_gaussian'",
        ),
    }

    # declarations read by analyses (xpersson.plugins.Boundary)
    traits = frozenset({"repulsive"})
    contact_area = ("elastic_area_fraction", "plastic_area_fraction")
    elastic_area = "elastic_area_fraction"
    elastic_area_complement = ("plastic_area_fraction", "non_contact_area_fraction")
    #: Same walls for every load (validate() checks every p0): the pipeline asks once.
    fast_paths = FastPaths(shared_walls=True, reused=True)

    approximation_tolerance: ClassVar[float] = 1e-3
    """Deviation of the three-Gaussian area fractions from the exact series that is flagged."""

    def __init__(self, **params: Any) -> None:
        super().__init__(**params)
        y = self._params["sigma_Y"]
        spec = self.parameters["sigma_Y"]
        if not isinstance(y, int | float) or isinstance(y, bool) or not spec.in_bounds(float(y)):
            raise ValueError(
                f"boundary.sigma_Y = {y!r}: the penetration hardness must be a number in Pa "
                f"in the range {spec.range_text()} (and above every p0)"
            )
        self._params["sigma_Y"] = float(y)
        approx = self._params["approximation"]
        if approx not in self.parameters["approximation"].choices:
            raise ValueError(
                f"boundary.approximation = {approx!r} must be "
                f"{self.parameters['approximation'].range_text()}"
            )

    @property
    def sigma_Y(self) -> float:
        """Penetration hardness [Pa]."""
        return float(self._params["sigma_Y"])

    def validate(self, ctx: SceneContext) -> None:
        """Refuse loads at or above the hardness (``boundary.sigma_Y`` must exceed max p0)."""
        check_below_hardness("sigma_Y", self.sigma_Y, ctx.p0, "penetration hardness")

    def walls(self, ctx: SceneContext, p0: float, clock: DiffusionClock) -> tuple[Wall, Wall]:
        """Absorbing walls at ``p = 0`` and ``p = sigma_Y`` [Pa] (exact series in the engine)."""
        from xpersson.engine import Wall

        check_below_hardness("sigma_Y", self.sigma_Y, np.asarray([p0]), "penetration hardness")
        return Wall.absorbing(0.0), Wall.absorbing(self.sigma_Y)

    def interpret(
        self, ctx: SceneContext, results: list[EngineResult]
    ) -> dict[str, tuple[tuple[str, ...], np.ndarray]]:
        """Area fractions and load shares per (p0, zeta) from the engine results."""
        y = self.sigma_Y
        n_zeta = int(np.asarray(ctx.zeta).size)
        eng = stack(results, n_zeta)
        ex_el, ex_pl, ex_non = _exact(eng["tau"], np.asarray(ctx.p0, dtype=float)[:, None], y)
        if self._params["approximation"] == "three_gaussian":
            approx = [
                three_gaussian_areas(t, p, y) for t, p in zip(eng["tau"], ctx.p0, strict=True)
            ]
            el, pl, non, load = (
                np.array([getattr(a, k) for a in approx]).reshape(-1, n_zeta)
                for k in ("elastic", "plastic", "non_contact", "load")
            )
        else:
            el, pl, non, load = eng["elastic"], eng["plastic"], eng["non_contact"], eng["load"]
        dev = np.maximum.reduce([np.abs(el - ex_el), np.abs(pl - ex_pl), np.abs(non - ex_non)])
        if self._params["approximation"] == "three_gaussian":
            self._flag_validity(ctx, eng["tau"], dev)
        out = assemble(ctx, np.full(n_zeta, y), el, pl, non, load)
        out["exact_series_deviation"] = (("p0", "zeta"), dev)
        return out

    def _flag_validity(self, ctx: SceneContext, tau: np.ndarray, dev: np.ndarray) -> None:
        bad = dev > self.approximation_tolerance
        if not bad.any():
            return
        i, j = np.argwhere(bad)[0]
        warnings.warn(
            f"approximation='three_gaussian' is outside its validity range "
            f"(sqrt(2 tau) << sigma_Y - p0): at p0 = {ctx.p0[i]:g} Pa it deviates from the exact "
            f"series by {dev[i, j]:.3g} (> {self.approximation_tolerance:g}) from zeta = "
            f"{ctx.zeta[j]:g} on (sqrt(2 tau) = {np.sqrt(2 * tau[i, j]):.3g} Pa, sigma_Y = "
            f"{self.sigma_Y:g} Pa); it violates P(0) = 0 there. Use approximation='none'.",
            ApproximationValidityWarning,
            stacklevel=3,
        )
