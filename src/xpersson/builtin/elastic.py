"""Built-in elastic physics: the coefficient f(zeta) from the PSD and the p = 0 wall.

Persson (2001): dP/dzeta = f(zeta) d2P/dp2 with f = (pi/4) E*^2 q_L q^3 C(q), q = zeta q_L,
absorbing wall P(0, zeta) = 0. The correction-factor closures (YP08, WM17, Xu24) change the
variance of the mirrored Gaussian through the running contact area; they are selected with
``closure`` and are defined for the elastic wall only.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..physics import closures, elastic
from ..physics.psd import stacked_C
from ..plugins import CLOSURE_PARAMETERS, Boundary, Coefficient, FastPaths, ParamSpec, VarSpec

if TYPE_CHECKING:  # pragma: no cover
    from ..engine import Wall
    from ..plugins import DiffusionClock, SceneContext

__all__ = ["ElasticCoefficient", "ElasticBoundary"]


class ElasticCoefficient(Coefficient):
    """f(zeta) = (pi/4) E*^2 q_L q^3 C(q) [Pa^2], with optional correction closures.

    ``closure``: ``persson01`` (none), ``yp08`` (Yang & Persson 2008, S = gamma + (1-gamma)A^2),
    ``wm17`` (Wang & Müser 2017), ``xu24`` (Xu et al. 2024, algebraic). ``gamma`` defaults to
    :data:`xpersson.physics.closures.GAMMA_DEFAULT` = 0.42 (yp08, xu24) and 5/9 (wm17).
    """

    summary = "elastic diffusion coefficient from the PSD, with YP08/WM17/Xu24 closures"
    references = (
        "10.1063/1.1388626",
        "10.1088/0953-8984/20/21/215214",
        "10.1007/s11249-017-0900-2",
        "10.1007/s11249-024-01838-4",
    )
    parameters = dict(CLOSURE_PARAMETERS)  # closure, gamma: declared once for every coefficient
    outputs: dict[str, VarSpec] = {}
    traits = frozenset({"elastic_spectrum"})
    #: contact similarity: tau and f are E*^2 times the spectrum's moment, the closures act
    #: through A(G); stacked: a block of points (other spectra, other E*), tau and f asked per
    #: point; shared tau: without a closure, effective_tau only broadcasts tau(zeta)
    fast_paths = FastPaths(
        contact_similarity=True,
        stacked_params=frozenset(),
        shared_tau={"closure": "persson01"},
        reused=True,
    )

    def corrects_variance(self) -> bool:
        """True for the yp08, wm17 and xu24 closures."""
        return self._params["closure"] != "persson01"

    def variance_factor(self, ctx: SceneContext, area: np.ndarray) -> np.ndarray | None:
        """``S = d tau_eff/d tau_c`` of the closure at the running area (None for persson01)."""
        if not self.corrects_variance():
            return None
        return closures.variance_factor(self._params["closure"], area, self._params["gamma"])

    def __init__(self, **params: Any) -> None:
        super().__init__(**params)
        if self._params["closure"] == "persson01" and self._params["gamma"] is not None:
            raise ValueError(
                f"gamma: {self._params['gamma']:g} is not used by closure 'persson01'; remove "
                "gamma or choose closure 'yp08', 'wm17' or 'xu24' (gamma in (0, 1])"
            )

    def f(self, ctx: SceneContext, zeta: np.ndarray) -> np.ndarray:
        """f(zeta) [Pa^2]."""
        return np.asarray(elastic.coefficient_f(ctx.psd, ctx.E_star, zeta), dtype=float)

    def tau(self, ctx: SceneContext, zeta: np.ndarray) -> np.ndarray:
        """tau(zeta) = (pi/4) E*^2 int_{q_L}^{zeta q_L} q^3 C dq [Pa^2] (exact)."""
        return np.asarray(elastic.diffusion_time(ctx.psd, ctx.E_star, zeta), dtype=float)

    def clock_key(self, ctx: SceneContext) -> Any:
        """:meth:`tau` and :meth:`f` depend on the spectrum and E* alone (``None`` for a
        subclass that redefines either)."""
        if (type(self).tau, type(self).f) != (ElasticCoefficient.tau, ElasticCoefficient.f):
            return None
        return ("elastic", ctx.psd, float(ctx.E_star))

    def tau_stacked(
        self, ctxs: Sequence[SceneContext], points: Sequence[Coefficient], zeta: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """``(tau, f)`` [Pa^2] of a block of points, each ``(n_point, n_zeta)``: the numbers of
        :meth:`tau` and :meth:`f` per point (the same operations in the same order), the
        products made once over the block; a subclass that redefines them is asked per point.
        """
        own = (ElasticCoefficient.tau, ElasticCoefficient.f)
        if any((type(c).tau, type(c).f) != own for c in points):
            return super().tau_stacked(ctxs, points, zeta)
        z = np.asarray(zeta, dtype=float)
        q_L = np.array([x.psd.q_L for x in ctxs], dtype=float)
        q = z * q_L[:, None]  # [1/m], row k: zeta * q_L of point k
        i3 = np.stack([np.asarray(x.psd.I3(q[k]), dtype=float) for k, x in enumerate(ctxs)])
        C = stacked_C([x.psd for x in ctxs], q)  # None: spectra of other kinds, asked each
        if C is None:
            C = np.stack([np.asarray(x.psd.C(q[k]), dtype=float) for k, x in enumerate(ctxs)])
        c = 0.25 * np.pi * np.array([x.E_star**2 for x in ctxs], dtype=float)
        return c[:, None] * i3, (c * q_L)[:, None] * q**3 * C

    def effective_tau(self, ctx: SceneContext, zeta: np.ndarray) -> np.ndarray:
        """Per-load diffusion time [Pa^2]; the closures solve their ODE/fixed point to 1e-10.

        Without a closure (``persson01``) the time does not depend on the load, which may then
        be tensile (adhesive boundaries); the closures need ``p0 > 0``.
        """
        if self._params["closure"] == "persson01":
            return super().effective_tau(ctx, zeta)
        tau_c = self.tau(ctx, zeta)
        return closures.effective_tau(
            tau_c, ctx.p0, self._params["closure"], self._params["gamma"], rtol=1e-10
        )


class ElasticBoundary(Boundary):
    """Elastic contact: absorbing wall P(0, zeta) = 0 (points reaching zero stress separate)."""

    summary = "elastic contact: absorbing wall at p = 0, non-contact area from its flux"
    references = ("10.1063/1.1388626", "10.1016/j.wear.2005.12.007")
    parameters: dict[str, ParamSpec] = {}
    outputs: dict[str, VarSpec] = {}
    traits = frozenset({"repulsive", "load_similar", "conservative"})
    #: the wall p = 0 is the same for every load (asked once), the same in units of E*
    #: (contact similarity) and for every point of a stacked block
    fast_paths = FastPaths(
        contact_similarity=True, stacked_params=frozenset(), shared_walls=True, reused=True
    )

    def walls(self, ctx: SceneContext, p0: float, clock: DiffusionClock) -> tuple[Wall, None]:
        """One absorbing wall at p = 0 [Pa]; no upper wall."""
        from ..engine import Wall

        return Wall.absorbing(0.0), None

    def interpret(self, ctx: SceneContext, results: list[Any]) -> dict[str, Any]:
        """Nothing beyond the core's area and non-contact fractions."""
        return {}
