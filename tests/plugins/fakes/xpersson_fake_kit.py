"""Plugins for the ``xpersson.testing`` tests: good ones and contract violators."""

from __future__ import annotations

import itertools
from typing import Any

from xpersson.plugins import Boundary, Coefficient, ParamSpec, VarSpec

_counter = itertools.count()


class ShiftedWall(Boundary):
    """Absorbing wall at p = -s with the detached fraction as output."""

    summary = "absorbing wall at p = -s (kit test double)"
    references = ("10.1063/1.1388626",)
    parameters = {"s": ParamSpec("Pa", example=2e4, bounds=(0.0, None), description="offset")}
    outputs = {"detached_fraction": VarSpec(("p0", "zeta"), "1", "detached area fraction")}

    def walls(self, ctx: Any, p0: float, clock: Any) -> tuple[Any, None]:
        from xpersson.engine import Wall

        return Wall.absorbing(-self.params["s"]), None

    def interpret(self, ctx: Any, results: list[Any]) -> dict[str, Any]:
        import numpy as np

        return {
            "detached_fraction": (("p0", "zeta"), np.array([r.absorbed_lower for r in results]))
        }


class FileWall(ShiftedWall):
    """Reads a file (a ``kind="path"`` parameter) but cannot give its table inline."""

    summary = "wall with a file parameter and no archived_params (kit test double)"
    parameters = {
        **ShiftedWall.parameters,
        "table": ParamSpec("1", kind="path", default=None, description="a table file"),
    }


class InlineFileWall(FileWall):
    """:class:`FileWall` with ``archived_params()`` (its parameters as they are)."""

    summary = "wall with a file parameter and archived_params (kit test double)"

    def archived_params(self) -> dict[str, Any]:
        return dict(self.params)


class DriftingWall(ShiftedWall):
    """Non-deterministic: the wall moves a little on every call."""

    summary = "non-deterministic wall (kit test double)"

    def walls(self, ctx: Any, p0: float, clock: Any) -> tuple[Any, None]:
        from xpersson.engine import Wall

        return Wall.absorbing(-self.params["s"] - next(_counter)), None


class UnpicklableWall(ShiftedWall):
    """Holds a lambda: cannot be shipped to dask workers."""

    summary = "unpicklable wall (kit test double)"

    def __init__(self, **params: Any) -> None:
        super().__init__(**params)
        self.hook = lambda x: x


class NoExampleWall(Boundary):
    summary = "required parameter without example (kit test double)"
    parameters = {"s": ParamSpec("Pa")}


class HalfCoefficient(Coefficient):
    """Half the elastic coefficient: tau = tau_elastic / 2."""

    summary = "half the elastic diffusion coefficient (kit test double)"

    def f(self, ctx: Any, zeta: Any) -> Any:
        from xpersson.physics import elastic

        return 0.5 * elastic.coefficient_f(ctx.psd, ctx.E_star, zeta)

    def tau(self, ctx: Any, zeta: Any) -> Any:
        from xpersson.physics import elastic

        return 0.5 * elastic.diffusion_time(ctx.psd, ctx.E_star, zeta)
