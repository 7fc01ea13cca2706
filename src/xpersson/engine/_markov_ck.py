"""Chapman-Kolmogorov propagation of the pressure density (engine method ``markov_ck``).

Persson's step B2: the density at a larger magnification is the density at a smaller one
convolved with the transition kernel of the added roughness band,

    P(p, tau1) = int K(p, p', tau1 - tau0) P(p', tau0) dp',
    K = exp(-(p - p')^2 / (4 dtau)) / sqrt(4 pi dtau) * (1 - exp(-d0 d1 / dtau)) [* upper],

the Gaussian kernel of variance ``2 dtau`` times the probability that the Brownian bridge from
``p'`` to ``p`` does not cross the (linearly interpolated) wall, ``d0``, ``d1`` the distances to
the wall at both ends.  For fixed and linearly moving walls this kernel is exact for any step,
so the density is carried from output to output (tau doubling in between) on a uniform grid that
follows the growing support ``p0 -/+ k sqrt(2 tau)``; the only error is the quadrature of the
integral, estimated by repeating the run on twice as many nodes.  Expanding the same integral to
second order in the increment gives the diffusion equation (B3-B5): this method is the integral
form, the other methods solve the differential one.

Sticky (moving yield-closure) walls are served by the walkers (``method="markov"``) only.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.special import erfc

from ._base import EngineMethod
from ._markov_options import GAP_STEPS, markov_options
from ._problem import Problem
from ._result import Raw

__all__ = ["ChapmanKolmogorovMethod", "run_kernel", "transition_kernel"]

Array = NDArray[np.float64]


def transition_kernel(
    p: Array,
    p_from: Array,
    dtau: float,
    lower: tuple[float, float] | None = None,
    upper: tuple[float, float] | None = None,
) -> Array:
    """Transition density [1/Pa] of the pressure process over ``dtau`` [Pa^2].

    Parameters
    ----------
    p : ndarray
        End pressures [Pa] (rows).
    p_from : ndarray
        Start pressures [Pa] (columns).
    dtau : float
        Diffusion-time increment [Pa^2] (> 0).
    lower, upper : (float, float), optional
        Absorbing wall positions [Pa] at the start and the end of the step.

    Returns
    -------
    ndarray, shape (p.size, p_from.size)
        The Gaussian kernel of variance ``2 dtau``, times the probability of not crossing each
        wall (zero beyond a wall).
    """
    pp = np.asarray(p, dtype=float)[:, None]
    pf = np.asarray(p_from, dtype=float)[None, :]
    k = np.exp(-((pp - pf) ** 2) / (4.0 * dtau)) / math.sqrt(4.0 * math.pi * dtau)
    if lower is not None:
        d0, d1 = pf - lower[0], pp - lower[1]
        k = k * np.where((d0 > 0) & (d1 > 0), -np.expm1(-np.clip(d0 * d1, 0, None) / dtau), 0.0)
    if upper is not None:
        d0, d1 = upper[0] - pf, upper[1] - pp
        k = k * np.where((d0 > 0) & (d1 > 0), -np.expm1(-np.clip(d0 * d1, 0, None) / dtau), 0.0)
    return k


def _trapezoid(x: Array) -> Array:
    w = np.empty_like(x)
    h = np.diff(x)
    w[0], w[-1] = h[0] / 2, h[-1] / 2
    w[1:-1] = (h[:-1] + h[1:]) / 2
    return w


def _times(pb: Problem, ratio: float) -> Array:
    tau = pb.tau[pb.tau > 0]
    if tau.size == 0:
        return np.zeros(1)
    t0 = float(tau[0])
    if not (pb.lower.is_fixed and (pb.upper is None or pb.upper.is_fixed)):
        ratio = min(ratio, 1.1)  # moving walls: the absorbed load is taken at mid-step
    n = int(math.ceil(math.log(pb.tau_max / t0) / math.log(ratio))) + 1 if pb.tau_max > t0 else 1
    geo = t0 * ratio ** np.arange(n)
    t = np.unique(np.concatenate([[0.0], tau, geo[geo < pb.tau_max]]))
    if pb.upper is None:
        return t
    out = [t[:1]]
    for a, b in zip(t[:-1], t[1:], strict=True):  # a step reaches at most one wall
        lo, up = pb.wall_positions(np.linspace(a, b, 5))
        dt_max = (float(np.min(up - lo)) / GAP_STEPS) ** 2 / 2.0
        m = max(1, int(math.ceil((b - a) / dt_max)))
        out.append(np.linspace(a, b, m + 1)[1:])
    return np.concatenate(out)


def _level(pb: Problem, n: int, k: float, ratio: float) -> dict[str, Any]:
    times = _times(pb, ratio)
    n_t = pb.tau.size
    res = {key: np.zeros(n_t) for key in ("area", "lower", "upper", "load", "mom_l", "mom_u")}
    res["area"][:] = 1.0
    res["load"][:] = pb.p0
    P_out = None if pb.p_out is None else np.zeros((n_t, pb.p_out.size))
    out_of = {float(t): i for i, t in enumerate(pb.tau)}
    x = np.array([pb.p0])
    w = np.array([1.0])  # the delta: weight 1 at p0 (its "density" times weight is the mass)
    P = np.array([1.0])
    ab_l = ab_u = mom_l = mom_u = 0.0
    n_max = n
    for j in range(1, times.size):
        t0, t1 = float(times[j - 1]), float(times[j])
        dt = t1 - t0
        lo, up = pb.wall_positions(np.array([t0, t1]))
        s1 = math.sqrt(2.0 * t1)
        left = max(float(lo[1]), pb.p0 - k * s1)
        right = min(float(up[1]), pb.p0 + k * s1)
        # nodes: h <= sigma of the next step / 4 (the next integral resolves its kernel)
        sig_next = math.sqrt(2.0 * (times[j + 1] - t1)) if j + 1 < times.size else math.inf
        m = int(min(8 * n, max(n, math.ceil(4.0 * (right - left) / sig_next))))
        n_max = max(n_max, m)
        xn = np.linspace(left, right, m + 1)
        wn = _trapezoid(xn)
        kern = transition_kernel(
            xn,
            x,
            dt,
            (float(lo[0]), float(lo[1])),
            None if pb.upper is None else (float(up[0]), float(up[1])),
        )
        mass_j = w * P
        Pn = kern @ mass_j
        kept = wn @ kern  # probability of each source to survive into the window
        loss = mass_j * np.clip(1.0 - kept, 0.0, None)
        a_mid = 0.5 * float(lo[0] + lo[1])
        if pb.upper is not None:  # split by the one-wall hitting probabilities erfc(d/2sqrt(dt))
            b_mid = 0.5 * float(up[0] + up[1])
            h_l = erfc(np.clip(x - a_mid, 0, None) / (2.0 * math.sqrt(dt)))
            h_u = erfc(np.clip(b_mid - x, 0, None) / (2.0 * math.sqrt(dt)))
            share = np.where(h_l + h_u > 0, h_l / np.maximum(h_l + h_u, 1e-300), 0.5)
            ab_l += float(loss @ share)
            ab_u += float(loss @ (1.0 - share))
            mom_l += float(loss @ share) * a_mid
            mom_u += float(loss @ (1.0 - share)) * b_mid
        else:  # the window's far edge is a truncation (<= erfc(k/sqrt 2)), counted at the wall
            ab_l += float(loss.sum())
            mom_l += float(loss.sum()) * a_mid
        x, w, P = xn, wn, Pn
        i = out_of.get(t1)
        if i is not None:
            res["area"][i] = float(w @ P)
            res["load"][i] = float(w @ (x * P))
            res["lower"][i], res["upper"][i] = ab_l, ab_u
            res["mom_l"][i], res["mom_u"][i] = mom_l, mom_u
            if P_out is not None:
                P_out[i] = np.interp(pb.p_out, x, P, left=0.0, right=0.0)
    if P_out is not None:
        for i in np.flatnonzero(pb.tau == 0):
            P_out[i] = 0.0
    res["P"] = P_out
    res["nsteps"] = times.size - 1
    res["n_nodes"] = n_max + 1
    return res


def run_kernel(pb: Problem, opts: dict[str, Any]) -> Raw:
    """Run the Chapman-Kolmogorov propagation at ``nodes`` and ``2 nodes``; report the finer.

    Options: ``nodes`` (grid intervals, default 200), ``window_k`` (half-width of the window in
    ``sqrt(2 tau)``, default 8), ``ratio`` (growth of tau between steps, default 2).
    """
    up = pb.upper
    if up is not None and up.kind == "yield_closure" and not up.is_fixed:
        raise ValueError(
            "method='markov_ck': a moving yield-closure wall (sticky wall) is served by the "
            "walkers, method='markov'"
        )
    n = int(opts.get("nodes", 200))
    k = float(opts.get("window_k", 8.0))
    ratio = float(opts.get("ratio", 2.0))
    if n < 16 or not (2.0 <= k <= 40.0) or not (1.0 < ratio <= 16.0):
        raise ValueError(
            'options["nodes"] [1] must be >= 16, options["window_k"] [1] in [2, 40] and '
            f'options["ratio"] [1] in (1, 16]; got {n}, {k}, {ratio}'
        )
    coarse = _level(pb, n, k, ratio)
    fine = _level(pb, 2 * n, k, ratio)
    err = np.abs(fine["area"] - coarse["area"]) + math.erfc(k / math.sqrt(2.0))
    wall_term = fine["mom_l"] + fine["mom_u"]
    return Raw(
        area=fine["area"],
        non_area=fine["lower"] + fine["upper"],
        absorbed_lower=fine["lower"],
        absorbed_upper=fine["upper"],
        load=fine["load"],
        wall_term=wall_term,
        error_estimate=err,
        P=fine["P"],
        message=f"Chapman-Kolmogorov integral, {fine['n_nodes']} nodes, "
        f"{fine['nsteps']} steps (checked against {coarse['n_nodes']} nodes)",
        nsteps=int(coarse["nsteps"] + fine["nsteps"]),
        n_nodes=int(fine["n_nodes"]),
        nfev=int(coarse["nsteps"] + fine["nsteps"]),
    )


class ChapmanKolmogorovMethod(EngineMethod):
    """The density of the process by the Chapman-Kolmogorov integral (``_markov_ck``)."""

    name = "markov_ck"

    @classmethod
    def admits(cls, problem: Problem) -> bool:
        up = problem.upper
        return up is None or up.kind != "yield_closure" or up.is_fixed

    def run(self) -> Raw:
        opts = markov_options(dict(self.problem.options))
        return run_kernel(self.problem, opts)
