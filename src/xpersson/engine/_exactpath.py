"""The exact path: closed forms of :mod:`xpersson.engine.exact` behind the method interface."""

from __future__ import annotations

import numpy as np

from ._base import EngineMethod
from ._problem import Problem
from ._result import Raw
from ._views import broadcast_view
from ._walls import Wall
from .exact import (
    linear_wall_absorbed_moment,
    linear_wall_area,
    linear_wall_density,
    linear_wall_load,
    linear_wall_non_area,
    one_wall,
    one_wall_area_non,
    one_wall_density,
    two_wall,
    two_wall_density,
    two_wall_load,
)

__all__ = ["ExactMethod"]

_EPS = np.finfo(float).eps


def _case(problem: Problem) -> str | None:
    lo, up = problem.lower, problem.upper
    if lo.kind != "absorbing" and not lo.is_fixed:
        return None
    if up is None:
        if lo.is_fixed:
            return "one"
        if not _bent(lo, problem.tau_max) and lo.linear_motion(problem.tau_max) is not None:
            return "linear"
        return None
    if lo.is_fixed and up.is_fixed:  # fixed yield walls are absorbing walls
        return "two"
    return None


def _bent(wall: Wall, tau_max: float) -> bool:
    """True when three of :meth:`Wall.linear_motion`'s probe times (0, the middle, ``tau_max``
    [Pa^2]) already show the wall is not linear, so its 257-point probe would reject it.

    A wall passing that probe has, with ``y0``, ``v`` its start [Pa] and velocity [1/Pa],
    every position within ``1e-13 S`` of the line and ``S <= 2.0001 max(|y0|, |v| tau_max)``
    (else its largest position would be far off the line); so its middle point is within
    ``2.1e-13 max(|y0|, |v| tau_max)``. A bend above ``1e-10`` of that is therefore a sure
    rejection, with room for positions that differ by rounding between the two evaluations.
    """
    if wall.kind != "absorbing" or wall.is_fixed or wall.motion is not None or not tau_max > 0:
        return False
    t = np.linspace(0.0, tau_max, 129)[[0, 64, 128]]  # the probe's own times
    with np.errstate(all="ignore"):
        y = np.asarray(wall.at(t), dtype=float)
    if not np.all(np.isfinite(y)):
        return False  # the probe decides
    v = (y[2] - y[0]) / tau_max
    bend = abs(y[1] - (y[0] + v * t[1]))
    return bool(bend > 1e-10 * max(abs(y[0]), abs(y[2]), abs(v) * tau_max, 1e-300))


class ExactMethod(EngineMethod):
    """Closed forms: one fixed wall, two fixed walls, a linearly moving lower wall."""

    name = "exact"
    batched = True

    @classmethod
    def admits(cls, problem: Problem) -> bool:
        return _case(problem) is not None

    def run(self) -> Raw:
        pb = self.problem
        case = _case(pb)
        if case is None:
            raise ValueError("method='exact': these walls have no closed form (use 'cn')")
        tau, p0 = pb.tau, pb.p0
        want_p = pb.p_out is not None
        P = None
        # density arguments: (..., n_tau, n_p) with p0 broadcast per load
        tp, pp = tau[..., None], np.asarray(p0)[..., None]
        zeros = np.zeros(np.shape(tau))  # calloc: no pages written
        identities, form = False, None
        if case == "one":
            a = float(pb.lower.position)
            if pb.is_batch and a == 0:  # load = p0 exactly: no array to compute
                area, non = one_wall_area_non(tau, p0, a)
                load = broadcast_view(np.asarray(p0, float), np.shape(tau))
            else:
                area, non, load = one_wall(tau, p0, a)
            ab_l, ab_u = non, zeros
            wall_term = a * ab_l if a != 0 else 0.0  # only summed into the load balance
            err = np.maximum(area, 1e-300)
            err *= 8 * _EPS
            # load = p0 - a (1 - A/A0) and non_area = erfc = 1 - erf are defined from the area:
            # both balances are identities of the closed form (a batch reports exact zeros)
            identities, form = True, (8 * _EPS, 8 * _EPS * 1e-300)
            if pb.is_batch:  # nothing in the batch writes into it: no memory for the zeros
                ab_u = broadcast_view(np.zeros(()), np.shape(tau))
            if want_p:
                P = one_wall_density(pb.p_out, tp, pp, a)
        elif case == "two":
            a, b = float(pb.lower.position), float(pb.upper.position)
            area, ab_l, ab_u = two_wall(tau, p0, a, b)
            non = ab_l + ab_u
            load = two_wall_load(tau, p0, a, b)
            wall_term = a * ab_l + b * ab_u
            err = 64 * _EPS * np.maximum(area, 1e-300) + 1e-16 * (tau > 0)
            if want_p:
                P = two_wall_density(pb.p_out, tp, pp, a, b)
        else:
            p_start, vel = pb.lower.linear_motion(pb.tau_max)
            s0, c = -p_start, -vel
            area = linear_wall_area(tau, p0, s0, c)
            non = linear_wall_non_area(tau, p0, s0, c)
            ab_l, ab_u = non, zeros
            load = linear_wall_load(tau, p0, s0, c)
            wall_term = linear_wall_absorbed_moment(tau, p0, s0, c)
            # cancellation of the two Phi terms when the wall runs into the mass (c < 0)
            amp = 1.0 + np.abs(c) * tau / (p0 + s0)
            err = 16 * _EPS * amp * np.maximum(area, 1e-300)
            if want_p:
                P = linear_wall_density(pb.p_out, tp, pp, s0, c)
        return Raw(
            area=area,
            non_area=non,
            absorbed_lower=ab_l,
            absorbed_upper=ab_u,
            load=load,
            wall_term=wall_term,
            error_estimate=err,
            P=P,
            message=f"closed form ({case} wall case)",
            nfev=int(tau.size),
            exact_balances=identities,
            error_form=form,
        )
