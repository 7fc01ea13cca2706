"""The analyses' ``ctx.solve_at``: the same solve at other magnifications (the one sanctioned
call back from the analyses into the engine)."""

from __future__ import annotations

import itertools
from typing import Any

import numpy as np

from ..cache import Cache
from ..plugins import DiffusionClock, SceneContext
from ..scene import ResolvedScene
from .frontend import replaced
from .stages import shared_tau

__all__ = ["make_solve_at"]


#: The answers of one solve's ``solve_at``, for the analyses that sample the same grid.
_ANSWERS = Cache(
    "pipeline.solve_at",
    scope="solve",
    maxsize=512,
    doc="area variables of ctx.solve_at(zeta, loads, tau) within one solve",
)
#: Numbers naming each ``solve_at`` made (its scene, context and walls are fixed for its life;
#: a number is never reused, unlike an object's id)
_SERIAL = itertools.count()


def make_solve_at(
    rs: ResolvedScene, ctx: SceneContext, walls: list[Any], clock: DiffusionClock
) -> Any:
    """``(zeta, loads, tau) -> area variables`` of the same solve at other magnifications.

    ``walls`` are the loads' walls on ``clock``, the run's diffusion clock (which the
    boundary's ``interpret`` reads as ``ctx.clock``).

    Answers are kept for the solve (:data:`_ANSWERS`, scope ``"solve"``): several analyses
    sample the same grid. Values are read-only.
    """
    serial = next(_SERIAL)

    def solve_at(
        zeta: np.ndarray, loads: np.ndarray | None = None, tau: np.ndarray | None = None
    ) -> dict[str, np.ndarray]:
        z = np.asarray(zeta, float)
        idx = np.arange(rs.p0.size) if loads is None else np.asarray(loads, dtype=int)
        given = None if tau is None else np.asarray(tau, float)
        key = ("solve_at", serial, z, idx, given)
        return _ANSWERS.get(key, lambda: _solve(rs, ctx, walls, clock, z, idx, given))

    return solve_at


def _solve(
    rs: ResolvedScene,
    ctx: SceneContext,
    walls: list[Any],
    clock: DiffusionClock,
    z: np.ndarray,
    idx: np.ndarray,
    tau: np.ndarray | None,
) -> dict[str, np.ndarray]:
    """The area variables of loads ``idx`` at magnifications ``z`` (one engine call)."""
    from .. import engine

    c = replaced(ctx, zeta=z, p=None, p0=rs.p0[idx])
    tau_c, tau_eff, shared = _times(rs.coefficient, c, z, idx.size, tau)
    pairs = [walls[i] for i in idx]
    one_wall = all(pair is pairs[0] for pair in pairs)  # identity: cheap for shared walls
    # one engine call for every load (each load gets what engine.solve gives it); a shared
    # tau(zeta) goes in 1-D: checked once, not per load, and broadcast there as here
    res = engine.solve_batch(
        tau_c if shared else tau_eff,
        rs.p0[idx],
        pairs[0] if one_wall else pairs,
        rtol=rs.rtol,
        atol=rs.atol,
        method=rs.method,
        options=rs.solver_options or None,
    )
    out = {
        "area_fraction": np.asarray(res.area, float).reshape(idx.size, -1),
        "non_contact_fraction": np.asarray(res.non_area, float).reshape(idx.size, -1),
        "diffusion_time": tau_c,
        "effective_diffusion_time": tau_eff,
    }
    for name, value in rs.boundary.interpret(replaced(c, clock=clock), res).items():
        out[name] = np.asarray(value[1] if isinstance(value, tuple) else value, float)
    return out


def _times(
    coef: Any, c: SceneContext, z: np.ndarray, n: int, given: np.ndarray | None
) -> tuple[np.ndarray, np.ndarray, bool]:
    """``(tau(zeta), effective tau (n, n_zeta))`` [Pa^2] at magnifications ``z``, and whether
    the engine takes tau(zeta) 1-D (the declared fast path; else the per-load rows).

    Where the coefficient's effective tau is tau(zeta) for every load, tau(zeta) is the
    caller's ``given`` (an analysis's stacked integral), else the coefficient's, broadcast over
    the loads as the main solve does (no per-load copy; the engine takes its square root once).
    The fast path (``shared_tau``) knows this from the declaration; the plain path asks every
    load's effective tau and sees it (each row equal to the coefficient's tau): both then use
    the same tau, so that a given tau whose last digits differ from the coefficient's
    (another quadrature) gives the same numbers on either path. A load-dependent effective tau
    (a closure) is the coefficient's on both paths (``given`` is then not used).
    """
    if shared_tau(coef):
        tau_c = given if given is not None else np.asarray(coef.tau(c, z), float)
        return tau_c, np.broadcast_to(tau_c, (n, z.size)), True
    tau_c = np.asarray(coef.tau(c, z), float)
    tau_eff = np.asarray(coef.effective_tau(c, z), float).reshape(n, -1)
    seen = given is not None and given.shape == tau_c.shape == tau_eff.shape[1:]
    if seen and np.array_equal(tau_eff, np.broadcast_to(tau_c, tau_eff.shape)):
        return given, np.array(np.broadcast_to(given, tau_eff.shape)), False
    return tau_c, tau_eff, False
