"""The analyses' ``ctx.solve_at``: the same solve at other magnifications (the one sanctioned
call back from the analyses into the engine)."""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from ..plugins import SceneContext
from ..scene import ResolvedScene

__all__ = ["make_solve_at"]


def make_solve_at(rs: ResolvedScene, ctx: SceneContext, walls: list[Any]) -> Any:
    """``(zeta, loads) -> area variables`` of the same solve at other magnifications."""
    from .. import engine

    cache: dict[bytes, dict[str, np.ndarray]] = {}

    def solve_at(
        zeta: np.ndarray, loads: np.ndarray | None = None, tau: np.ndarray | None = None
    ) -> dict[str, np.ndarray]:
        z = np.asarray(zeta, float)
        idx = np.arange(rs.p0.size) if loads is None else np.asarray(loads, dtype=int)
        key = z.tobytes() + idx.tobytes()
        if key in cache:  # several analyses sample the same grid
            return cache[key]
        c = dataclasses.replace(ctx, zeta=z, p=None, p0=rs.p0[idx])
        # tau(zeta) [Pa^2] the caller already has (a block's stacked call): the effective tau
        # of every load where the coefficient declares it the same for every load
        given = tau is not None and getattr(rs.coefficient, "tau_per_load", True) is False
        if given:
            tau_c = np.asarray(tau, float)
            tau_eff = np.broadcast_to(tau_c, (idx.size, z.size))
        else:
            tau_eff = np.asarray(rs.coefficient.effective_tau(c, z), float).reshape(idx.size, -1)
        pairs = [walls[i] for i in idx]
        shared = all(pair is pairs[0] for pair in pairs)  # identity: cheap for shared walls
        # one engine call for every load (each load gets what engine.solve gives it)
        res = engine.solve_batch(
            tau_eff,
            rs.p0[idx],
            pairs[0] if shared else pairs,
            rtol=rs.rtol,
            atol=rs.atol,
            method=rs.method,
            options=rs.solver_options or None,
        )
        out = {
            "area_fraction": np.asarray(res.area, float).reshape(idx.size, -1),
            "non_contact_fraction": np.asarray(res.non_area, float).reshape(idx.size, -1),
            "diffusion_time": tau_c if given else np.asarray(rs.coefficient.tau(c, z), float),
            "effective_diffusion_time": tau_eff,
        }
        for name, value in rs.boundary.interpret(c, res).items():
            out[name] = np.asarray(value[1] if isinstance(value, tuple) else value, float)
        cache.clear()
        cache[key] = out
        return out

    return solve_at
