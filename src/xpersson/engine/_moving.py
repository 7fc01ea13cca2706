"""Front-fixed Crank-Nicolson solver for moving walls (absorbing or yield closure).

Scheme
------
* Window.  The free solution ``G = N(p; p0, 2 tau)`` bounds P from above for absorbing walls, and
  mass released by a yield wall starts above ``p0``; so the domain is truncated to
  ``[max(l, p0 - k s), min(u, p0 + k s)]`` with ``s = sqrt(2 tau)`` and artificial absorbing walls
  where the real ones are farther (error ``<= erfc(k/sqrt 2)`` each, ``k`` from ``atol``).  The
  window follows the growing support ``~ sqrt(tau)``; a yield wall stays real once it entered.
* Front fixing.  Nodes ``p_j(tau) = l_eff(tau) + W(tau) x_j`` on a fixed map ``x_j`` of [0, 1]
  clustered at both walls; the equation in the moving frame, ``dQ_j/dtau = P_pp + v_j P_p`` with
  the mesh velocity ``v_j = dp_j/dtau`` (from positions, no wall derivative needed).
* Start.  Analytic: the free Gaussian at ``tau_s``, the largest time at which no real wall lies
  inside the window; outputs before ``tau_s`` are analytic.
* Time.  Geometric steps (``steps_per_decade``) merged with the output times; Crank-Nicolson
  with two implicit-Euler half steps first (Rannacher).
* Yield closure.  ``P(Y) = A_pl Y'`` with ``A_pl`` advanced by the trapezoid rule of
  ``dA_pl/dtau = -Y' P(Y) - P_p(Y)``, solved implicitly with the interior (one bordered row,
  reduced to tridiagonal).
* Accuracy.  Levels ``(N, M)``, ``(2N, 2M)``, ``(4N, 4M)``... on nested grids and step sequences;
  Richardson extrapolation ``E_l = (4 R_l - R_{l-1})/3`` of every output, error estimate
  ``|E_l - E_{l-1}|`` (conservative: it measures the error of ``E_{l-1}``).  Levels are added
  until the estimate meets ``rtol |A| + atol`` or the budget (``max_steps``, ``levels``) is spent,
  in which case ``status`` says so.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import CubicSpline
from scipy.linalg.lapack import dgtsv
from scipy.optimize import brentq

from ._grid import Stencils, clustered
from ._methods import EngineMethod
from ._problem import Problem, window_k
from ._result import Raw

__all__ = ["CNMethod"]

Array = NDArray[np.float64]
_KEYS = ("area", "abs_l", "abs_u", "load", "mom_l", "mom_u")


@dataclass
class _Plan:
    base: Array  # level-0 time sequence tau_s ... tau_end
    out_index: Array  # index in base of each numerical output
    tau_s: float
    k: float
    yield_wall: bool


def _start_time(pb: Problem, k: float) -> float:
    """Largest tau_s with every real wall outside the window on [0, tau_s]."""
    cand = pb.tau_max * np.logspace(-18, 0, 721)
    s = np.sqrt(2.0 * cand)
    lo, up = pb.wall_positions(cand)
    ok = (lo <= pb.p0 - k * s) & (up >= pb.p0 + k * s)
    if ok.all():
        return pb.tau_max
    first = int(np.argmin(ok))
    if first == 0:
        return float(cand[0])
    return float(cand[first - 1]) * 0.5


def _switch_times(pb: Problem, k: float, t_lo: float, t_hi: float) -> list[float]:
    """Times where a real wall enters/leaves the window (kinks of the window edges)."""
    cand = t_lo * np.logspace(0.0, math.log10(t_hi / t_lo), 513) if t_hi > t_lo else []
    if len(cand) < 2:
        return []
    out: list[float] = []

    def gaps(t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        s = np.sqrt(2.0 * t)
        lo, up = pb.wall_positions(t)
        return lo - (pb.p0 - k * s), up - (pb.p0 + k * s)

    gl, gu = gaps(cand)
    for g, which in ((gl, 0), (gu, 1)):
        if pb.upper is None and which == 1:
            continue
        flips = np.flatnonzero(np.sign(g[:-1]) != np.sign(g[1:]))
        for i in flips:
            a, b = float(cand[i]), float(cand[i + 1])
            try:
                t = brentq(
                    lambda t, w=which: float(gaps(np.array([t]))[w][0]), a, b, xtol=1e-15 * b
                )
            except ValueError:
                continue
            out.append(t)
    return out


def _plan(pb: Problem, k: float, per_decade: float) -> _Plan:
    tau_s = _start_time(pb, k)
    outs = pb.tau[pb.tau > tau_s]
    yield_wall = pb.upper is not None and not pb.upper.acts_absorbing
    if outs.size == 0:
        return _Plan(np.array([tau_s]), np.zeros(0, int), tau_s, k, yield_wall)
    decades = math.log10(outs[-1] / tau_s)
    n_geo = max(1, int(math.ceil(decades * per_decade)))
    geo = tau_s * np.logspace(0.0, decades, n_geo + 1)
    fixed = np.union1d(outs, _switch_times(pb, k, tau_s, float(outs[-1])))
    # merge; drop geometric points too close to an output or a kink
    ratio = 10 ** (1.0 / per_decade) - 1.0
    keep = np.ones(geo.size, bool)
    for t in fixed:
        keep &= np.abs(geo - t) > 0.3 * ratio * t
    keep[0] = True
    base = np.union1d(geo[keep & (geo < outs[-1])], fixed)
    base = base[base >= tau_s]
    idx = np.searchsorted(base, outs)
    return _Plan(base, idx, tau_s, k, yield_wall)


def _level_times(base: Array, nsub: int, n_ie: int) -> tuple[Array, Array]:
    """Nested refinement of ``base`` plus Rannacher halves; returns (times, theta per step)."""
    d = np.diff(base)
    frac = np.arange(nsub) / nsub
    t = np.append((base[:-1, None] + d[:, None] * frac[None, :]).ravel(), base[-1])
    n_ie = min(n_ie, t.size - 1)
    if n_ie > 0:
        mids = 0.5 * (t[:n_ie] + t[1 : n_ie + 1])
        t = np.sort(np.concatenate([t, mids]))
    theta = np.full(t.size - 1, 0.5)
    theta[: 2 * n_ie] = 1.0
    return t, theta


def _wall_speed(wall, tau: Array) -> Array:
    """dp_w/dtau [1/Pa] of a wall at ``tau`` (declared, or by central differences)."""
    if wall is None or wall.is_fixed:
        return np.zeros_like(tau)
    if wall.dposition is not None:
        return wall.speed(tau)
    if wall.motion is not None:
        return np.full_like(tau, wall.motion[1])
    hi, lo = tau * (1 + 1e-5), tau * (1 - 1e-5)
    return (wall.at(hi) - wall.at(lo)) / (hi - lo)


def _edges(pb: Problem, plan: _Plan, taus: Array) -> dict:
    """Window edges and their speeds at the start (a) and end (b) of every step.

    The regime of each edge (real wall or artificial edge ``p0 -/+ k sqrt(2 tau)``) is fixed per
    step (at its midpoint); the kinks where it changes are step boundaries (see ``_plan``).
    """
    k, p0 = plan.k, pb.p0
    mid = 0.5 * (taus[:-1] + taus[1:])
    lo_m, up_m = pb.wall_positions(mid)
    s_m = np.sqrt(2.0 * mid)
    rl = lo_m >= p0 - k * s_m
    if plan.yield_wall:
        ru = np.logical_or.accumulate(up_m <= p0 + k * s_m)
    else:
        ru = up_m <= p0 + k * s_m
    out = {"rl": rl, "ru": ru}
    for tag, t in (("a", taus[:-1]), ("b", taus[1:])):
        s = np.sqrt(2.0 * t)
        ds = 1.0 / s
        lo, up = pb.wall_positions(t)
        lo_v = _wall_speed(pb.lower, t)
        up_v = _wall_speed(pb.upper, t) if pb.upper is not None else np.zeros_like(t)
        le = np.where(rl, lo, p0 - k * s)
        ue = np.where(ru, up, p0 + k * s)
        out["l" + tag] = le
        out["w" + tag] = ue - le
        out["lv" + tag] = np.where(rl, lo_v, -k * ds)
        out["wv" + tag] = np.where(ru, up_v, k * ds) - out["lv" + tag]
        out["ys" + tag] = np.where(ru, pb.upper.speed(t), 0.0) if plan.yield_wall else 0.0 * t
    return out


def _march(pb: Problem, plan: _Plan, n: int, nsub: int, stretch: float, n_ie: int) -> dict:
    """One level.  Unknown: ``R = W Q`` (mass per unit x), which is stationary for the free
    Gaussian in an artificial window, so that time errors come only from the walls' influence:

        R_tau = R_xx / W^2 + (v / W) R_x + (W'/W) R,   v = l_eff' + x W'.
    """
    taus, theta = _level_times(plan.base, nsub, n_ie)
    out_at = np.searchsorted(taus, pb.tau[pb.tau > plan.tau_s])
    st = Stencils(clustered(n, stretch))
    x = st.x
    nn = x.size
    p0 = pb.p0
    ed = _edges(pb, plan, taus)
    if np.any(ed["wa"] <= 0) or np.any(ed["wb"] <= 0):
        raise FloatingPointError("the walls swept the whole window (area 0)")
    n_out = out_at.size
    res = {key: np.zeros(n_out) for key in _KEYS}
    want_p = pb.p_out is not None
    res["P"] = np.zeros((n_out, pb.p_out.size)) if want_p else None
    dt = np.diff(taus)[:, None]
    xi = x[None, 1:-1]
    cn = dt * theta[:, None]
    co = dt * (1.0 - theta[:, None])

    def ops(tag: str):
        w = ed["w" + tag][:, None]
        v = ed["lv" + tag][:, None] + xi * ed["wv" + tag][:, None]
        r = ed["wv" + tag][:, None] / w
        return (
            st.lap_sub / w**2 + v * st.der_sub / w,
            st.lap_dia / w**2 + v * st.der_dia / w + r,
            st.lap_sup / w**2 + v * st.der_sup / w,
        )

    b_sub, b_dia, b_sup = ops("b")
    a_sub, a_dia, a_sup = ops("a")
    i_sub, i_dia, i_sup = -cn * b_sub, 1.0 - cn * b_dia, -cn * b_sup
    e_sub, e_dia, e_sup = co * a_sub, 1.0 + co * a_dia, co * a_sup
    n_steps = taus.size - 1
    dl = np.zeros((n_steps, nn - 1))
    du = np.zeros((n_steps, nn - 1))
    dd = np.ones((n_steps, nn))
    dl[:, :-1] = i_sub
    dd[:, 1:-1] = i_dia
    du[:, 1:] = i_sup
    dlo, dhi = st.d_lo, st.d_hi
    la, wa_, lb, wb_ = ed["la"], ed["wa"], ed["lb"], ed["wb"]
    rl, ru = ed["rl"], ed["ru"]
    ysa, ysb = ed["ysa"], ed["ysb"]
    yield_wall = plan.yield_wall
    # initial free Gaussian (density per unit x)
    p = la[0] + wa_[0] * x
    r = wa_[0] * np.exp(-((p - p0) ** 2) / (4.0 * taus[0])) / math.sqrt(4.0 * math.pi * taus[0])
    r[0] = 0.0
    r[-1] = 0.0
    a_pl = 0.0
    abs_l = abs_u = mom_l = mom_u = 0.0
    b = np.zeros(nn)

    def record(j: int, lv: float, wv: float) -> None:
        pm = lv + wv * x
        res["area"][j] = np.dot(st.w, r)
        res["load"][j] = np.dot(st.w, pm * r)
        res["abs_l"][j], res["mom_l"][j] = abs_l, mom_l
        if yield_wall:
            res["abs_u"][j], res["mom_u"][j] = a_pl, (lv + wv) * a_pl
        else:
            res["abs_u"][j], res["mom_u"][j] = abs_u, mom_u
        if want_p:
            cs = CubicSpline(pm, r / wv)
            pv = pb.p_out
            inside = (pv >= pm[0]) & (pv <= pm[-1])
            res["P"][j, inside] = cs(pv[inside])

    nxt = 0
    while nxt < n_out and out_at[nxt] == 0:
        record(nxt, la[0], wa_[0])
        nxt += 1
    for m in range(n_steps):
        w0, w1 = wa_[m], wb_[m]
        # P_p at the walls at the start of the step (regime of this step)
        f_lo = (dlo[0] * r[0] + dlo[1] * r[1] + dlo[2] * r[2]) / w0**2
        f_hi = (dhi[0] * r[-1] + dhi[1] * r[-2] + dhi[2] * r[-3]) / w0**2
        b[1:-1] = e_sub[m] * r[:-2] + e_dia[m] * r[1:-1] + e_sup[m] * r[2:]
        th = theta[m]
        step = dt[m, 0]
        wn, wo = th * step, (1.0 - th) * step
        yield_real = yield_wall and ru[m]
        if yield_real:
            # row N:  R_N (1 + ys wn (ys + d0/W)) + ys wn (d1/W) R_{N-1} + ys wn (d2/W) R_{N-2}
            #         = W ys (A_pl + wo g_old),   g = -Y' P(Y) - P_p(Y)
            ys = ysb[m]
            g_old = -ysa[m] * r[-1] / w0 - f_hi
            d0, d1, d2 = dhi / w1
            r0, r1, r2 = ys * wn * d2, ys * wn * d1, 1.0 + ys * wn * (ys + d0)
            fac = r0 / i_sub[m, -1] if i_sub[m, -1] != 0.0 else 0.0
            row_dl = dl[m].copy()
            row_dd = dd[m].copy()
            row_dl[-1] = r1 - fac * i_dia[m, -1]
            row_dd[-1] = r2 - fac * i_sup[m, -1]
            b[-1] = w1 * ys * (a_pl + wo * g_old) - fac * b[-2]
            _, _, _, r_new, info = dgtsv(row_dl, row_dd, du[m], b)
            b[-1] = 0.0
        else:
            _, _, _, r_new, info = dgtsv(dl[m], dd[m], du[m], b)
        if info != 0:
            raise FloatingPointError(f"tridiagonal solve failed (info={info})")
        fl_new = (dlo[0] * r_new[0] + dlo[1] * r_new[1] + dlo[2] * r_new[2]) / w1**2
        fh_new = (dhi[0] * r_new[-1] + dhi[1] * r_new[-2] + dhi[2] * r_new[-3]) / w1**2
        if rl[m]:
            abs_l += wn * fl_new + wo * f_lo
            mom_l += wn * lb[m] * fl_new + wo * la[m] * f_lo
        if yield_real:
            g_new = -ysb[m] * r_new[-1] / w1 - fh_new
            a_pl += wn * g_new + wo * g_old
        elif ru[m] and not yield_wall:
            abs_u -= wn * fh_new + wo * f_hi
            mom_u -= wn * (lb[m] + w1) * fh_new + wo * (la[m] + w0) * f_hi
        r = r_new
        while nxt < n_out and out_at[nxt] == m + 1:
            record(nxt, lb[m], w1)
            nxt += 1
    res["nsteps"] = n_steps
    res["n_nodes"] = nn
    return res


class CNMethod(EngineMethod):
    """Moving (or fixed) walls: front-fixed Crank-Nicolson with Richardson control."""

    name = "cn"

    @classmethod
    def admits(cls, problem: Problem) -> bool:
        return True

    def run(self) -> Raw:
        pb = self.problem
        opt = pb.options
        scale = (1e-6 / pb.rtol) ** 0.25
        n0 = int(opt.get("nodes", max(24, 2 * int(round(39 * scale)))))
        per_dec = float(opt.get("steps_per_decade", max(6.0, n0 / 4.0)))
        max_levels = int(opt.get("levels", 5))
        stretch = float(opt.get("stretch", 1.0))
        n_ie = int(opt.get("rannacher", 2))
        k = float(opt.get("window_k", window_k(pb.atol)))
        plan = _plan(pb, k, per_dec)
        tau = pb.tau
        n_t = tau.size
        analytic = tau <= plan.tau_s
        num = ~analytic
        raw_levels: list[dict] = []
        status, message = "success", ""
        nsteps = 0
        best: dict | None = None
        err = np.full(int(num.sum()), np.inf)
        keys = (*_KEYS, "P")
        if num.any():
            ext1: list[dict] = []  # Richardson (4th order) values E_l
            for lev in range(max_levels):
                need = (plan.base.size - 1) * 2**lev + 2 * n_ie
                if nsteps + need > pb.max_steps:
                    status = "max_steps"
                    message = f"max_steps = {pb.max_steps} reached before the tolerance was met"
                    break
                try:
                    r = _march(pb, plan, n0 * 2**lev, 2**lev, stretch, n_ie)
                except FloatingPointError as exc:
                    status, message = "tolerance_not_met", f"numerical failure: {exc}"
                    break
                nsteps += r["nsteps"]
                raw_levels.append(r)
                if lev == 0:
                    best = r
                    continue
                prev = raw_levels[-2]
                e = {
                    key: None if r[key] is None else r[key] + (r[key] - prev[key]) / 3.0
                    for key in keys
                }
                ext1.append(e)
                if lev == 1:
                    best = e
                    err = np.abs(r["area"] - prev["area"])  # ~ 3x the error of E_1
                    continue
                e_prev = ext1[-2]
                best = {
                    key: None if e[key] is None else e[key] + (e[key] - e_prev[key]) / 15.0
                    for key in keys
                }
                # error of E_l (4th order) ~ |E_l - E_{l-1}|/15; doubled: bounds the Romberg value
                err = 2.0 * np.abs(e["area"] - e_prev["area"]) / 15.0
                if np.all(err <= pb.tolerance(best["area"])):
                    break
            if best is None:
                return self._failed(status, message or "no level completed", nsteps)
            if status == "success" and np.any(err > pb.tolerance(best["area"])):
                status = "tolerance_not_met"
                i = int(np.argmax(err / pb.tolerance(best["area"])))
                message = (
                    f"after {len(raw_levels)} levels (N = {raw_levels[-1]['n_nodes']}) the error "
                    f"estimate {err[i]:.2e} exceeds the tolerance at tau = {tau[num][i]:.6g} Pa^2"
                )
        area = np.ones(n_t)
        ab_l = np.zeros(n_t)
        ab_u = np.zeros(n_t)
        load = np.full(n_t, pb.p0)
        wall_term = np.zeros(n_t)
        e_all = np.zeros(n_t)
        trunc = 2.0 * math.erfc(k / math.sqrt(2.0))
        # analytic outputs: free Gaussian inside the window (walls unfelt to erfc(k/sqrt2))
        e_all[analytic & (tau > 0)] = trunc
        if best is not None and num.any():
            area[num] = np.maximum(best["area"], 0.0)
            ab_l[num] = best["abs_l"]
            ab_u[num] = best["abs_u"]
            load[num] = best["load"]
            wall_term[num] = best["mom_l"] + best["mom_u"]
            e_all[num] = err + trunc
        P = None
        if pb.p_out is not None:
            P = np.zeros((n_t, pb.p_out.size))
            for i in np.flatnonzero(analytic & (tau > 0)):
                t = tau[i]
                P[i] = np.exp(-((pb.p_out - pb.p0) ** 2) / (4 * t)) / math.sqrt(4 * math.pi * t)
            if best is not None and num.any():
                P[num] = np.maximum(best["P"], 0.0)
        if status == "success" and not message:
            message = (
                f"{len(raw_levels)} Richardson levels, finest N = {raw_levels[-1]['n_nodes']}"
                if raw_levels
                else "analytic start covers every output"
            )
        return Raw(
            area=area,
            non_area=ab_l + ab_u,
            absorbed_lower=ab_l,
            absorbed_upper=ab_u,
            load=load,
            wall_term=wall_term,
            error_estimate=e_all,
            P=P,
            status=status,
            message=message,
            nsteps=nsteps,
            n_nodes=raw_levels[-1]["n_nodes"] if raw_levels else 0,
            nfev=nsteps,
        )

    def _failed(self, status: str, message: str, nsteps: int) -> Raw:
        n_t = self.problem.tau.size
        nan = np.full(n_t, np.nan)
        return Raw(nan, nan, nan, nan, nan, nan, nan, None, status, message, nsteps, 0, nsteps)
