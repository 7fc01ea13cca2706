"""``plastic_scale_dependent``: hardness increasing with magnification (Lambert 2025).

The yield wall moves, ``p = Y(zeta)``, with ``Y`` non-decreasing (force conservation). At the
moving wall ``P(Y) != 0``; it is fixed by the closure of V. Lambert (physics.md §3.2,
https://github.com/vlambert/ScaleDependentPlasticity)

    A_pl(zeta) = f(zeta) P(Y(zeta), zeta) / Y'(zeta)   <=>   P(Y) = A_pl dY/dtau,

with ``dY/dtau = Y'(zeta) / f(zeta)`` in diffusion time ``tau`` [Pa^2]. Together with the
diffusion equation it conserves the total area (A_el + A_pl + A_non = 1) and the total force
(``int_0^Y p P dp + Y(zeta) A_pl = p0``). For a constant hardness (``n = 0`` or a constant
table) it reduces to the fixed absorbing wall of ``plastic``; that case is dispatched to the
exact two-wall solution.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from xpersson.plugins import Boundary, FastPaths, ParamSpec

from ._hardness import HardnessLaw, PowerLaw, load_table, table_law
from ._outputs import AREA_OUTPUTS, assemble, stack
from .plastic import check_below_hardness

if TYPE_CHECKING:  # pragma: no cover
    from xpersson.engine import EngineResult, Wall
    from xpersson.plugins import DiffusionClock, SceneContext

__all__ = ["ScaleDependentPlasticBoundary", "YieldWallLaw", "kink_times"]


class YieldWallLaw:
    """Position ``Y(zeta(tau))`` [Pa] or speed ``dY/dtau = Y'(zeta)/f(zeta)`` [1/Pa] in tau.

    A picklable callable ``tau [Pa^2] -> value`` (scalar in, float out; array in, array out).

    Parameters
    ----------
    law : HardnessLaw
        The hardness law Y(zeta).
    clock : DiffusionClock
        Maps tau to zeta and gives f(zeta) [Pa^2].
    derivative : bool
        False for the position, True for dY/dtau.
    """

    def __init__(self, law: HardnessLaw, clock: DiffusionClock, derivative: bool) -> None:
        self.law = law
        self.clock = clock
        self.derivative = derivative

    def __eq__(self, other: object) -> bool:
        # equal laws on one clock are one wall: the engine solves such loads together
        return (
            isinstance(other, YieldWallLaw)
            and other.law is self.law
            and other.clock is self.clock
            and other.derivative == self.derivative
        )

    def __hash__(self) -> int:
        # consistent with __eq__ (the same law object has the same type): the engine groups
        # loads by their walls in a dict
        return hash((type(self.law).__qualname__, self.derivative))

    def __call__(self, tau: np.ndarray | float) -> np.ndarray | float:
        val = self._evaluate(np.asarray(tau, dtype=float))
        return float(val) if val.ndim == 0 else val

    def _evaluate(self, t: np.ndarray) -> np.ndarray:
        # the inverse clock may overshoot zeta_max by round-off, where f drops to 0 (q > q_1)
        z = np.clip(np.asarray(self.clock.zeta_of_tau(t), dtype=float), 1.0, self.clock.zeta_max)
        if self.derivative:
            f = np.asarray(self.clock.f(z), dtype=float)
            if np.any(~(f > 0)):
                raise ValueError(
                    "plastic_scale_dependent: the diffusion coefficient f(zeta) [Pa^2] must be "
                    "> 0 on [1, zeta_max] for a moving yield wall (dY/dtau = Y'(zeta)/f(zeta))"
                )
            val = self.law.dY(z) / f
        else:
            val = self.law.Y(z)
        return np.asarray(val, dtype=float).reshape(t.shape)


def kink_times(law: HardnessLaw, clock: DiffusionClock) -> tuple[float, ...]:
    """Diffusion times [Pa^2] where the yield wall's speed ``dY/dtau = Y'(zeta) / f(zeta)``
    has a kink: the clock's kinks of ``f`` (the spectrum's nodes, e.g. a roll-off knee) and
    the law's kinks of ``Y'`` inside ``(1, zeta_max)`` (the engine makes them step
    boundaries, see :class:`xpersson.engine.Wall`)."""
    z = np.unique(np.asarray([*clock.kinks, *law.kinks], dtype=float))
    z = z[(z > 1.0) & (z < clock.zeta_max)]
    if z.size == 0:
        return ()
    return tuple(float(t) for t in np.atleast_1d(clock.tau_of_zeta(z)) if t > 0)


class ScaleDependentPlasticBoundary(Boundary):
    """Elastoplastic contact with a magnification-dependent hardness Y(zeta) [Pa].

    ``Y(zeta) = Y1 zeta**n`` (``Y1`` [Pa] > every p0, ``n`` >= 0), or a two-column table
    ``zeta, Y`` (``table``, Y in ``table_unit``) interpolated monotonically in log-log. Walls:
    absorbing at ``p = 0`` and Lambert's yield closure at ``p = Y(zeta)``. Outputs as for
    ``plastic``; ``yield_stress`` is Y(zeta) and the plastic area carries Y(zeta).

    Parameters
    ----------
    Y1 : float, optional
        Hardness at zeta = 1 [Pa] for the power law.
    n : float
        Power-law exponent [1], >= 0 (0: constant hardness).
    table : str, optional
        Path of a two-column text file ``zeta  Y`` (instead of ``Y1``, ``n``).
    table_unit : str
        Pressure unit of the Y column of ``table`` (default ``"Pa"``).
    """

    summary = "Elastoplastic contact with scale-dependent hardness Y(zeta) (Lambert 2025 closure)"
    references = (
        "https://github.com/vlambert/ScaleDependentPlasticity",
        "10.1063/1.1388626",
    )
    parameters = {
        "Y1": ParamSpec(
            unit="Pa",
            default=None,
            bounds=(0.0, None),
            inclusive=(False, True),
            description="hardness at zeta = 1 of the power law Y1 zeta**n; must exceed every p0",
            sweepable=True,
            example=3.0e6,
        ),
        "n": ParamSpec(
            unit="1",
            default=0.0,
            bounds=(0.0, None),
            inclusive=(True, True),
            description="exponent of the power law Y1 zeta**n (>= 0; 0 = constant hardness)",
            sweepable=True,
        ),
        "table": ParamSpec(
            unit="1",
            kind="path",
            default=None,
            description="two-column text file 'zeta Y' (non-decreasing Y) instead of Y1, n",
        ),
        "table_unit": ParamSpec(
            unit="1",
            kind="string",
            default="Pa",
            description="pressure unit of the Y column of table (e.g. 'GPa')",
        ),
        "table_zeta": ParamSpec(
            unit="1", default=None, array=True, description="the table inline: zeta (with table_Y)"
        ),
        "table_Y": ParamSpec(
            unit="Pa", default=None, array=True, description="the table inline: Y (with table_zeta)"
        ),
    }
    outputs = dict(AREA_OUTPUTS)
    # declarations read by analyses (xpersson.plugins.Boundary)
    traits = frozenset({"repulsive"})
    contact_area = ("elastic_area_fraction", "plastic_area_fraction")
    elastic_area = "elastic_area_fraction"
    elastic_area_complement = ("plastic_area_fraction", "non_contact_area_fraction")
    #: Same walls for every load (validate() checks every p0): the pipeline asks once.
    fast_paths = FastPaths(shared_walls=True, reused=True)

    def __init__(self, **params: Any) -> None:
        super().__init__(**params)
        y1, n, table = self._params["Y1"], self._params["n"], self._params["table"]
        inline = self._inline()
        if inline is not None and table is not None:
            raise ValueError("boundary: give either table or table_zeta/table_Y, not both")
        tabulated = table is not None or inline is not None
        if tabulated and y1 is not None:
            raise ValueError("boundary: give either Y1 [Pa] (with n) or table, not both")
        if not tabulated:
            if y1 is None:
                raise ValueError(
                    "boundary.Y1 [Pa] is required (hardness at zeta = 1 of Y1 zeta**n, "
                    "allowed range Y1 > max p0), or give boundary.table"
                )
            for name in ("Y1", "n"):
                val = self._params[name]
                spec = self.parameters[name]
                if (
                    not isinstance(val, int | float)
                    or isinstance(val, bool)
                    or not spec.in_bounds(float(val))
                    or not np.isfinite(val)
                ):
                    unit = "Pa" if name == "Y1" else "dimensionless"
                    extra = (
                        " (a decreasing hardness violates force conservation)"
                        if name == "n"
                        else " and above every p0"
                    )
                    raise ValueError(
                        f"boundary.{name} = {val!r} [{unit}] outside the allowed range "
                        f"{spec.range_text()}{extra}"
                    )
            self._params["Y1"], self._params["n"] = float(y1), float(n)
            self._law: HardnessLaw = PowerLaw(float(y1), float(n))
        elif inline is not None:
            self._law = inline
        else:
            self._law = load_table(table, str(self._params["table_unit"]))

    def _inline(self) -> HardnessLaw | None:
        """The table given inline (``table_zeta``, ``table_Y`` [Pa]), checked; or None."""
        zeta, Y = self._params["table_zeta"], self._params["table_Y"]
        if zeta is None and Y is None:
            return None
        if zeta is None or Y is None:
            raise ValueError("boundary.table_zeta and table_Y [Pa] must be given together")
        return table_law(zeta, Y, "boundary.table_zeta/table_Y")

    def archived_params(self) -> dict[str, Any]:
        """The parameters with a table read from its file given inline (the archive's scene:
        no file path in it; the archive rebuilds this boundary bit for bit)."""
        out = dict(self._params)
        if out["table"] is not None:
            out["table_zeta"], out["table_Y"] = self._law.zeta, self._law.values
            out["table"], out["table_unit"] = None, "Pa"
        return out

    def __getstate__(self) -> dict[str, Any]:
        return dict(self.__dict__)

    @property
    def law(self) -> HardnessLaw:
        """The hardness law Y(zeta) [Pa]."""
        return self._law

    def validate(self, ctx: SceneContext) -> None:
        """Refuse Y(1) <= max p0 and tables that do not cover the output magnifications."""
        name = "Y1" if self._params["Y1"] is not None else "table"
        y_start = float(self._law.Y(np.asarray(1.0)))
        check_below_hardness(name, y_start, ctx.p0, "hardness at zeta = 1")
        self._law.check_range(float(np.max(ctx.zeta)))

    def walls(self, ctx: SceneContext, p0: float, clock: DiffusionClock) -> tuple[Wall, Wall]:
        """Absorbing wall at 0; yield-closure wall at Y(zeta(tau)) (fixed wall if constant)."""
        from xpersson.engine import Wall

        if self._law.is_constant:
            return Wall.absorbing(0.0), Wall.absorbing(float(self._law.Y(np.asarray(1.0))))
        return Wall.absorbing(0.0), Wall.yield_closure(
            position=YieldWallLaw(self._law, clock, derivative=False),
            dposition=YieldWallLaw(self._law, clock, derivative=True),
            kinks=kink_times(self._law, clock),
        )

    def interpret(
        self, ctx: SceneContext, results: list[EngineResult]
    ) -> dict[str, tuple[tuple[str, ...], np.ndarray]]:
        """Area fractions and load shares per (p0, zeta); the plastic area carries Y(zeta)."""
        zeta = np.asarray(ctx.zeta, dtype=float)
        eng = stack(results, zeta.size)
        return assemble(
            ctx, self._law.Y(zeta), eng["elastic"], eng["plastic"], eng["non_contact"], eng["load"]
        )
