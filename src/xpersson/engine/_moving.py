"""One grid level of the ``cn`` method: the front-fixed finite-volume Crank-Nicolson march of
a batch of loads between moving walls (absorbing or yield closure), the Richardson combination
of two levels and the projection onto admissible probabilities.  See :mod:`._cn` for the
scheme.

The loads' systems are concatenated (boundary rows are identity rows, so they do not couple).
The operators are built vectorised for a block of steps at a time (memory proportional to the
grid times the block, see ``_BLOCK``): every face coefficient is a combination of three face
functions, so a block's four coefficient arrays are one BLAS product.  A step is then one
explicit tridiagonal product in flux form, one LAPACK ``dgtsv`` solve (called directly, as in
:func:`._cnstep.tridiagonal_solve`) and a gather of the nodes next to the walls, from which
the wall fluxes (absorbed probabilities, wall moments) are summed after the march with the
end faces' coefficients the solve used.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import CubicSpline
from scipy.linalg.lapack import dgtsv

from ._cn_plan import _edges_batch, _faces, _level_times, _Plan
from ._grid import clustered
from ._problem import Problem
from ._progress import report as report_progress

__all__ = ["_march", "_combine", "_weighted", "_project"]

Array = NDArray[np.float64]


_KEYS = ("area", "abs_l", "abs_u", "load", "mom_l", "mom_u")


_REPORT_EVERY = 64  # time steps between progress reports (see _progress)


_BLOCK = 1 << 16  # operator entries built at once per array in _march (steps x loads x nodes)


_SNAP = 1 << 20  # largest output snapshot array in _march (outputs x loads x nodes)


def _march(pbs: list[Problem], plan: _Plan, n: int, nsub: int, stretch: float, n_ie: int) -> dict:
    """One grid level (``n`` intervals, ``nsub`` substeps per base step) for a batch of loads:
    per-load outputs ``(n_load, n_out)`` at the numerical output times (see the module)."""
    taus, theta, out_at, x, xf, dxf, w, ed = _level_grid(pbs, plan, n, nsub, stretch, n_ie)
    pb0, nb, nn, n_out = pbs[0], len(pbs), x.size, out_at.size
    res, snaps = _outputs(nb, n_out, nn, pb0.p_out)
    yield_wall = plan.yield_wall
    p0 = np.array([pb.p0 for pb in pbs])[:, None]
    n_steps, step = taus.size - 1, np.diff(taus)
    wn_all, wo_all = theta * step, (1.0 - theta) * step
    yreal = ed["ru"] & yield_wall
    g_all = np.where(yreal, ed["wb"] * ed["ysb"], 0.0)  # g = W Y' of the closure R_N = g A_pl

    r = _initial_state(ed["la"], ed["wa"], x, w, p0, taus[0], plan.k)
    near, last, bnd, wflat = _rows(nb, n, stretch)
    hist = np.empty((n_steps + 1, 4 * nb))  # R at `near` after every step
    hist[0] = r[near]
    # the yield wall's last rows: z = (R_{N-1}, R_N before the step, A_pl, R_{N-1}, R_N after)
    z = np.zeros((5, nb))
    a_pl, z_old, z_new, z_rhs = z[2], z[:2].reshape(-1), z[3:].reshape(-1), z[:3]  # views
    pair = np.concatenate([last - 1, last])
    a_pl_at = np.zeros((nb, n_out))
    # the end faces' coefficients the solve used, (8, loads, steps): see _block_system
    ends = np.empty((8, nb, n_steps))
    basis, w_last, wi = _basis(n, stretch), w[-1], w[1:-1]

    def record(j: int, m: int) -> None:
        _record(res, a_pl_at, snaps, r, a_pl, j, m, ed, x, w, pb0.p_out)

    out_steps = out_at.tolist() + [-1]
    nxt = 0
    while nxt < n_out and out_steps[nxt] == 0:
        record(nxt, 0)
        nxt += 1
    block = max(1, min(_BLOCK // (nb * nn), n_steps))
    # buffers reused by every block: operators, and the states (row 0 the state before it)
    work = (np.empty((block, 4, nb, nn)), np.empty((block, nb, nn)))
    states_buf = np.empty((block + 1, nb * nn))
    # work buffers of a step: face fluxes G, G2 and their differences dG
    G, G2, dG = np.empty(nb * nn - 1), np.empty(nb * nn - 1), np.empty(nb * nn - 2)
    G_hi, G_lo = G[1:], G[:-1]
    mul, sub, add_r, info = np.multiply, np.subtract, np.add.reduce, 0
    for m0 in range(0, n_steps, block):
        ms = slice(m0, min(m0 + block, n_steps))
        c = ms.stop - ms.start
        g = g_all[:, ms].T  # (steps, loads)
        dl, du, Dg, Ga, Gp, k_rhs, k_gain = _block_system(
            ed, basis, ms, wn_all[ms], wo_all[ms], g, wi, w_last, ends, yreal[:, ms].T, work
        )
        ys = yreal[:, ms].any(axis=0).tolist()
        # the states of the block: row 0 the state before it, row i + 1 the state after step
        # m0 + i (the solve overwrites its right-hand side in place)
        states = states_buf[: c + 1]
        states[0] = r
        r = states[0]
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
            s_in[i + 1] += dG
            if nb > 1:
                rhs[bnd] = 0.0
            if ys[i]:  # last row: g (w_N R_N + A_pl - wo F_{N-1/2})
                r.take(pair, out=z_old)  # (the method: no dispatch through np.take)
                rhs[last] = add_r(k_rhs[i] * z_rhs, 0)
            # LAPACK dgtsv in place (the 1-D C-contiguous rows are passed without copies)
            sol, info_m = dgtsv(dl_[i], Dg[i], du_[i], rhs, 1, 1, 1, 1)[3:]
            info |= info_m
            if sol is not rhs:  # the wrapper made a copy: the block's states must hold it
                rhs[...] = sol
            if ys[i]:  # dA_pl: out-flux through the last face + the half cell's loss
                sol.take(pair, out=z_new)
                a_pl += add_r(k_gain[i] * z, 0)
            r = sol
            while out_steps[nxt] == m + 1:
                record(nxt, m + 1)
                nxt += 1
            if (m + 1) % _REPORT_EVERY == 0:
                report_progress(_REPORT_EVERY * nn * nb)
        if info != 0:
            raise FloatingPointError(f"tridiagonal solve failed (info={info})")
        hist[m0 + 1 : m0 + c + 1] = states[1:, near]
    report_progress((n_steps % _REPORT_EVERY) * nn * nb)
    if snaps is not None:
        _reduce_snapshots(res, snaps, ed, x, w, out_at)
    _wall_sums(res, ed, hist, ends, out_at, a_pl_at, yield_wall)
    res["nsteps"] = n_steps
    res["n_nodes"] = nn
    return res


def _outputs(nb: int, n_out: int, nn: int, p_out: Array | None) -> tuple[dict, Array | None]:
    """Output arrays of a level, and the state snapshots: reduced after the march (one copy
    per output instead of a dozen small reductions), unless the density is wanted or the
    snapshots would be large (then None: each output is reduced when reached)."""
    res = {key: np.zeros((nb, n_out)) for key in _KEYS}
    want_p = p_out is not None
    res["P"] = np.zeros((nb, n_out, p_out.size)) if want_p else None
    snaps = None if want_p or n_out * nb * nn > _SNAP else np.empty((n_out, nb * nn))
    return res, snaps


def _level_grid(
    pbs: list[Problem], plan: _Plan, n: int, nsub: int, stretch: float, n_ie: int
) -> tuple:
    """Times, theta per step, output steps, nodes ``x`` (faces, spacings, control volumes) and
    the window edges of one grid level."""
    taus, theta = _level_times(plan.base, nsub, n_ie, plan.zones)
    pb0 = pbs[0]
    out_at = np.searchsorted(taus, pb0.tau[pb0.tau > plan.tau_s])
    x, xf, dxf, w = _nodes(n, stretch)
    ed = _edges_batch(pbs, plan, taus)
    if (ed["wa"] <= 0).any() or (ed["wb"] <= 0).any():
        raise FloatingPointError("the walls swept the whole window (area 0)")
    return taus, theta, out_at, x, xf, dxf, w, ed


@lru_cache(maxsize=32)
def _nodes(n: int, stretch: float) -> tuple[Array, Array, Array, Array]:
    """Nodes ``x`` of a level (:func:`.clustered`), face midpoints, spacings and control
    volumes (:func:`._cn_plan._faces`), read-only: the levels of every solve reuse a few."""
    x = clustered(n, stretch)
    out = (x, *_faces(x))
    for a in out:
        a.setflags(write=False)
    return out


@lru_cache(maxsize=32)
def _rows(nb: int, n: int, stretch: float) -> tuple[Array, Array, Array, Array]:
    """Rows of the concatenated system of ``nb`` loads on the nodes of :func:`_nodes`: the two
    nodes at each wall (the solve leaves round-off ~ eps on the wall nodes, which the wall
    fluxes must include for the balance to hold to round-off), the last rows, the identity rows
    (the walls) and the control volumes (0 there); read-only (the levels of every solve reuse
    a few)."""
    w = _nodes(n, stretch)[3]
    nn = w.size
    rows = np.arange(nb) * nn  # first node of each load in the concatenated system
    near = np.concatenate([rows, rows + 1, rows + nn - 2, rows + nn - 1])
    last = rows + nn - 1
    bnd = np.concatenate([rows, last])  # identity rows (the walls)
    wflat = np.tile(w, nb)
    wflat[bnd] = 0.0
    out = (near, last, bnd, wflat)
    for a in out:
        a.setflags(write=False)
    return out


@lru_cache(maxsize=32)
def _basis(n: int, stretch: float) -> Array:
    """Face functions ``1, x_f, 1/dx_f`` (3, nodes) of :func:`_nodes`; the last slot (no face)
    is 0; read-only."""
    xf, dxf = _nodes(n, stretch)[1:3]
    nf = xf.size
    basis = np.zeros((3, nf + 1))
    basis[0, :nf] = 1.0
    basis[1, :nf] = xf
    basis[2, :nf] = 1.0 / dxf
    basis.setflags(write=False)
    return basis


def _block_system(
    ed: dict,
    basis: Array,
    ms: slice,
    wn: Array,
    wo: Array,
    g: Array,
    wi: Array,
    w_last: float,
    ends: Array,
    yreal: Array,
    work: tuple[Array, Array],
) -> tuple[Array, ...]:
    """The systems of the steps ``ms`` with the loads concatenated, one row per step.

    Face fluxes ``F = D (R_{j+1} - R_j) + A (R_j + R_{j+1})`` with ``D = 1 / (W^2 dx_f)``,
    ``A = (l' + x_f W') / (2 W)``: every face coefficient is a combination of the three face
    functions of ``basis`` with per-(step, load) weights, so the four coefficient arrays of a
    block are one matrix product (one pass over memory instead of a dozen broadcasts).

    dgtsv's sub-diagonal ``dl[r]`` (row r + 1) ``= wn (A - D)`` at the end of the step,
    diagonal ``Dg[r]``, super-diagonal ``du[r]`` (row r) ``= -wn (A + D)``; the last slot of
    each load couples nothing (boundary rows are identity rows).  Interior rows j = 1..n-1:
    ``w_j R_j - wn (F_{j+1/2} - F_{j-1/2}) = w_j R_j^old + wo (F^old_{j+1/2} - F^old_{j-1/2})``.
    Also the explicit half's face coefficients ``Ga = wo (A - D)``, ``Gp = wo (A + D)`` at the
    start of the step (flux form) and the yield wall's last-row coefficients of
    ``(R_{N-1}, R_N, A_pl)`` before the step for the right-hand side (``k_rhs``, (steps, 3,
    loads)) and of ``(R_{N-1}, R_N, A_pl, R_{N-1}, R_N)`` before / after it for the gain of
    ``A_pl`` (``k_gain``, (steps, 5, loads), 0 where ``yreal`` (steps, loads) is False; both
    None where it is False throughout the block).  The
    coefficients of the first and last faces, as used, are written into ``ends[:, :, ms]``
    (order: wn(A-D), wn(A+D) at the first face, then at the last face; then the same four of
    the explicit half): the wall fluxes are summed from them.  ``work``: buffers (steps,
    4, loads, nodes) and (steps, loads, nodes) for the arrays, ``steps >= c`` (reused from block
    to block: fresh memory would cost a page fault per 4 kB on every block).
    """
    c = ms.stop - ms.start
    nb, nn = g.shape[1], basis.shape[1]
    nf = nn - 1
    coef = np.empty((c, 4, nb, 3))
    for k, (tag, th) in enumerate((("b", wn), ("a", wo))):
        W = ed["w" + tag][:, ms].T
        th = th[:, None]
        a_ = th * (ed["lv" + tag][:, ms].T / (2.0 * W))
        b_ = th * (ed["wv" + tag][:, ms].T / (2.0 * W))
        d_ = th / W**2
        coef[:, 2 * k, :, 0], coef[:, 2 * k, :, 1], coef[:, 2 * k, :, 2] = a_, b_, -d_
        sign = -1.0 if tag == "b" else 1.0  # dgtsv's super-diagonal is -wn (A + D)
        coef[:, 2 * k + 1, :, 0], coef[:, 2 * k + 1, :, 1] = sign * a_, sign * b_
        coef[:, 2 * k + 1, :, 2] = sign * d_
    # one BLAS product (c 4 nb, 3) x (3, nodes): wn(A-D), -wn(A+D), wo(A-D), wo(A+D)
    # (negating every weight negates the product exactly: round to nearest is symmetric)
    ops = work[0][:c]
    np.matmul(coef.reshape(-1, 3), basis, out=ops.reshape(-1, nn))
    for k, face in enumerate((0, 0, nf - 1, nf - 1)):
        ends[k, :, ms] = ops[:, k % 2, :, face].T
        ends[k + 4, :, ms] = ops[:, 2 + k % 2, :, face].T
    ends[1, :, ms] *= -1.0  # wn(A + D), as the solve used it
    ends[3, :, ms] *= -1.0
    dl, du, Ga, Gp = (ops[:, k] for k in range(4))
    Dg = work[1][:c]
    np.subtract(wi, dl[..., 1:nf], out=Dg[..., 1:-1])
    Dg[..., 1:-1] -= du[..., : nf - 1]
    Dg[..., 0] = 1.0
    # last row of a real yield wall: half cell plus A_pl, closure R_N = g A_pl
    Dg[..., -1] = 1.0 + g * (w_last + ends[3, :, ms].T)
    dl[..., nf - 1] = g * ends[2, :, ms].T
    du[..., 0] = 0.0
    dl, du, Dg, Ga, Gp = (a.reshape(c, nb * nn) for a in (dl, du, Dg, Ga, Gp))
    if not yreal.any():  # no real yield wall in the block: the last-row terms are not used
        return dl, du, Dg, Ga, Gp, None, None
    # last row of a real yield wall: g (w_N R_N + A_pl - wo F_{N-1/2})
    k_rhs = np.stack([-g * ends[6, :, ms].T, g * (w_last - ends[7, :, ms].T), g], axis=1)
    mb1, pb1, ma1, pa1 = (ends[k, :, ms].T for k in (2, 3, 6, 7))
    k_gain = np.stack([-ma1, w_last - pa1, 0.0 * g, -mb1, -(pb1 + w_last)], axis=1)
    k_gain *= yreal[:, None, :]
    return dl, du, Dg, Ga, Gp, k_rhs, k_gain


def _initial_state(
    la: Array, wa_: Array, x: Array, w: Array, p0: Array, t0: float, k: float
) -> Array:
    """The free Gaussian at ``t0`` [Pa^2] (mass per unit x, the loads concatenated),
    normalised to the window mass ``erf(k / sqrt 2)``."""
    pn = la[:, :1] + wa_[:, :1] * x[None, :]
    r2 = wa_[:, :1] * np.exp(-((pn - p0) ** 2) / (4.0 * t0)) / math.sqrt(4.0 * math.pi * t0)
    r2[:, 0] = 0.0
    r2[:, -1] = 0.0
    r2 *= math.erf(k / math.sqrt(2.0)) / (r2 @ w)[:, None]
    r = r2.ravel()
    return r


def _reduce_snapshots(res: dict, snaps: Array, ed: dict, x: Array, w: Array, out_at: Array) -> None:
    """Area ``int R dx`` and load ``int p R dx`` (``p = l + W x``) per output, into ``res``."""
    la, wa_, lb, wb_ = ed["la"], ed["wa"], ed["lb"], ed["wb"]
    n_out, nb = snaps.shape[0], la.shape[0]
    R = snaps.reshape(n_out, nb, x.size)
    lv, wv = _at_outputs(la, lb, out_at), _at_outputs(wa_, wb_, out_at)
    res["area"] = (R @ w).T
    res["load"] = lv * res["area"] + wv * (R @ (x * w)).T


def _at_outputs(start: Array, end: Array, out_at: Array) -> Array:
    """A window edge at the output steps: ``start[:, 0]`` at step 0, else ``end[:, m - 1]``
    (``np.hstack([start[:, :1], end])[:, out_at]`` without building the whole)."""
    v = end[:, out_at - 1]
    first = out_at == 0
    if first.any():
        v[:, first] = start[:, :1]
    return v


def _record(
    res: dict,
    a_pl_at: Array,
    snaps: Array | None,
    r: Array,
    a_pl: Array,
    j: int,
    m: int,
    ed: dict,
    x: Array,
    w: Array,
    p_out: Array | None,
) -> None:
    """Outputs ``j`` after step ``m`` (the state ``r``; wall terms are added later)."""
    a_pl_at[:, j] = a_pl
    if snaps is not None:
        snaps[j] = r
        return
    la, wa_, lb, wb_ = ed["la"], ed["wa"], ed["lb"], ed["wb"]
    nb, nn = a_pl_at.shape[0], x.size
    r_ = r.reshape(nb, nn)
    lv, wv = (la[:, 0], wa_[:, 0]) if m == 0 else (lb[:, m - 1], wb_[:, m - 1])
    pm = lv[:, None] + wv[:, None] * x[None, :]
    res["area"][:, j] = r_ @ w
    res["load"][:, j] = (pm * r_) @ w
    if p_out is not None:
        pv = p_out
        for i in range(nb):
            cs = CubicSpline(pm[i], r_[i] / wv[i])
            inside = (pv >= pm[i, 0]) & (pv <= pm[i, -1])
            res["P"][i, j, inside] = cs(pv[inside])


def _wall_sums(
    res: dict,
    ed: dict,
    hist: Array,
    ends: Array,
    out_at: Array,
    a_pl_at: Array,
    yield_wall: bool,
) -> None:
    """Absorbed probabilities and wall moments per output from the nodes next to the walls
    after every step (R = 0 on an absorbing wall) and the end faces' coefficients the solve
    used (``ends``, see :func:`_block_system`), into ``res``."""
    nb = a_pl_at.shape[0]
    la, wa_, lb, wb_, rl, ru = ed["la"], ed["wa"], ed["lb"], ed["wb"], ed["rl"], ed["ru"]
    r0, r1, rm, rn = (hist[:, i * nb : (i + 1) * nb].T for i in range(4))  # (nb, n_steps + 1)
    mb0, pb0, mb1, pb1, ma0, pa0, ma1, pa1 = ends
    # the wall fluxes times the step's weights: new (end of step) and old (start) halves
    f_new0 = mb0 * r0[:, 1:] + pb0 * r1[:, 1:]
    f_old0 = ma0 * r0[:, :-1] + pa0 * r1[:, :-1]
    f_new1 = mb1 * rm[:, 1:] + pb1 * rn[:, 1:]
    f_old1 = ma1 * rm[:, :-1] + pa1 * rn[:, :-1]
    abs_l = _cumsum0(np.where(rl, f_new0 + f_old0, 0.0))
    mom_l = _cumsum0(np.where(rl, lb * f_new0 + la * f_old0, 0.0))
    res["abs_l"], res["mom_l"] = abs_l[:, out_at], mom_l[:, out_at]
    if yield_wall:
        res["abs_u"] = a_pl_at
        ends_ = np.hstack([la[:, :1] + wa_[:, :1], lb + wb_])[:, out_at]
        res["mom_u"] = ends_ * a_pl_at
    else:
        out_hi = -(f_new1 + f_old1)
        mom = (lb + wb_) * f_new1 + (la + wa_) * f_old1
        res["abs_u"] = _cumsum0(np.where(ru, out_hi, 0.0))[:, out_at]
        res["mom_u"] = -_cumsum0(np.where(ru, mom, 0.0))[:, out_at]


def _cumsum0(a: Array) -> Array:
    """Running sums along the rows of ``a`` after a column of zeros, ``(nb, 1 + steps)``."""
    out = np.empty((a.shape[0], a.shape[1] + 1))
    out[:, 0] = 0.0
    np.cumsum(a, axis=1, out=out[:, 1:])
    return out


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


def _weighted(levels: list[dict], weights: Array) -> dict:
    """The combination ``sum_i weights[i] levels[i]`` of every output (weights summing to 1,
    e.g. Richardson's: the probability balance, linear in the levels, is kept)."""
    out = {}
    for key in (*_KEYS, "P"):
        if levels[0][key] is None:
            out[key] = None
        else:
            out[key] = sum(float(c) * lv[key] for c, lv in zip(weights, levels, strict=True))
    return out


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
