"""Front-fixed Crank-Nicolson solver for moving walls (absorbing or yield closure).

Scheme
------
* Window.  The free solution ``G = N(p; p0, 2 tau)`` bounds P from above for absorbing walls, and
  mass released by a yield wall starts above ``p0``; so the domain is truncated to
  ``[max(l, p0 - k s), min(u, p0 + k s)]`` with ``s = sqrt(2 tau)`` and artificial absorbing walls
  where the real ones are farther (error ``<= erfc(k/sqrt 2)`` each, ``k`` from ``atol``).  The
  window follows the growing support ``~ sqrt(tau)``; a yield wall stays real once it entered.
* Front fixing.  Nodes ``p_j(tau) = l_eff(tau) + W(tau) x_j`` on a fixed map ``x_j`` of [0, 1]
  clustered at both walls.  The unknown ``R = W P`` (mass per unit x) obeys the conservation law
  ``R_tau = d/dx [R_x / W^2 + (v / W) R]`` with the mesh velocity ``v = l_eff' + x W'``.
* Finite volumes.  Control volumes between face midpoints (the trapezoid weights), face fluxes
  ``F = (R_{j+1} - R_j)/(W^2 dx) + v (R_j + R_{j+1})/(2W)``: the discrete mass changes exactly
  by the wall fluxes, which are what is counted as absorbed (non-contact / plastic area), so
  ``area + absorbed = initial mass`` holds to round-off at every step and every refinement level
  (and for their Richardson combination): the area never exceeds 1.
* Start.  Analytic: the free Gaussian at ``tau_s``, the largest time at which no real wall lies
  inside the window (its discrete mass set to the window mass ``erf(k/sqrt 2)``).
* Time.  Geometric steps merged with the output times and the kinks of the window edges;
  Crank-Nicolson with two implicit-Euler half steps first (Rannacher).  One tridiagonal solve
  per step for all loads of a batch (their systems concatenated); the operators are built
  vectorised for a block of steps at a time, so memory stays proportional to the grid and a
  step costs one flux-form product and one LAPACK ``dgtsv`` call.
* Yield closure.  ``P(Y) = A_pl Y'``: the last node is a half cell whose mass plus ``A_pl``
  changes by the flux through its inner face (``dA_pl/dtau = -Y' P(Y) - P_p(Y)`` at the wall),
  solved implicitly with the interior (one row of the tridiagonal system).
* Accuracy (aimed at the request).  A pilot pair of grids ``(N0, 2 N0)`` measures the constant
  of the second-order error; the final grid ``N`` is chosen so that the error estimate of the
  result is about ``AIM = 0.5`` times ``rtol |A| + atol`` (the actual error about half of it:
  0.15-0.4 rtol on the benchmark scenes) and the pair ``(N/2, N)`` is solved; the result is the
  finer solution, its error estimate ``2 |R_N - R_{N/2}| / 3`` (twice the asymptotic value).
  For tight tolerances, where second order would need very fine grids, the pair is combined by
  Richardson extrapolation and its (fourth-order) error predicted from three pilot levels.
  If an estimate misses the tolerance the grid is refined again, up to ``max_steps`` /
  ``levels``; ``status`` says when it could not.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import CubicSpline
from scipy.optimize import brentq

from ._base import EngineMethod
from ._cnstep import tridiagonal_solve
from ._grid import clustered
from ._problem import Problem, window_k
from ._progress import report as report_progress
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
    zones: tuple[tuple[float, float], ...] = ()  # graded stretches (tau_b, tau_end) after
    # declared wall breakpoints: steps uniform in (tau - tau_b)^(1/4), implicit first step;
    # chord mesh speeds from the first breakpoint on


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


def _level_times(
    base: Array, nsub: int, n_ie: int, zones: tuple[tuple[float, float], ...] = ()
) -> tuple[Array, Array]:
    """Nested refinement of ``base`` plus Rannacher halves; returns (times, theta per step).

    Inside a graded zone ``(tau_b, tau_e)`` the steps are subdivided uniformly in
    ``(tau - tau_b)^(1/4)`` and the step starting at ``tau_b`` is implicit Euler (the wall's
    speed may be unbounded there).
    """
    d = np.diff(base)
    frac = np.arange(nsub) / nsub
    a = base[:-1]
    sub = a[:, None] + d[:, None] * frac[None, :]
    for tb, te in zones:
        m = (a >= tb) & (base[1:] <= te)
        if m.any() and nsub > 1:
            ua, ub = (a[m] - tb) ** (1 / _GRADE), (base[1:][m] - tb) ** (1 / _GRADE)
            sub[m] = tb + (ua[:, None] + (ub - ua)[:, None] * frac[None, :]) ** _GRADE
            sub[m, 0] = a[m]
    t = np.append(sub.ravel(), base[-1])
    n_ie = min(n_ie, t.size - 1)
    if n_ie > 0:
        mids = 0.5 * (t[:n_ie] + t[1 : n_ie + 1])
        t = np.sort(np.concatenate([t, mids]))
    theta = np.full(t.size - 1, 0.5)
    theta[: 2 * n_ie] = 1.0
    if zones:
        theta[np.isin(t[:-1], [tb for tb, _ in zones])] = 1.0
    return t, theta


def _wall_speeds(wall, tau: Array) -> tuple[Array, Array]:
    """dp_w/dtau [1/Pa] of a wall at ``tau`` just before and just after (declared, or by central
    differences).

    The two differ only at the wall's declared breakpoints, where the difference is one-sided
    (the speed just before ends a step, the speed just after starts one).
    """
    if wall is None or wall.is_fixed:
        z = np.zeros_like(tau)
        return z, z
    if wall.dposition is not None:
        v = wall.speed(tau)
        return v, v
    if wall.motion is not None:
        v = np.full_like(tau, wall.motion[1])
        return v, v
    h = 1e-5 * tau
    bp = getattr(wall, "breakpoints", ())
    if bp:
        # never difference across a breakpoint: the step shrinks with the distance to it
        b = np.asarray(bp)
        dist = np.min(np.abs(tau[..., None] - b), axis=-1)
        h = np.where(dist > 0, np.minimum(h, 1e-3 * dist), h)
    hi, lo = tau + h, tau - h
    p_hi, p_lo = np.split(wall.at(np.concatenate([hi, lo])), 2)  # one call of the wall
    v = (p_hi - p_lo) / (hi - lo)
    before, after = v, v
    at_bp = np.isin(tau, bp) if bp else np.zeros(tau.shape, bool)
    if at_bp.any():
        t = tau[at_bp]
        p_t = wall.at(t)
        before, after = v.copy(), v.copy()
        before[at_bp] = (p_t - p_lo[at_bp]) / (t - lo[at_bp])
        after[at_bp] = (p_hi[at_bp] - p_t) / (hi[at_bp] - t)
    return before, after


def _tracks(pb: Problem, taus: Array) -> dict:
    """The walls along a time sequence (shared by the loads of a batch): positions [Pa] at the
    step midpoints and at ``taus``, speeds [1/Pa] just before / after each time."""
    mid = 0.5 * (taus[:-1] + taus[1:])
    lo, up = pb.wall_positions(np.concatenate([mid, taus]))  # one call of each wall
    n = mid.size
    lo_m, up_m, lo, up = lo[:n], up[:n], lo[n:], up[n:]
    lo_vb, lo_va = _wall_speeds(pb.lower, taus)
    if pb.upper is not None:
        up_vb, up_va = _wall_speeds(pb.upper, taus)
        ys = pb.upper.speed(taus)
    else:
        up_vb = up_va = ys = np.zeros_like(taus)
    return {
        "mid": mid,
        "lo_m": lo_m,
        "up_m": up_m,
        "lo": lo,
        "up": up,
        "lo_vb": lo_vb,
        "lo_va": lo_va,
        "up_vb": up_vb,
        "up_va": up_va,
        "ys": ys,
    }


def _edges(pb: Problem, plan: _Plan, taus: Array, tr: dict | None = None) -> dict:
    """Window edges and their speeds at the start (a) and end (b) of every step.

    The regime of each edge (real wall or artificial edge ``p0 -/+ k sqrt(2 tau)``) is fixed per
    step (at its midpoint); the kinks where it changes are step boundaries (see ``_plan``).
    ``tr``: the walls along ``taus`` (:func:`_tracks`), computed here unless given.
    """
    if tr is None:
        tr = _tracks(pb, taus)
    k, p0 = plan.k, pb.p0
    mid = tr["mid"]
    s_m = np.sqrt(2.0 * mid)
    rl = tr["lo_m"] >= p0 - k * s_m
    if plan.yield_wall:
        ru = np.logical_or.accumulate(tr["up_m"] <= p0 + k * s_m)
    else:
        ru = tr["up_m"] <= p0 + k * s_m
    out = {"rl": rl, "ru": ru}
    for tag, sl in (("a", slice(None, -1)), ("b", slice(1, None))):
        t = taus[sl]
        s = np.sqrt(2.0 * t)
        ds = 1.0 / s
        lo, up = tr["lo"][sl], tr["up"][sl]
        lo_v, up_v = tr["lo_v" + tag][sl], tr["up_v" + tag][sl]
        le = np.where(rl, lo, p0 - k * s)
        ue = np.where(ru, up, p0 + k * s)
        out["l" + tag] = le
        out["w" + tag] = ue - le
        out["lv" + tag] = np.where(rl, lo_v, -k * ds)
        out["wv" + tag] = np.where(ru, up_v, k * ds) - out["lv" + tag]
        out["ys" + tag] = np.where(ru, tr["ys"][sl], 0.0) if plan.yield_wall else 0.0 * t
    # from the first breakpoint on, the mesh moves with the chord speeds of each step (the
    # exact displacement of the edges: the wall may move like sqrt(tau - tau_b), whose point
    # speeds are unbounded and made the scheme first order; after the graded stretch the chord
    # speeds also keep the Richardson control's error expansion clean)
    chord = np.zeros(mid.shape, bool)
    if plan.zones:
        chord |= taus[:-1] >= plan.zones[0][0]
    if chord.any():
        dt = np.diff(taus)
        lvc = (out["lb"] - out["la"]) / dt
        wvc = (out["wb"] - out["wa"]) / dt
        for tag in ("a", "b"):
            out["lv" + tag] = np.where(chord, lvc, out["lv" + tag])
            out["wv" + tag] = np.where(chord, wvc, out["wv" + tag])
    out["chord"] = chord
    return out


def _faces(x: Array) -> tuple[Array, Array, Array]:
    """Face midpoints, node spacings and trapezoid weights (control volumes) of ``x``."""
    w = np.zeros_like(x)
    d = np.diff(x)
    w[:-1] += d / 2
    w[1:] += d / 2
    return 0.5 * (x[1:] + x[:-1]), d, w


def _edges_batch(pbs: list[Problem], plan: _Plan, taus: Array) -> dict:
    tr = _tracks(pbs[0], taus)  # the loads of a batch share their walls
    eds = [_edges(pb, plan, taus, tr) for pb in pbs]
    if len(eds) == 1:
        return {key: val[None] for key, val in eds[0].items()}
    return {key: np.stack([e[key] for e in eds]) for key in eds[0]}


def _march(pbs: list[Problem], plan: _Plan, n: int, nsub: int, stretch: float, n_ie: int) -> dict:
    """One grid level (``n`` intervals, ``nsub`` substeps per base step) for a batch of loads.

    Returns per-load outputs ``(n_load, n_out)`` at the numerical output times.

    The loads' systems are concatenated (boundary rows are identity rows, so they do not
    couple).  The operators are built vectorised for a block of steps at a time (memory
    proportional to the grid times the block, see ``_BLOCK``); a step is then one explicit
    tridiagonal product, one LAPACK ``dgtsv`` solve and a gather of the three nodes next to the
    walls, from which the wall fluxes (absorbed probabilities, wall moments) are summed after
    the march.
    """
    taus, theta = _level_times(plan.base, nsub, n_ie, plan.zones)
    pb0 = pbs[0]
    nb = len(pbs)
    out_at = np.searchsorted(taus, pb0.tau[pb0.tau > plan.tau_s])
    x = clustered(n, stretch)
    nn = x.size
    xf, dxf, w = _faces(x)
    ed = _edges_batch(pbs, plan, taus)
    if np.any(ed["wa"] <= 0) or np.any(ed["wb"] <= 0):
        raise FloatingPointError("the walls swept the whole window (area 0)")
    n_out = out_at.size
    res = {key: np.zeros((nb, n_out)) for key in _KEYS}
    want_p = pb0.p_out is not None
    res["P"] = np.zeros((nb, n_out, pb0.p_out.size)) if want_p else None
    yield_wall = plan.yield_wall
    p0 = np.array([pb.p0 for pb in pbs])[:, None]
    la, wa_, lb, wb_ = ed["la"], ed["wa"], ed["lb"], ed["wb"]
    n_steps = taus.size - 1
    step = np.diff(taus)
    wn_all, wo_all = theta * step, (1.0 - theta) * step
    rl, ru = ed["rl"], ed["ru"]
    yreal = ru & yield_wall
    # g = W Y' of the yield closure R_N = g A_pl (0 where the yield wall is not real)
    g_all = np.where(yreal, wb_ * ed["ysb"], 0.0)

    # face coefficients F = D (R_{j+1} - R_j) + A (R_j + R_{j+1}) at the start (a) and end (b)
    # of a step are outer products: D = (1/W^2) (1/dx_f), A = (lv + x_f wv) / (2W); returned
    # as (A - D, A + D), shaped (steps, loads, faces)
    def coefs(tag: str, ms: slice) -> tuple[Array, Array]:
        W = ed["w" + tag][:, ms].T[..., None]
        D = (1.0 / W**2) * (1.0 / dxf)
        A = (ed["lv" + tag][:, ms].T[..., None] + xf * ed["wv" + tag][:, ms].T[..., None]) / (
            2.0 * W
        )
        amd = A - D
        A += D
        return amd, A

    def end_faces(tag: str) -> tuple[Array, Array, Array, Array]:
        """(A-D) and (A+D) at the first face, then at the last face; (nb, n_steps)."""
        W = ed["w" + tag]
        lv, wv = ed["lv" + tag], ed["wv" + tag]
        # the same expressions as in coefs (bitwise): the wall fluxes must be the ones the
        # solve used, or the balance of large CN fluxes loses digits
        d0, d1 = (1.0 / W**2) * (1.0 / dxf[0]), (1.0 / W**2) * (1.0 / dxf[-1])
        a0, a1 = (lv + xf[0] * wv) / (2.0 * W), (lv + xf[-1] * wv) / (2.0 * W)
        return a0 - d0, a0 + d0, a1 - d1, a1 + d1

    # initial free Gaussian (mass per unit x), normalised to the window mass erf(k / sqrt 2)
    t0 = taus[0]
    pn = la[:, :1] + wa_[:, :1] * x[None, :]
    r2 = wa_[:, :1] * np.exp(-((pn - p0) ** 2) / (4.0 * t0)) / math.sqrt(4.0 * math.pi * t0)
    r2[:, 0] = 0.0
    r2[:, -1] = 0.0
    r2 *= math.erf(plan.k / math.sqrt(2.0)) / (r2 @ w)[:, None]
    r = r2.ravel()
    rows = np.arange(nb) * nn  # first node of each load in the concatenated system
    # the two nodes at each wall (the solve leaves round-off ~ eps on the wall nodes, which the
    # wall fluxes must include for the balance to hold to round-off)
    near = np.concatenate([rows, rows + 1, rows + nn - 2, rows + nn - 1])
    last = rows + nn - 1
    bnd = np.concatenate([rows, last])  # identity rows (the walls)
    wflat = np.tile(w, nb)
    wflat[bnd] = 0.0
    hist = np.empty((n_steps + 1, 4 * nb))  # R at `near` after every step
    hist[0] = r[near]
    a_pl = np.zeros(nb)
    a_pl_at = np.zeros((nb, n_out))
    if yield_wall:
        _, _, am1, ap1 = end_faces("a")
        _, _, bm1, bp1 = end_faces("b")
    w_last = w[-1]

    # outputs: snapshots of the state, reduced after the march (one copy per output instead of
    # a dozen small reductions), unless the density is wanted or the snapshots would be large
    snaps = None if want_p or n_out * nb * nn > _SNAP else np.empty((n_out, nb * nn))

    def record(j: int, m: int) -> None:
        """Outputs ``j`` after step ``m`` (the state ``r``; wall terms are added later)."""
        a_pl_at[:, j] = a_pl
        if snaps is not None:
            snaps[j] = r
            return
        r_ = r.reshape(nb, nn)
        lv, wv = (la[:, 0], wa_[:, 0]) if m == 0 else (lb[:, m - 1], wb_[:, m - 1])
        pm = lv[:, None] + wv[:, None] * x[None, :]
        res["area"][:, j] = r_ @ w
        res["load"][:, j] = (pm * r_) @ w
        if want_p:
            pv = pb0.p_out
            for i in range(nb):
                cs = CubicSpline(pm[i], r_[i] / wv[i])
                inside = (pv >= pm[i, 0]) & (pv <= pm[i, -1])
                res["P"][i, j, inside] = cs(pv[inside])

    out_steps = out_at.tolist() + [-1]
    nxt = 0
    while nxt < n_out and out_steps[nxt] == 0:
        record(nxt, 0)
        nxt += 1
    block = max(1, _BLOCK // (nb * nn))
    # work buffers of a step: face fluxes G, G2 and their differences dG
    G, G2, dG = np.empty(nb * nn - 1), np.empty(nb * nn - 1), np.empty(nb * nn - 2)
    G_hi, G_lo = G[1:], G[:-1]
    mul, sub = np.multiply, np.subtract
    wi = w[1:-1]
    nf = nn - 1
    for m0 in range(0, n_steps, block):
        ms = slice(m0, min(m0 + block, n_steps))
        c = ms.stop - ms.start
        wn = wn_all[ms, None, None]
        wo = wo_all[ms, None, None]
        g = g_all[:, ms].T  # (steps, loads)
        # the system of a step, one row per step with the loads concatenated: dgtsv's
        # sub-diagonal dl[r] (row r + 1), diagonal Dg[r], super-diagonal du[r] (row r); the
        # last slot of each load couples nothing (boundary rows are identity rows)
        # interior rows j = 1..n-1:
        #   w_j R_j - wn (F_{j+1/2} - F_{j-1/2}) = w_j R_j^old + wo (F^old_{j+1/2} - F^old_{j-1/2})
        amd, apd = coefs("b", ms)
        dl = np.empty((c, nb, nn))
        du = np.empty((c, nb, nn))
        Dg = np.empty((c, nb, nn))
        np.multiply(wn, amd, out=dl[..., :nf])  # coefficient of R_{j-1} in row j
        np.multiply(-wn, apd, out=du[..., :nf])  # coefficient of R_{j+1} in row j
        np.subtract(wi, dl[..., 1:nf], out=Dg[..., 1:-1])
        Dg[..., 1:-1] -= du[..., : nf - 1]
        Dg[..., 0] = 1.0
        # last row of a real yield wall: half cell plus A_pl, closure R_N = g A_pl
        Dg[..., -1] = 1.0 + g * (w_last + wn[..., 0] * apd[..., -1])
        dl[..., nf - 1] = g * wn[..., 0] * amd[..., -1]
        dl[..., nf] = 0.0
        du[..., 0] = 0.0
        du[..., nf] = 0.0
        # explicit half in flux form (the fluxes telescope: a product with the large
        # coefficients of a stiff step would lose the balance to round-off):
        #   rhs_j = w_j R_j + (G_{j+1/2} - G_{j-1/2}),  G = wo (A - D) R_j + wo (A + D) R_{j+1};
        # face j of a load is slot j; slot n (between two loads' systems) stays 0
        amd, apd = coefs("a", ms)
        Ga = np.empty((c, nb, nn))
        Gp = np.empty((c, nb, nn))
        np.multiply(wo, amd, out=Ga[..., :nf])
        np.multiply(wo, apd, out=Gp[..., :nf])
        Ga[..., nf] = 0.0
        Gp[..., nf] = 0.0
        # last row of a real yield wall: g (w_N R_N + A_pl - wo F_{N-1/2})
        ye_s = (-g * wo[..., 0] * amd[..., -1]).T
        ye_d = (g * (w_last - wo[..., 0] * apd[..., -1])).T
        del amd, apd
        dl, du, Dg, Ga, Gp = (a.reshape(c, nb * nn) for a in (dl, du, Dg, Ga, Gp))
        g = g.T
        ys = yreal[:, ms].any(axis=0).tolist()
        # the states of the block: row 0 the state before it, row i + 1 the state after step
        # m0 + i (the solve overwrites its right-hand side in place)
        states = np.empty((c + 1, nb * nn))
        states[0] = r
        # views made once per block (a step is ~10 numpy calls: their count is its cost)
        s_lo, s_hi, s_in = states[:, :-1], states[:, 1:], states[:, 1:-1]
        ga, gp, dl_, du_ = Ga[:, :-1], Gp[:, :-1], dl[:, :-1], du[:, :-1]
        for i in range(c):
            m = m0 + i
            mul(ga[i], s_lo[i], out=G)
            mul(gp[i], s_hi[i], out=G2)
            G += G2
            rhs = states[i + 1]
            mul(wflat, r, out=rhs)  # 0 on the walls' identity rows
            sub(G_hi, G_lo, out=dG)
            inner = s_in[i + 1]
            inner += dG
            if nb > 1:
                rhs[bnd] = 0.0
            if ys[i]:
                rhs[last] = ye_s[:, i] * r[last - 1] + ye_d[:, i] * r[last] + g[:, i] * a_pl
            sol = tridiagonal_solve(dl_[i], Dg[i], du_[i], rhs)
            if ys[i]:
                # dA_pl = out-flux through the last face + the half cell's loss
                f_new = bm1[:, m] * sol[last - 1] + bp1[:, m] * sol[last]
                f_old = am1[:, m] * r[last - 1] + ap1[:, m] * r[last]
                out_hi = -(wn_all[m] * f_new + wo_all[m] * f_old)
                a_pl = a_pl + np.where(yreal[:, m], out_hi + w_last * (r[last] - sol[last]), 0.0)
            r = sol
            while out_steps[nxt] == m + 1:
                record(nxt, m + 1)
                nxt += 1
            if (m + 1) % _REPORT_EVERY == 0:
                report_progress(_REPORT_EVERY * nn * nb)
        hist[m0 + 1 : m0 + c + 1] = states[1:, near]
        r = r.copy()  # the last state outlives its block
    report_progress((n_steps % _REPORT_EVERY) * nn * nb)
    if snaps is not None:
        # area int R dx and load int p R dx with p = l + W x, per output (nb, n_out)
        R = snaps.reshape(n_out, nb, nn)
        lv = np.hstack([la[:, :1], lb])[:, out_at]
        wv = np.hstack([wa_[:, :1], wb_])[:, out_at]
        res["area"] = (R @ w).T
        res["load"] = lv * res["area"] + wv * (R @ (x * w)).T
    # wall fluxes of every step from the nodes next to the walls (R = 0 on an absorbing wall)
    r0, r1, rm, rn = (hist[:, i * nb : (i + 1) * nb].T for i in range(4))  # (nb, n_steps + 1)
    am0a, ap0a, am1a, ap1a = end_faces("a")
    am0b, ap0b, am1b, ap1b = end_faces("b")
    f_old0 = am0a * r0[:, :-1] + ap0a * r1[:, :-1]
    f_new0 = am0b * r0[:, 1:] + ap0b * r1[:, 1:]
    f_old1 = am1a * rm[:, :-1] + ap1a * rn[:, :-1]
    f_new1 = am1b * rm[:, 1:] + ap1b * rn[:, 1:]
    wn_, wo_ = wn_all[None, :], wo_all[None, :]
    zero = np.zeros((nb, 1))
    abs_l = np.hstack([zero, np.cumsum(np.where(rl, wn_ * f_new0 + wo_ * f_old0, 0.0), axis=1)])
    mom_l = np.hstack(
        [zero, np.cumsum(np.where(rl, wn_ * lb * f_new0 + wo_ * la * f_old0, 0.0), axis=1)]
    )
    res["abs_l"], res["mom_l"] = abs_l[:, out_at], mom_l[:, out_at]
    if yield_wall:
        res["abs_u"] = a_pl_at
        ends = np.hstack([la[:, :1] + wa_[:, :1], lb + wb_])[:, out_at]
        res["mom_u"] = ends * a_pl_at
    else:
        out_hi = -(wn_ * f_new1 + wo_ * f_old1)
        mom = wn_ * (lb + wb_) * f_new1 + wo_ * (la + wa_) * f_old1
        res["abs_u"] = np.hstack([zero, np.cumsum(np.where(ru, out_hi, 0.0), axis=1)])[:, out_at]
        res["mom_u"] = -np.hstack([zero, np.cumsum(np.where(ru, mom, 0.0), axis=1)])[:, out_at]
    res["nsteps"] = n_steps
    res["n_nodes"] = nn
    return res


def _combine(fine: dict, coarse: dict, extrapolate: bool) -> dict:
    """The finer level, or its Richardson combination with the coarser (linear in the levels:
    the probability balance is kept)."""
    out = {}
    for key in (*_KEYS, "P"):
        if fine[key] is None:
            out[key] = None
        elif extrapolate:
            out[key] = fine[key] + (fine[key] - coarse[key]) / 3.0
        else:
            out[key] = fine[key]
    return out


class CNMethod(EngineMethod):
    """Moving (or fixed) walls: front-fixed finite-volume Crank-Nicolson, error aimed at rtol."""

    name = "cn"
    batched = True

    @classmethod
    def admits(cls, problem: Problem) -> bool:
        return True

    def run(self) -> Raw:
        pb = self.problem
        if pb.is_batch:
            n = pb.tau.shape[0]
            shared = bool(np.all(pb.tau == pb.tau[:1]))
            if not shared:  # loads on different clocks: one at a time
                raws = [self._run([pb.load(i)]) for i in range(n)]
                return _stack(raws)
            return self._run([pb.load(i) for i in range(n)])
        raw = self._run([pb])
        return _unbatch(raw)

    # -- the solver --------------------------------------------------------------------------
    def _run(self, pbs: list[Problem]) -> Raw:
        pb = pbs[0]
        opt = pb.options
        n0 = int(opt.get("nodes", 24))
        per_node = (
            float(opt.get("steps_per_decade", 0.0)) / n0 if "steps_per_decade" in opt else 0.25
        )
        max_levels = int(opt.get("levels", 10))
        max_work = float(opt.get("max_work", 1e8))  # node-steps per load over all grids
        stretch = float(opt.get("stretch", 1.0))
        n_ie = int(opt.get("rannacher", 2))
        k = float(opt.get("window_k", window_k(pb.atol)))
        aim = float(opt.get("aim", AIM))
        if not 0.0 < aim <= 1.0:
            raise ValueError(
                f"options['aim'] [1] (error estimate aimed at, as a fraction of "
                f"the tolerance) must be in (0, 1]; got {aim!r}"
            )
        tau = pb.tau
        tau_s = min(_start_time(p, k) for p in pbs)
        analytic = tau <= tau_s
        num = ~analytic
        nb = len(pbs)
        status, message = "success", ""
        nsteps = 0
        work = 0.0
        n_used = 0
        best: dict | None = None
        err = np.full((nb, int(num.sum())), np.inf)
        cache: dict[tuple[int, int], dict] = {}
        plans: dict[int, _Plan] = {}
        if num.any():
            # the kinks of the window edges do not depend on the grid: found once
            t_end = float(tau[num][-1])
            kinks = [t for p in pbs for t in _switch_times(p, k, tau_s, t_end)]

            def level(n_base: int, mult: int) -> dict:
                """Grid n_base * mult on the time plan of n_base subdivided mult times."""
                nonlocal nsteps, work
                key = (n_base, mult)
                if key not in cache:
                    if n_base not in plans:
                        plans[n_base] = _joint_plan(pbs, k, per_node * n_base, tau_s, kinks)
                    plan = plans[n_base]
                    cost = (plan.base.size - 1) * mult + 2 * n_ie
                    if nsteps + cost > pb.max_steps:
                        raise _Budget(
                            f"max_steps = {pb.max_steps} reached before the tolerance was met"
                        )
                    if work + cost * n_base * mult > max_work:
                        raise _Budget(
                            f"the next grid (N = {n_base * mult}, {cost} steps) would exceed "
                            f"the work budget options['max_work'] = {max_work:.3g} node-steps; "
                            "loosen rtol/atol or raise max_work"
                        )
                    work += cost * n_base * mult
                    if len(cache) >= max_levels:
                        raise _Levels(f"after {len(cache)} grids (levels = {max_levels})")
                    cache[key] = _march(pbs, plan, n_base * mult, mult, stretch, n_ie)
                    nsteps += cache[key]["nsteps"]
                return cache[key]

            def tol_of(area: Array) -> Array:
                return pb.rtol * np.abs(area) + pb.atol

            scale = _load_scale(pbs, tau[num])

            def load_ratio(a: dict, b: dict, factor: float) -> float:
                """Estimated error of the load identity of ``a`` against the tolerance."""
                la_ = a["load"] + a["mom_l"] + a["mom_u"]
                lb_ = b["load"] + b["mom_l"] + b["mom_u"]
                return float(np.max(factor * np.abs(la_ - lb_) / scale)) / (pb.rtol + pb.atol)

            try:
                n_base, mode, rounds = n0, "R", 0
                while True:
                    l1, l2 = level(n_base, 1), level(n_base, 2)
                    e_r = 2.0 * np.abs(l2["area"] - l1["area"]) / 3.0  # ~2x error of R(2n)
                    ratio = max(
                        float(np.max(e_r / tol_of(l2["area"]))), load_ratio(l2, l1, 2.0 / 3.0)
                    )
                    if mode == "R" and ratio <= 1.0:
                        best, err, n_used = _combine(l2, l1, False), e_r, 2 * n_base
                        break
                    if mode == "R" and math.sqrt(ratio / aim) <= R_MAX_REFINE:
                        # after a missed prediction (slower than second order, e.g. kinks of a
                        # tabulated wall) grow at least 1.25x, so that the grids keep advancing
                        rounds += 1
                        n_base = _round_grid(
                            n_base * max(math.sqrt(ratio / aim), 1.0 if rounds == 1 else 1.25)
                        )
                        continue
                    mode = "E"  # fourth order: Richardson pairs on three nested grids
                    l4 = level(n_base, 4)
                    e_b = _combine(l4, l2, True)
                    e_a = _combine(l2, l1, True)
                    d = 2.0 * np.abs(e_b["area"] - e_a["area"]) / 15.0
                    ratio = max(
                        float(np.max(d / tol_of(e_b["area"]))), load_ratio(e_b, e_a, 2.0 / 15.0)
                    )
                    if ratio <= 1.0:
                        best, err, n_used = e_b, d, 4 * n_base
                        break
                    rounds += 1
                    grow = max((ratio / aim) ** 0.25, 1.0 if rounds == 1 else 1.25)
                    n_base = _round_grid(n_base * grow)
            except (_Budget, _Levels) as exc:
                status = "max_steps" if isinstance(exc, _Budget) else "tolerance_not_met"
                message = str(exc)
            except FloatingPointError as exc:
                status, message = "tolerance_not_met", f"numerical failure: {exc}"
            if best is None and cache:  # budget spent: the finest pair computed, flagged
                # (a finer level whose partner was never reached has no error estimate: the
                # finest level *with* a coarser partner is used instead)
                paired = [c for c in cache if any(o[0] == c[0] and o[1] < c[1] for o in cache)]
                (nbf, mf) = max(paired or cache, key=lambda c: c[0] * c[1])
                pair = [c for c in cache if c[0] == nbf and c[1] < mf]
                fine = cache[(nbf, mf)]
                if pair:
                    coarse = cache[max(pair, key=lambda c: c[1])]
                    best = _combine(fine, coarse, False)
                    err = 2.0 * np.abs(fine["area"] - coarse["area"]) / 3.0
                else:
                    best = _combine(fine, fine, False)
                n_used = nbf * mf
            # a probability projected onto [0, 1] is off by at most 1: no estimate (a single
            # level) is reported as 1, never as inf
            err = np.minimum(err, 1.0)
            if best is None:
                return self._failed(nb, status, message or "no level completed", nsteps)
            # round-off of the sums over the grid (the level difference cannot see it)
            err = err + 16.0 * np.finfo(float).eps * math.sqrt(max(n_used, 1)) * np.abs(
                best["area"]
            )
            if status == "success" and np.any(err > tol_of(best["area"])):
                status = "tolerance_not_met"
            if status != "success":
                i = np.unravel_index(int(np.argmax(err / tol_of(best["area"]))), err.shape)
                message = (message + "; " if message else "") + (
                    f"the error estimate {err[i]:.2e} exceeds the tolerance at tau = "
                    f"{tau[num][i[1]]:.6g} Pa^2"
                )
        shape = (nb, tau.size)
        area = np.ones(shape)
        ab_l = np.zeros(shape)
        ab_u = np.zeros(shape)
        load = np.broadcast_to(np.array([p.p0 for p in pbs])[:, None], shape).copy()
        wall_term = np.zeros(shape)
        e_all = np.zeros(shape)
        trunc = 2.0 * math.erfc(k / math.sqrt(2.0))
        e_all[:, analytic & (tau > 0)] = trunc
        if best is not None and num.any():
            # the probabilities are projected onto their admissible set (area, absorbed >= 0,
            # area <= 1, absorbed_lower + absorbed_upper <= 1); the distance moved is a lower
            # bound of the error, so the estimate is raised to it, and a distance beyond the
            # estimate (round-off of the step sums included) is reported, not hidden
            proj, dist = _project(best["area"], best["abs_l"], best["abs_u"])
            roundoff = 16.0 * np.finfo(float).eps * (nsteps + math.sqrt(max(n_used, 1)))
            bound = err + trunc + roundoff
            for key, d in dist.items():
                if np.any(d > bound) and status == "success":
                    status = "tolerance_not_met"
                    message = (
                        f"{key} outside [0, 1] by {float(np.max(d)):.2e}, beyond its error estimate"
                    )
            err = np.maximum(err, dist["area"])
            area[:, num], ab_l[:, num], ab_u[:, num] = proj
            load[:, num] = best["load"]
            wall_term[:, num] = best["mom_l"] + best["mom_u"]
            e_all[:, num] = err + trunc
        P = None
        if pb.p_out is not None:
            P = np.zeros((nb, tau.size, pb.p_out.size))
            for i, p in enumerate(pbs):
                for j in np.flatnonzero(analytic & (tau > 0)):
                    t = tau[j]
                    P[i, j] = np.exp(-((p.p_out - p.p0) ** 2) / (4 * t)) / math.sqrt(
                        4 * math.pi * t
                    )
            if best is not None and num.any():
                P[:, num] = np.maximum(best["P"], 0.0)
        if status == "success" and not message:
            message = (
                f"{len(cache)} grids, finest N = {n_used}"
                if cache
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
            n_nodes=n_used + 1 if n_used else 0,
            nfev=nsteps,
        )

    def _failed(self, nb: int, status: str, message: str, nsteps: int) -> Raw:
        n_t = self.problem.tau.shape[-1]
        nan = np.full((nb, n_t), np.nan)
        return Raw(nan, nan, nan, nan, nan, nan, nan, None, status, message, nsteps, 0, nsteps)


_REPORT_EVERY = 64  # time steps between progress reports (see _progress)
_BLOCK = 1 << 14  # operator entries built at once per array in _march (steps x loads x nodes)
_SNAP = 1 << 20  # largest output snapshot array in _march (outputs x loads x nodes)


def _project(
    area: Array, abs_l: Array, abs_u: Array
) -> tuple[tuple[Array, Array, Array], dict[str, Array]]:
    """Nearest admissible probabilities and the distance each moved.

    ``area`` is clipped to [0, 1]; the absorbed fractions to >= 0 and, where their sum (the
    non-contact fraction) exceeds 1, scaled down to sum to 1.
    """
    a = np.clip(area, 0.0, 1.0)
    lo = np.maximum(abs_l, 0.0)
    up = np.maximum(abs_u, 0.0)
    total = lo + up
    over = total > 1.0
    scale = np.where(over, 1.0 / np.where(over, total, 1.0), 1.0)
    lo = np.minimum(lo * scale, 1.0)
    up = np.where(over, np.minimum(up * scale, 1.0 - lo), up)
    up = np.where(lo + up > 1.0, np.nextafter(up, 0.0), up)  # the sum's round-off
    dist = {
        "area": np.abs(a - area),
        "absorbed_lower": np.abs(lo - abs_l),
        "absorbed_upper": np.abs(up - abs_u),
        "non_contact_fraction": np.abs(lo + up - (abs_l + abs_u)),
    }
    return (a, lo, up), dist


_GRADE = 4.0  # steps uniform in (tau - tau_b)^(1/_GRADE) after a wall breakpoint
AIM = 0.5  # the next grid is aimed at an error estimate of AIM x tolerance (about half the
# estimate is the actual error: AIM/2 x rtol expected; 0.5 leaves a factor 2 for the prediction)
R_MAX_REFINE = 8.0  # largest refinement the second-order mode may ask for (else Richardson)


class _Budget(Exception):
    pass


class _Levels(Exception):
    pass


def _load_scale(pbs: list[Problem], tau: Array) -> Array:
    """Scale of the load identity per (load, output): max(|p0|, |walls|) [Pa] (as in finish)."""
    out = []
    for p in pbs:
        lo, up = p.wall_positions(tau)
        sc = np.maximum(abs(p.p0), np.abs(lo))
        sc = np.maximum(sc, np.where(np.isfinite(up), np.abs(up), 0.0))
        out.append(np.where(sc > 0, sc, 1.0))
    return np.array(out)


def _round_grid(n: float) -> int:
    """Even grid size >= 8 (the coarse partner of a pair is n // 2)."""
    return max(8, 2 * int(math.ceil(n / 2.0)))


def _joint_plan(
    pbs: list[Problem], k: float, per_decade: float, tau_s: float, kinks: list[float] | None = None
) -> _Plan:
    """One time schedule for a batch of loads: common analytic start, all kinks (the times
    where a real wall enters or leaves the window; found here unless given)."""
    pb = pbs[0]
    outs = pb.tau[pb.tau > tau_s]
    yield_wall = pb.upper is not None and not pb.upper.acts_absorbing
    if outs.size == 0:
        return _Plan(np.array([tau_s]), np.zeros(0, int), tau_s, k, yield_wall)
    per_decade = max(per_decade, 4.0)
    decades = math.log10(outs[-1] / tau_s)
    n_geo = max(1, int(math.ceil(decades * per_decade)))
    geo = tau_s * np.logspace(0.0, decades, n_geo + 1)
    if kinks is None:
        kinks = [t for p in pbs for t in _switch_times(p, k, tau_s, float(outs[-1]))]
    ratio = 10 ** (1.0 / per_decade) - 1.0
    zones, graded = _graded_zones(pbs, tau_s, float(outs[-1]), ratio)
    fixed = np.union1d(np.union1d(outs, kinks), graded)
    keep = np.ones(geo.size, bool)
    for t in fixed:
        keep &= np.abs(geo - t) > 0.3 * ratio * t
    for tb, te in zones:
        keep &= (geo <= tb) | (geo >= te)
    keep[0] = True
    base = np.union1d(geo[keep & (geo < outs[-1])], fixed)
    base = base[base >= tau_s]
    return _Plan(base, np.searchsorted(base, outs), tau_s, k, yield_wall, zones)


def _graded_zones(
    pbs: list[Problem], tau_s: float, tau_end: float, ratio: float
) -> tuple[tuple[tuple[float, float], ...], Array]:
    """Graded stretches after the walls' declared breakpoints, and their step times.

    After a breakpoint ``tau_b`` the wall may move like ``sqrt(tau - tau_b)`` (unbounded speed):
    on ``[tau_b, tau_b + H]``, ``H = min(tau_b, tau_end - tau_b)``, the steps are uniform in
    ``u = (tau - tau_b)^(1/4)`` (in ``s = u^2`` the motion is smooth; the quartic grading also
    removes the ``ds^2 log`` term that uniform steps in ``s`` leave, so that the error has a
    clean second-order expansion for the Richardson control); at its end they match the
    geometric steps ``~ ratio tau``.
    """
    bps = sorted(
        {
            float(t)
            for p in pbs
            for w in (p.lower, p.upper)
            if w is not None
            for t in getattr(w, "breakpoints", ())
            if tau_s < t < tau_end
        }
    )
    zones: list[tuple[float, float]] = []
    pts: list[Array] = []
    for i, tb in enumerate(bps):
        nxt = bps[i + 1] if i + 1 < len(bps) else tau_end
        h = min(tb, nxt - tb)
        n_g = max(2, int(math.ceil(_GRADE * (h / tb) ** (1 / _GRADE) / ratio)))
        pts.append(tb + h * (np.arange(n_g + 1) / n_g) ** _GRADE)
        zones.append((tb, tb + h))
    return tuple(zones), (np.concatenate(pts) if pts else np.zeros(0))


def _unbatch(raw: Raw) -> Raw:
    for name in (
        "area",
        "non_area",
        "absorbed_lower",
        "absorbed_upper",
        "load",
        "wall_term",
        "error_estimate",
    ):
        setattr(raw, name, getattr(raw, name)[0])
    if raw.P is not None:
        raw.P = raw.P[0]
    return raw


def _stack(raws: list[Raw]) -> Raw:
    out = Raw(
        *(
            np.concatenate([getattr(r, f) for r in raws])
            for f in (
                "area",
                "non_area",
                "absorbed_lower",
                "absorbed_upper",
                "load",
                "wall_term",
                "error_estimate",
            )
        )
    )
    out.P = None if raws[0].P is None else np.concatenate([r.P for r in raws])
    out.status = np.array([r.status for r in raws], dtype=object)
    out.message = [r.message for r in raws]
    out.nsteps = np.array([r.nsteps for r in raws])
    out.n_nodes = np.array([r.n_nodes for r in raws])
    out.nfev = np.array([r.nfev for r in raws])
    return out
