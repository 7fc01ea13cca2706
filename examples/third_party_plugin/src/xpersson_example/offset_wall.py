"""A constant-offset absorbing wall: P(-s, zeta) = 0 (constant adhesive stress sigma_a = s).

Persson's adhesive boundary condition (Persson & Tosatti 2001) with a scale-independent detachment
stress: contact patches carry tensile stress down to ``-s`` and detach when they reach it. The
exact image solution (of a linearly moving absorbing wall, diffusion time tau in Pa^2) is

.. math::

    P = N(p; p_0, 2\\tau) - N(p; -2s - p_0, 2\\tau), \\quad
    A/A_0 = \\mathrm{erf}\\left(\\frac{p_0 + s}{2\\sqrt{\\tau}}\\right), \\quad
    \\int p P \\, dp = p_0 + s (1 - A/A_0).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from xpersson.plugins import Boundary, FastPaths, ParamSpec, VarSpec

if TYPE_CHECKING:  # only for type checkers: importing the engine here would slow listing
    from xpersson.engine import Wall
    from xpersson.plugins import DiffusionClock, SceneContext

__all__ = ["OffsetWall"]


class OffsetWall(Boundary):
    """Absorbing wall at p = -s [Pa]: adhesion with a constant detachment stress.

    Parameters
    ----------
    s : float
        Detachment (adhesive) stress sigma_a [Pa], >= 0; ``s = 0`` is the elastic wall.
    """

    api_version = 1
    summary = "absorbing wall at p = -s: adhesion with a constant detachment stress"
    references = ("10.1016/j.surfrep.2006.04.001", "arXiv:cond-mat/0603807")
    parameters = {
        "s": ParamSpec(
            "Pa",
            bounds=(0.0, None),
            example=2e4,
            sweepable=True,
            description="detachment stress sigma_a (wall at p = -s)",
        ),
    }
    outputs = {
        "detached_fraction": VarSpec(
            ("p0", "zeta"),
            "1",
            "fraction of the nominal area detached at the adhesive wall",
            description="probability absorbed at p = -s",
        ),
        "adhesive_load_excess": VarSpec(
            ("p0", "zeta"),
            "Pa",
            "tensile stress left behind by detached patches, s * detached_fraction",
            description="int p P dp - p0 = s (1 - A/A0) for the constant wall",
        ),
    }
    #: The wall p = -s is the same for every load: the pipeline may ask once for all loads
    #: (check_plugin compares that with asking each load).
    fast_paths = FastPaths(shared_walls=True)

    def validate(self, ctx: SceneContext) -> None:
        """Every load must lie above the wall (always true for p0 > 0)."""
        bad = ctx.p0[ctx.p0 <= -self.params["s"]]
        if bad.size:
            raise ValueError(f"load.p0: {bad[0]:g} Pa lies below the wall p = -s")

    def walls(self, ctx: SceneContext, p0: float, clock: DiffusionClock) -> tuple[Wall, None]:
        """One fixed absorbing wall at p = -s [Pa]; no upper wall."""
        from xpersson.engine import Wall  # imported when the plugin runs, not when listed

        return Wall.absorbing(-self.params["s"]), None

    def interpret(self, ctx: SceneContext, results: list[Any]) -> dict[str, Any]:
        """Detached fraction (the absorbed flux) and the load it leaves behind [Pa]."""
        import numpy as np

        detached = np.array([np.asarray(r.absorbed_lower, dtype=float) for r in results])
        return {
            "detached_fraction": (("p0", "zeta"), detached),
            "adhesive_load_excess": (("p0", "zeta"), self.params["s"] * detached),
        }
