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


def _plan(pb: Problem, k: float, per_decade: float) -> _Plan:
    tau_s = _start_time(pb, k)
    outs = pb.tau[pb.tau > tau_s]
    yield_wall = pb.upper is not None and not pb.upper.acts_absorbing
    if outs.size == 0:
        return _Plan(np.array([tau_s]), np.zeros(0, int), tau_s, k, yield_wall)
    decades = math.log10(outs[-1] / tau_s)
    n_geo = max(1, int(math.ceil(decades * per_decade)))
    geo = tau_s * np.logspace(0.0, decades, n_geo + 1)
    # merge outputs; drop geometric points too close to an output
    ratio = 10 ** (1.0 / per_decade) - 1.0
    keep = np.ones(geo.size, bool)
    for t in outs:
        keep &= np.abs(geo - t) > 0.3 * ratio * t
    keep[0] = True
    base = np.union1d(geo[keep & (geo < outs[-1])], outs)
    idx = np.searchsorted(base, outs)
    return _Plan(base, idx, tau_s, k, yield_wall)


def _refine(base: Array, nsub: int) -> Array:
    d = np.diff(base)
    frac = np.arange(nsub) / nsub
    t = (base[:-1, None] + d[:, None] * frac[None, :]).ravel()
    return np.append(t, base[-1])


