"""The Markov process behind the diffusion equation, simulated: engine methods ``markov``.

Persson's derivation (Appendix B of Persson 2001, :cite:p:`persson2001`) treats the contact pressure
at a point as a Markov process in the magnification: each added band of roughness changes the
pressure by a Gaussian increment (Chapman-Kolmogorov, B2), whose variance in diffusion time
``tau`` is ``2 d tau`` (B3-B5).  This module simulates that process instead of solving its
Fokker-Planck equation, as an independent referee for the engine's other methods:

* ``method="markov"`` (:class:`MarkovMethod`): ``N`` independent walkers, increments exact in
  ``tau`` (``p -> p + sqrt(2 dtau) Z``).  Crossing a wall *between* two steps is detected
  exactly with the Brownian-bridge probability ``exp(-d0 d1 / dtau)`` (``d0``, ``d1`` the
  distances to the wall at both ends of the step, the wall linear in between), so fixed and
  linearly moving walls are treated without time-step error and the elastic case needs one step
  per output.  Absorbed walkers are *stopped* at the wall (their pressure stays the wall's: the
  load identity).  Non-linear wall motion is followed by geometric sub-steps
  (``steps_per_decade``); two walls limit a step to ``sqrt(2 dtau) <= gap / 6`` so that a step
  reaches at most one wall.  The moving yield wall (``Wall.yield_closure``, Lambert's closure,
  :cite:p:`lambert2025`) is the process with a *sticky* wall: walkers that reach ``Y`` become
  plastic
  and ride the wall up; in each step a fraction ``q = dY / E|dp|`` of the plastic walkers is
  released into the elastic domain at a half-normal depth ``|dp|`` below the wall, which is the
  release that conserves the expected pressure (the force balance ``int p P dp + Y A_pl = p0``
  that defines the closure).  The error estimate is the Monte Carlo standard error of the area,
  ``sqrt(A (1 - A) / N)``; ``P`` is the histogram of the walkers on cells centred on ``p_out``.
* ``method="markov_ck"`` (:class:`ChapmanKolmogorovMethod`, module ``_markov_ck``): the same
  process propagated as a density, by the Chapman-Kolmogorov integral with the Gaussian
  transition kernel (killed by the same bridge factor) on a grid.

Options (``solve(options=...)``, scene ``[solver] walkers`` / ``seed``): ``walkers`` (int,
default 100 000), ``seed`` (int, default 0; each load draws its own stream from ``(seed, p0)``),
``steps_per_decade`` (sub-steps for moving walls, default 64), ``chunk`` (walkers per batch,
bounds the memory; default 1 000 000).

Units: pressures in Pa, diffusion time in Pa^2, densities in 1/Pa.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.special import erfc, erfcx

from ._base import EngineMethod
from ._markov_ck import run_kernel
from ._markov_options import GAP_STEPS, markov_options
from ._problem import Problem
from ._result import Raw
from ._walls import Wall

__all__ = ["MarkovMethod", "markov_options", "sample_paths", "step_times", "walker_rng"]

Array = NDArray[np.float64]


def walker_rng(seed: int, p0: float) -> np.random.Generator:
    """The random stream of one load: a ``SeedSequence`` of ``(seed, bits of p0)``.

    Two solves with the same seed are identical; the loads of one scene are independent.
    """
    bits = int(np.asarray(p0, dtype=np.float64).view(np.uint64))
    return np.random.default_rng(np.random.SeedSequence([int(seed), bits]))


def _is_moving(wall: Wall | None, tau_max: float) -> bool:
    """True when the wall moves other than linearly (linear motion is bridged exactly)."""
    if wall is None or wall.is_fixed:
        return False
    return wall.linear_motion(tau_max) is None


def step_times(pb: Problem, per_decade: float) -> Array:
    """Time nodes of the walk: the outputs, plus geometric sub-steps for curved wall motion.

    Fixed and linearly moving absorbing walls need no sub-steps (the bridge is exact); the
    two-wall and yield restrictions are applied per step by :func:`_substeps`.
    """
    tau = pb.tau[pb.tau > 0]
    nodes = [np.zeros(1), tau]
    tmax = float(pb.tau_max)
    moving = _is_moving(pb.lower, tmax) or _is_moving(pb.upper, tmax)
    if pb.upper is not None and pb.upper.kind == "yield_closure" and not pb.upper.is_fixed:
        moving = True
    if moving and tau.size:
        t_lo = float(tau[0])
        n = max(2, int(math.ceil(per_decade * math.log10(tmax / t_lo))) + 1)
        nodes.append(np.geomspace(t_lo, tmax, n))
    return np.unique(np.concatenate(nodes))


def _substeps(t0: float, t1: float, gap: float, speed: float, sticky_near: bool) -> Array:
    """Split ``[t0, t1]`` so that each step reaches at most one wall.

    ``gap`` [Pa] is the smallest distance between the walls (inf for one wall), ``speed`` the
    largest ``dY/dtau`` [1/Pa] of a sticky wall.  Near a sticky wall (plastic walkers, or walkers
    within reach) a step also keeps ``b = dY/dtau sqrt(dtau) <= 0.2`` (the release law neglects
    the wall's drift within a step), with at most 256 sub-steps per interval.
    """
    dt_max = (gap / GAP_STEPS) ** 2 / 2.0 if math.isfinite(gap) else math.inf
    if speed > 0 and sticky_near:
        dt_max = min(dt_max, max((0.2 / speed) ** 2, (t1 - t0) / 256.0))
    n = 1 if not math.isfinite(dt_max) else max(1, int(math.ceil((t1 - t0) / dt_max)))
    return np.linspace(t0, t1, n + 1)


@dataclass
class _Walkers:
    """The state of one batch: elastic positions, plastic count, absorbed tallies."""

    x: Array  # pressures of walkers strictly between the walls [Pa]
    n_plastic: int = 0  # walkers riding a sticky (yield closure) upper wall
    n_lower: int = 0  # absorbed at the lower wall
    n_upper: int = 0  # absorbed at an absorbing upper wall
    mom_lower: float = 0.0  # sum of the lower wall's position at absorption [Pa]
    mom_upper: float = 0.0  # same for an absorbing upper wall [Pa]
    sq_walls: float = 0.0  # sum of squared stopping positions (for the load's standard error)
    n_plastic_before: int = 0  # plastic walkers at the start of the current step


def _crossed(rng: np.random.Generator, d0: Array, d1: Array, dt: float) -> Array:
    """Did a Brownian path (variance 2 dt) cross a linear wall, distances d0 > 0 -> d1?"""
    out = d1 <= 0.0
    inside = ~out
    if inside.any():
        prob = np.exp(-d0[inside] * d1[inside] / dt)
        out[inside] = rng.random(int(inside.sum())) < prob
    return out


def _hit_fraction(rng: np.random.Generator, d0: Array, d1: Array, dt: float) -> Array:
    """When, as a fraction of the step, a crossing bridge first reached the wall.

    The bridge ``d0 -> d1`` (distances to a linear wall, variance ``2 dt``) that crossed has the
    hitting time of the bridge ``d0 -> -|d1|`` (reflection).  The map ``u = s / (1 - s/dt)``
    turns that bridge into a Brownian motion with drift ``-|d1|/dt`` started at ``d0``, whose
    first passage is inverse Gaussian (Wald) with mean ``d0 dt / |d1|`` and shape ``d0^2 / 2``.
    """
    if d0.size == 0:
        return d0
    b = np.maximum(np.abs(d1), 1e-300)
    u = rng.wald(np.maximum(d0, 1e-300) * dt / b, np.maximum(d0, 1e-300) ** 2 / 2.0)
    return u / (dt + u)


def _sticky_release(rng: np.random.Generator, speed: float, durations: Array) -> Array:
    """Depth below a sticky wall [Pa] of each stuck walker after ``durations`` [Pa^2] (NaN: stuck).

    In the frame of the wall the plastic mass ``m`` and the density ``rho(D)`` at depth ``D``
    obey ``rho_t = rho_DD``, ``rho(0) = a m``, ``m' = rho_D(0)`` with ``a = dY/dtau`` (Lambert's
    closure ``P(Y) = A_pl dY/dtau``, :cite:p:`lambert2025`; the wall's drift is carried by the
    moving
    wall itself).  From one stuck walker: ``m(t) = exp(a^2 t) erfc(a sqrt t)``, and the mass
    deeper than ``D`` is ``S(z) = erfc(z) - exp(-z^2) erfcx(z + a sqrt t)``, ``z = D/(2 sqrt t)``,
    which is inverted by bisection.
    """
    out = np.full(durations.size, np.nan)
    if speed <= 0.0 or durations.size == 0:
        return out
    b = speed * np.sqrt(np.maximum(durations, 0.0))
    stay = erfcx(b)  # = exp(b^2) erfc(b)
    u = rng.random(durations.size)
    go = u < 1.0 - stay
    if not go.any():
        return out
    bg, ug = b[go], u[go]
    lo = np.zeros(bg.size)
    hi = np.full(bg.size, 10.0)
    for _ in range(48):
        mid = 0.5 * (lo + hi)
        deeper = erfc(mid) - np.exp(-mid * mid) * erfcx(mid + bg) > ug
        lo = np.where(deeper, mid, lo)
        hi = np.where(deeper, hi, mid)
    # the wall's rise pays the released walkers' depth: E[sum depth] = dY per stuck walker
    # (the force balance that defines the closure); the drift-free law releases the fraction
    # int_0^b 2x erfcx(x) dx / b^2 of it, restored by scaling the depths
    out[go] = 2.0 * np.sqrt(durations[go]) * 0.5 * (lo + hi) * _depth_scale(bg)
    return out


_B_TABLE = np.concatenate([np.linspace(0.0, 2.0, 401), np.geomspace(2.0, 1e3, 300)[1:]])
_X_FINE = np.concatenate([np.linspace(0.0, 2.0, 40_001), np.geomspace(2.0, 1e3, 20_000)[1:]])
_INT = np.concatenate(
    [
        [0.0],
        np.cumsum(
            0.5
            * np.diff(_X_FINE)
            * (2 * _X_FINE[1:] * erfcx(_X_FINE[1:]) + 2 * _X_FINE[:-1] * erfcx(_X_FINE[:-1]))
        ),
    ]
)
_SCALE = np.where(
    _B_TABLE > 0, _B_TABLE**2 / np.maximum(np.interp(_B_TABLE, _X_FINE, _INT), 1e-300), 1.0
)


def _depth_scale(b: Array) -> Array:
    """``b^2 / int_0^b 2 x erfcx(x) dx`` (1 at b = 0), tabulated on [0, 1000]."""
    big = b > _B_TABLE[-1]  # erfcx(x) ~ 1/(x sqrt(pi)): the integral grows as 2 b / sqrt(pi)
    return np.where(big, b * math.sqrt(math.pi) / 2.0, np.interp(b, _B_TABLE, _SCALE))


def _walk(
    pb: Problem,
    st: _Walkers,
    rng: np.random.Generator,
    dt: float,
    lower: tuple[float, float],
    upper: tuple[float, float] | None,
) -> None:
    """Advance a batch by ``dt`` [Pa^2] (one exact step; bridge test at each wall).

    ``lower`` and ``upper`` are the wall positions [Pa] at the start and the end of the step.
    """
    if dt <= 0:
        return
    a0, a1 = lower
    sticky = pb.upper is not None and pb.upper.kind == "yield_closure" and not pb.upper.is_fixed
    x = st.x
    y0 = y1 = 0.0
    new_frac = np.zeros(0)  # hit fractions of the walkers that stuck to the wall in this step
    if upper is not None:
        y0, y1 = upper
    if x.size:
        x1 = x + math.sqrt(2.0 * dt) * rng.standard_normal(x.size)
        hit_l = _crossed(rng, x - a0, x1 - a1, dt)
        frac = _hit_fraction(rng, x[hit_l] - a0, x1[hit_l] - a1, dt)
        at = a0 + (a1 - a0) * frac
        st.n_lower += int(hit_l.sum())
        st.mom_lower += float(at.sum())
        st.sq_walls += float(np.square(at).sum())
        if pb.upper is not None:
            hit_u = _crossed(rng, y0 - x, y1 - x1, dt) & ~hit_l
            frac = _hit_fraction(rng, y0 - x[hit_u], y1 - x1[hit_u], dt)
            at = y0 + (y1 - y0) * frac
            if sticky:  # stuck at the hit time; released below by the sticky law
                new_frac = frac
            else:
                st.n_upper += int(hit_u.sum())
                st.mom_upper += float(at.sum())
                st.sq_walls += float(np.square(at).sum())
            x = x1[~(hit_l | hit_u)]
        else:
            x = x1[~hit_l]
    if sticky:
        speed = max(0.0, y1 - y0) / dt  # dY/dtau over the step [1/Pa]
        rest = np.concatenate([np.full(st.n_plastic_before, dt), (1.0 - new_frac) * dt])
        depth = _sticky_release(rng, speed, rest)
        free = np.isfinite(depth)
        st.n_plastic += int(new_frac.size) - int(free.sum())
        if free.any():
            new = y1 - depth[free]
            below = new <= a1
            st.n_lower += int(below.sum())
            st.mom_lower += float(below.sum()) * a1
            st.sq_walls += float(below.sum()) * a1 * a1
            x = np.concatenate([x, new[~below]])
    st.n_plastic_before = st.n_plastic
    st.x = x


def _edges(p: Array) -> Array:
    """Cell edges around the output pressures (midpoints; half a spacing beyond the ends)."""
    if p.size == 1:
        return np.array([p[0] - 0.5, p[0] + 0.5])
    mid = 0.5 * (p[1:] + p[:-1])
    return np.concatenate([[p[0] - (mid[0] - p[0])], mid, [p[-1] + (p[-1] - mid[-1])]])


def _simulate(pb: Problem, opts: dict[str, Any]) -> dict[str, Any]:
    n_total = int(opts["walkers"])
    rng = walker_rng(int(opts["seed"]), pb.p0)
    times = step_times(pb, float(opts["steps_per_decade"]))
    out_idx = np.searchsorted(times, pb.tau)
    n_t = pb.tau.size
    acc = {
        k: np.zeros(n_t)
        for k in ("area", "lower", "upper", "load", "mom_l", "mom_u", "plastic", "load2")
    }
    hist = None
    if pb.p_out is not None:
        edges = _edges(np.sort(pb.p_out))
        hist = np.zeros((n_t, pb.p_out.size))
    nsteps = 0
    done = 0
    sticky = pb.upper is not None and pb.upper.kind == "yield_closure" and not pb.upper.is_fixed
    # wall positions: evaluated once on the step times, linear in between (as the bridge is)
    walls_lo, walls_up = pb.wall_positions(times)
    speeds = pb.upper.speed(times) if sticky else np.zeros(times.size)
    while done < n_total:
        n = min(int(opts["chunk"]), n_total - done)
        done += n
        st = _Walkers(np.full(n, pb.p0))
        for k in range(times.size):
            if k > 0:
                t0, t1 = float(times[k - 1]), float(times[k])
                near = sticky and (
                    st.n_plastic > 0
                    or (
                        st.x.size > 0
                        and float(st.x.max()) + 8.0 * math.sqrt(2.0 * (t1 - t0)) >= walls_up[k - 1]
                    )
                )
                gap = float(min(walls_up[k - 1] - walls_lo[k - 1], walls_up[k] - walls_lo[k]))
                sub = _substeps(t0, t1, gap, float(max(speeds[k - 1], speeds[k])), near)
                lo_s = np.interp(sub, times[k - 1 : k + 1], walls_lo[k - 1 : k + 1])
                up_s = np.interp(sub, times[k - 1 : k + 1], walls_up[k - 1 : k + 1])
                for m in range(sub.size - 1):
                    up_m = None if pb.upper is None else (float(up_s[m]), float(up_s[m + 1]))
                    _walk(
                        pb,
                        st,
                        rng,
                        float(sub[m + 1] - sub[m]),
                        (float(lo_s[m]), float(lo_s[m + 1])),
                        up_m,
                    )
                    nsteps += 1
            for i in np.flatnonzero(out_idx == k):
                acc["area"][i] += st.x.size
                acc["lower"][i] += st.n_lower
                acc["upper"][i] += st.n_upper + st.n_plastic
                acc["plastic"][i] += st.n_plastic
                acc["load"][i] += float(st.x.sum())
                acc["load2"][i] += float(np.square(st.x).sum()) + st.sq_walls
                if sticky:
                    acc["load2"][i] += st.n_plastic * float(walls_up[k]) ** 2
                acc["mom_l"][i] += st.mom_lower
                acc["mom_u"][i] += st.mom_upper
                if hist is not None:
                    hist[i] += np.histogram(st.x, bins=edges)[0]
    acc["nsteps"] = nsteps
    acc["hist"] = hist
    return acc


class MarkovMethod(EngineMethod):
    """Monte Carlo walkers of the pressure process (see the module docstring)."""

    name = "markov"

    @classmethod
    def admits(cls, problem: Problem) -> bool:
        return True

    def run(self) -> Raw:
        pb = self.problem
        opts = markov_options(dict(pb.options))
        if opts.get("mode", "walkers") == "kernel":
            return run_kernel(pb, opts)
        n = int(opts["walkers"])
        acc = _simulate(pb, opts)
        area = acc["area"] / n
        ab_l = acc["lower"] / n
        ab_u = acc["upper"] / n
        load = acc["load"] / n
        sticky = pb.upper is not None and pb.upper.kind == "yield_closure"
        sticky = sticky and not pb.upper.is_fixed
        wall_term = acc["mom_l"] / n
        if sticky:
            wall_term = wall_term + pb.upper.at(pb.tau) * acc["plastic"] / n
        else:
            wall_term = wall_term + acc["mom_u"] / n
        se = np.sqrt(np.maximum(area * (1.0 - area), 1.0 / n) / n)
        P = None
        if acc["hist"] is not None:
            width = np.diff(np.sort(_edges(pb.p_out)))
            P = np.zeros_like(acc["hist"])
            order = np.argsort(pb.p_out)
            P[:, order] = acc["hist"] / (n * width[None, :])
        # the balances of a Monte Carlo run hold in expectation: judge them in standard errors
        # per walker: its pressure, or the wall position where it stopped (mean p0)
        se_load = np.sqrt(np.maximum(acc["load2"] / n - (load + wall_term) ** 2, 0.0) / n)
        lo, up = pb.wall_positions(pb.tau)
        scale = np.maximum(abs(pb.p0), np.abs(lo))
        scale = np.maximum(scale, np.where(np.isfinite(up), np.abs(up), 0.0))
        resid = load + wall_term - pb.p0
        tol = pb.tolerance(area)
        status, message = "success", ""
        z_load = np.abs(resid) / np.maximum(se_load + 4.0 * scale / n, 1e-300)
        if np.any(z_load > 6.0):
            i = int(np.argmax(z_load))
            status = "balance_violated"
            message = (
                f"load balance off by {z_load[i]:.1f} standard errors at tau = {pb.tau[i]:.6g} Pa^2"
            )
        elif np.any(se > tol):
            i = int(np.argmax(se / tol))
            status = "tolerance_not_met"
            need = int(math.ceil(n * (se[i] / tol[i]) ** 2))
            message = (
                f"Monte Carlo standard error {se[i]:.2e} of A/A0 with {n} walkers exceeds "
                f"the tolerance {tol[i]:.2e} at tau = {pb.tau[i]:.6g} Pa^2 (about {need:.2g}"
                f" walkers would meet it; the error falls as N^-1/2)"
            )
        else:
            message = f"{n} walkers, standard error <= tolerance"
        return Raw(
            area=area,
            non_area=ab_l + ab_u,
            absorbed_lower=ab_l,
            absorbed_upper=ab_u,
            load=load,
            wall_term=wall_term,
            error_estimate=se,
            P=P,
            status=status,
            message=message,
            nsteps=int(acc["nsteps"]),
            n_nodes=n,
            nfev=int(acc["nsteps"]),
            extra={"load_standard_error": se_load},
        )


def sample_paths(
    tau: Array,
    p0: float,
    n_paths: int,
    *,
    lower: Wall | None = None,
    upper: Wall | None = None,
    seed: int = 0,
) -> Array:
    """Trajectories of the pressure process, stopped at absorbing walls (for figures).

    Parameters
    ----------
    tau : ndarray
        Increasing diffusion times [Pa^2], starting at 0.
    p0 : float
        Start [Pa].
    n_paths : int
        Number of walkers.
    lower, upper : Wall, optional
        Absorbing walls (default: the elastic wall at 0; ``upper`` none).  A reflecting lower
        wall reflects the paths.
    seed : int
        Random seed.

    Returns
    -------
    ndarray, shape (n_paths, tau.size)
        Pressures [Pa]; a stopped path keeps the wall's position, NaN afterwards.
    """
    lower = Wall.absorbing(0.0) if lower is None else lower
    t = np.asarray(tau, dtype=float)
    rng = np.random.default_rng(seed)
    out = np.full((n_paths, t.size), np.nan)
    x = np.full(n_paths, float(p0))
    alive = np.ones(n_paths, bool)
    out[:, 0] = x
    for k in range(1, t.size):
        dt = t[k] - t[k - 1]
        x1 = x + math.sqrt(2.0 * dt) * rng.standard_normal(n_paths)
        a0, a1 = (float(v) for v in lower.at(t[k - 1 : k + 1]))
        if lower.kind == "reflecting":
            x1 = a1 + np.abs(x1 - a1)
            hit = np.zeros(n_paths, bool)
        else:
            hit = alive & _crossed(rng, x - a0, x1 - a1, dt)
        if upper is not None:
            b0, b1 = (float(v) for v in upper.at(t[k - 1 : k + 1]))
            hit_u = alive & ~hit & _crossed(rng, b0 - x, b1 - x1, dt)
            out[hit_u, k] = b1
            alive &= ~hit_u
        out[hit, k] = a1
        alive &= ~hit
        out[alive, k] = x1[alive]
        x = np.where(alive, x1, x)
    return out
