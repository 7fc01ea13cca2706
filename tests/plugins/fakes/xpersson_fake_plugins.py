"""Well-behaved fake plugins used by the registry, planner and CLI tests."""

from __future__ import annotations

from typing import Any

from xpersson.plugins import Analysis, Boundary, Coefficient, ParamSpec, VarSpec


class OffsetWall(Boundary):
    """Absorbing wall at p = -s."""

    summary = "absorbing wall at p = -s (test double)"
    references = ("10.1063/1.1388626",)
    parameters = {
        "s": ParamSpec("Pa", default=0.0, bounds=(0.0, None), description="wall offset"),
    }
    outputs = {"detached": VarSpec(("p0", "zeta"), "1", "detached area fraction")}

    def walls(self, ctx: Any, p0: float, clock: Any) -> tuple[Any, None]:
        from xpersson.engine import Wall

        return Wall.absorbing(-self.params["s"]), None


class OtherWall(OffsetWall):
    """Same physics under another distribution (duplicate-name tests)."""

    summary = "another wall (test double)"


class ScaledCoefficient(Coefficient):
    """f = k zeta [Pa^2]."""

    summary = "linear diffusion coefficient (test double)"
    parameters = {"k": ParamSpec("Pa**2", default=1e9, bounds=(0.0, None), inclusive=(False, True))}

    def f(self, ctx: Any, zeta: Any) -> Any:
        import numpy as np

        return self.params["k"] * np.asarray(zeta, dtype=float)

    def tau(self, ctx: Any, zeta: Any) -> Any:
        import numpy as np

        z = np.asarray(zeta, dtype=float)
        return 0.5 * self.params["k"] * (z * z - 1.0)


def _analysis(name: str, requires: tuple[str, ...], provides: tuple[str, ...]) -> type:
    outputs = {v: VarSpec(("p0", "zeta"), "1", f"{v} (test)") for v in provides}
    return type(
        name,
        (Analysis,),
        {
            "__module__": __name__,
            "__qualname__": name,
            "summary": f"test analysis {name}",
            "requires": requires,
            "provides": provides,
            "outputs": outputs,
            "compute": lambda self, ctx, ds: {v: ds["area_fraction"] * 0 for v in provides},
        },
    )


# a chain: C needs y (from B), B needs x (from A), A needs the core's area_fraction
AnaA = _analysis("AnaA", ("area_fraction",), ("x",))
AnaB = _analysis("AnaB", ("x",), ("y",))
AnaC = _analysis("AnaC", ("y",), ("z",))
# a cycle: P needs q_out from Q, Q needs p_out from P
AnaP = _analysis("AnaP", ("q_out",), ("p_out",))
AnaQ = _analysis("AnaQ", ("p_out",), ("q_out",))
# a second provider of x
AnaA2 = _analysis("AnaA2", ("area_fraction",), ("x",))
# needs w, which nobody provides
AnaW = _analysis("AnaW", ("w",), ("w_out",))


class NeedsParam(Analysis):
    """Provides v only with a required parameter."""

    summary = "analysis with a required parameter (test double)"
    parameters = {"scale": ParamSpec("m")}
    requires = ()
    provides = ("v",)
    outputs = {"v": VarSpec(("p0",), "m", "v (test)")}