def _march(pb: Problem, plan: _Plan, n: int, nsub: int, stretch: float, n_ie: int) -> dict:
    """One level: returns the outputs (arrays over numerical outputs) and counters."""
    taus = _refine(plan.base, nsub)
    out_at = plan.out_index * nsub
    st = Stencils(clustered(n, stretch))
    x = st.x
    k, p0 = plan.k, pb.p0
    sig = np.sqrt(2.0 * taus)
    lo, up = pb.wall_positions(taus)
    real_l = lo >= p0 - k * sig
    le = np.where(real_l, lo, p0 - k * sig)
    if plan.yield_wall:
        real_u = np.logical_or.accumulate(up <= p0 + k * sig)
        ue = np.where(real_u, up, p0 + k * sig)
        yspeed = np.where(real_u, pb.upper.speed(taus), 0.0)
    else:
        real_u = up <= p0 + k * sig
        ue = np.where(real_u, up, p0 + k * sig)
        yspeed = np.zeros_like(taus)
    width = ue - le
    n_out = out_at.size
    res = {key: np.zeros(n_out) for key in _KEYS}
    want_p = pb.p_out is not None
    res["P"] = np.zeros((n_out, pb.p_out.size)) if want_p else None
    if np.any(width <= 0):
        raise FloatingPointError("the walls swept the whole window (area 0)")
    # initial free Gaussian
    p = le[0] + width[0] * x
    q = np.exp(-((p - p0) ** 2) / (4.0 * taus[0])) / math.sqrt(4.0 * math.pi * taus[0])
    q[0] = 0.0
    q[-1] = 0.0
    a_pl = 0.0
    acc = dict.fromkeys(("abs_l", "abs_u", "mom_l", "mom_u"), 0.0)
    xi = x[1:-1]

    def flux(qv: Array, w: float) -> tuple[float, float]:
        f_lo = (st.d_lo[0] * qv[0] + st.d_lo[1] * qv[1] + st.d_lo[2] * qv[2]) / w
        f_hi = (st.d_hi[0] * qv[-1] + st.d_hi[1] * qv[-2] + st.d_hi[2] * qv[-3]) / w
        return f_lo, f_hi  # P_p at the lower and at the upper wall

    def apply(qv: Array, w: float, v: Array) -> Array:
        lap = st.lap_sub * qv[:-2] + st.lap_dia * qv[1:-1] + st.lap_sup * qv[2:]
        der = st.der_sub * qv[:-2] + st.der_dia * qv[1:-1] + st.der_sup * qv[2:]
        return lap / w**2 + v * der / w

    def record(j: int, m: int) -> None:
        pm = le[m] + width[m] * x
        res["area"][j] = width[m] * np.dot(st.w, q)
        res["load"][j] = width[m] * np.dot(st.w, pm * q)
        for key in acc:
            res[key][j] = acc[key]
        if plan.yield_wall:
            res["abs_u"][j] = a_pl
            res["mom_u"][j] = ue[m] * a_pl
        if want_p:
            cs = CubicSpline(pm, q)
            pv = pb.p_out
            inside = (pv >= pm[0]) & (pv <= pm[-1])
            res["P"][j, inside] = cs(pv[inside])

    f_lo, f_hi = flux(q, width[0])
    nxt = 0
    while nxt < n_out and out_at[nxt] == 0:
        record(nxt, 0)
        nxt += 1
    n_steps = taus.size - 1
    half_steps = []  # Rannacher: the first n_ie steps as two implicit-Euler halves
    for m in range(n_steps):
        t0, t1 = taus[m], taus[m + 1]
        if m < n_ie:
            mid = 0.5 * (t0 + t1)
            half_steps = [(t0, mid, 1.0), (mid, t1, 1.0)]
        else:
            half_steps = [(t0, t1, 0.5)]
        for ta, tb, theta in half_steps:
            # wall data at ta, tb (linear inside the step for the Rannacher halves)
            fa = (ta - t0) / (t1 - t0)
            fb = (tb - t0) / (t1 - t0)
            la = le[m] + fa * (le[m + 1] - le[m])
            lb = le[m] + fb * (le[m + 1] - le[m])
            wa = width[m] + fa * (width[m + 1] - width[m])
            wb = width[m] + fb * (width[m + 1] - width[m])
            ys_a = yspeed[m] + fa * (yspeed[m + 1] - yspeed[m])
            ys = yspeed[m] + fb * (yspeed[m + 1] - yspeed[m])
            dt = tb - ta
            v = ((lb - la) + xi * (wb - wa)) / dt
            rhs = q[1:-1].copy()
            if theta < 1.0:
                rhs += dt * (1.0 - theta) * apply(q, wa, v)
            c = dt * theta
            sub = -c * (st.lap_sub / wb**2 + v * st.der_sub / wb)
            dia = 1.0 - c * (st.lap_dia / wb**2 + v * st.der_dia / wb)
            sup = -c * (st.lap_sup / wb**2 + v * st.der_sup / wb)
            nn = x.size
            dl = np.zeros(nn - 1)
            du = np.zeros(nn - 1)
            dd = np.ones(nn)
            b = np.zeros(nn)
            dd[1:-1] = dia
            dl[:-1] = sub
            du[1:] = sup
            b[1:-1] = rhs
            yield_real = plan.yield_wall and real_u[m + 1]
            if yield_real:
                # row N: Q_N (1 + ys c (ys + d0/w)) + ys c (d1/w) Q_{N-1} + ys c (d2/w) Q_{N-2}
                #        = ys (A_pl + dt (1 - theta) g_old),  g = -Y' P(Y) - P_p(Y)
                old_real = real_u[m] or ta > t0
                g_old = (-ys_a * q[-1] - f_hi) if (theta < 1.0 and old_real) else 0.0
                d0, d1, d2 = st.d_hi / wb
                r_n = np.array([ys * c * d2, ys * c * d1, 1.0 + ys * c * (ys + d0)])
                b_n = ys * (a_pl + dt * (1.0 - theta) * g_old)
                # eliminate Q_{N-2} with row N-1 (entries at N-2, N-1, N)
                fac = r_n[0] / sub[-1] if sub[-1] != 0.0 else 0.0
                dl[-1] = r_n[1] - fac * dia[-1]
                dd[-1] = r_n[2] - fac * sup[-1]
                b[-1] = b_n - fac * rhs[-1]
            _, _, _, sol, info = dgtsv(dl, dd, du, b)
            if info != 0:
                raise FloatingPointError(f"tridiagonal solve failed (info={info})")
            q_new = sol
            f_lo_new, f_hi_new = flux(q_new, wb)
            wt_new, wt_old = theta * dt, (1.0 - theta) * dt
            ra, rb = real_l[m], real_l[m + 1]
            acc["abs_l"] += wt_new * f_lo_new * rb + wt_old * f_lo * ra
            acc["mom_l"] += wt_new * lb * f_lo_new * rb + wt_old * la * f_lo * ra
            if plan.yield_wall:
                if yield_real:
                    g_new = -ys * q_new[-1] - f_hi_new
                    g_old = (-ys_a * q[-1] - f_hi) if old_real else 0.0
                    a_pl += wt_new * g_new + wt_old * g_old
            else:
                ua, ub = la + wa, lb + wb
                sa, sb = real_u[m], real_u[m + 1]
                acc["abs_u"] -= wt_new * f_hi_new * sb + wt_old * f_hi * sa
                acc["mom_u"] -= wt_new * ub * f_hi_new * sb + wt_old * ua * f_hi * sa
            q, f_lo, f_hi = q_new, f_lo_new, f_hi_new
        while nxt < n_out and out_at[nxt] == m + 1:
            record(nxt, m + 1)
            nxt += 1
    res["nsteps"] = n_steps + n_ie
    res["n_nodes"] = x.size
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
        tol_scale = (pb.rtol / 1e-6) ** 0.25
        n0 = int(opt.get("nodes", max(24, int(round(64 / tol_scale / 2) * 2))))
        per_dec = float(opt.get("steps_per_decade", max(4.0, 16.0 / tol_scale)))
        max_levels = int(opt.get("levels", 6))
        min_levels = int(opt.get("min_levels", 3))
        stretch = float(opt.get("stretch", 1.0))
        n_ie = int(opt.get("rannacher", 2))
        k = float(opt.get("window_k", window_k(pb.atol)))
        plan = _plan(pb, k, per_dec)
        tau = pb.tau
        n_t = tau.size
        analytic = tau <= plan.tau_s
        num = ~analytic
        levels: list[dict] = []
        extrap: list[dict] = []
        status, message = "success", ""
        nsteps = 0
        err = np.zeros(int(num.sum()))
        if num.any():
            for lev in range(max_levels):
                n_steps_next = (plan.base.size - 1) * 2**lev + n_ie
                if nsteps + n_steps_next > pb.max_steps:
                    status = "max_steps"
                    message = f"max_steps = {pb.max_steps} reached before the tolerance was met"
                    break
                try:
                    r = _march(pb, plan, n0 * 2**lev, 2**lev, stretch, n_ie)
                except FloatingPointError as exc:
                    status, message = "tolerance_not_met", f"numerical failure: {exc}"
                    break
                nsteps += r["nsteps"]
                levels.append(r)
                if lev == 0:
                    extrap.append(r)
                    continue
                prev = levels[-2]
                e = {}
                for key in (*_KEYS, "P"):
                    if r[key] is None:
                        e[key] = None
                    else:
                        e[key] = r[key] + (r[key] - prev[key]) / 3.0
                extrap.append(e)
                if lev >= 2:
                    err = np.abs(e["area"] - extrap[-2]["area"])
                else:
                    err = np.abs(r["area"] - prev["area"])  # error of the finer raw level
                if lev + 1 >= min_levels and np.all(err <= pb.tolerance(e["area"])):
                    break
            else:
                pass
            if not extrap:
                return self._failed(status or "tolerance_not_met", message, nsteps)
            if len(extrap) == 1:
                err = np.full(err.shape, np.inf)
        best = extrap[-1] if extrap else None
        area = np.ones(n_t)
        ab_l = np.zeros(n_t)
        ab_u = np.zeros(n_t)
        load = np.full(n_t, pb.p0)
        wall_term = np.zeros(n_t)
        e_all = np.zeros(n_t)
        # analytic outputs: free Gaussian inside the window (walls unfelt to erfc(k/sqrt2))
        e_all[analytic & (tau > 0)] = 2.0 * math.erfc(k / math.sqrt(2.0))
        if best is not None and num.any():
            area[num] = np.maximum(best["area"], 0.0)
            ab_l[num] = best["abs_l"]
            ab_u[num] = best["abs_u"]
            load[num] = best["load"]
            wall_term[num] = best["mom_l"] + best["mom_u"]
            e_all[num] = err + 2.0 * math.erfc(k / math.sqrt(2.0))
        P = None
        if pb.p_out is not None:
            P = np.zeros((n_t, pb.p_out.size))
            for i in np.flatnonzero(analytic & (tau > 0)):
                t = tau[i]
                P[i] = np.exp(-((pb.p_out - pb.p0) ** 2) / (4 * t)) / math.sqrt(4 * math.pi * t)
            if best is not None and num.any():
                P[num] = np.maximum(best["P"], 0.0)
        if status == "success" and not message:
            message = f"{len(levels)} Richardson levels, finest N = {levels[-1]['n_nodes']}" if (
                levels) else "analytic start covers every output"
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
            n_nodes=levels[-1]["n_nodes"] if levels else 0,
            nfev=nsteps,
        )

    def _failed(self, status: str, message: str, nsteps: int) -> Raw:
        n_t = self.problem.tau.size
        nan = np.full(n_t, np.nan)
        return Raw(nan, nan, nan, nan, nan, nan, nan, None, status, message, nsteps, 0, nsteps)
