"""One grid level of the ``cn`` march: its times, nodes, window edges, initial state and
output arrays (:class:`_Level`, built by :func:`_setup_level`), the outputs recorded while
marching and the wall sums after it (:func:`_finish_level`).  The march itself, which may
advance several levels together (their systems concatenated), is :mod:`._moving`'s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import CubicSpline

from ._cn_plan import _edges_batch, _faces, _level_times, _Plan
from ._grid import clustered
from ._problem import Problem

__all__ = ["_Level", "_setup_level", "_finish_level", "_record"]

Array = NDArray[np.float64]


_KEYS = ("area", "abs_l", "abs_u", "load", "mom_l", "mom_u")


@dataclass
class _Level:
    """The arrays of one level (``nb`` loads of ``nn`` nodes, ``n_steps`` steps) that the march
    reads and fills: see :func:`_setup_level`."""

    nb: int
    nn: int
    n_steps: int
    ed: dict
    x: Array
    w: Array
    basis: Array
    p_out: Array | None
    yield_wall: bool
    out_at: Array
    res: dict
    snaps: Array | None
    a_pl_at: Array
    hist: Array  # R at `near` after every step, (n_steps + 1, 4 nb)
    ends: Array  # end faces' coefficients the solve used, (8, nb, n_steps)
    wn_all: Array
    wo_all: Array
    yreal: Array
    g_all: Array
    r0: Array  # the state at the start (the loads concatenated)
    near: Array
    last: Array
    bnd: Array
    wflat: Array
    work: tuple = field(default_factory=tuple)  # block buffers of _block_system

    def record(self, r: Array, a_pl: Array, j: int, m: int) -> None:
        """Output ``j`` after step ``m``: the state ``r`` (this level's rows) and ``a_pl``."""
        _record(
            self.res, self.a_pl_at, self.snaps, r, a_pl, j, m, self.ed, self.x, self.w, self.p_out
        )


def _setup_level(
    pbs: list[Problem], plan: _Plan, n: int, nsub: int, stretch: float, n_ie: int, snap: int
) -> _Level:
    """The level ``n`` intervals, ``nsub`` substeps per base step of ``plan`` for a batch of
    loads, its outputs at step 0 recorded (``snap``: largest snapshot array, see
    :func:`_outputs`)."""
    taus, theta, out_at, x, xf, dxf, w, ed = _level_grid(pbs, plan, n, nsub, stretch, n_ie)
    pb0, nb, nn, n_out = pbs[0], len(pbs), x.size, out_at.size
    res, snaps = _outputs(nb, n_out, nn, pb0.p_out, snap)
    p0 = np.array([pb.p0 for pb in pbs])[:, None]
    n_steps, step = taus.size - 1, np.diff(taus)
    yreal = ed["ru"] & plan.yield_wall
    near, last, bnd, wflat = _rows(nb, nn, w)
    lv = _Level(
        nb=nb,
        nn=nn,
        n_steps=n_steps,
        ed=ed,
        x=x,
        w=w,
        basis=_basis(xf, dxf),
        p_out=pb0.p_out,
        yield_wall=plan.yield_wall,
        out_at=out_at,
        res=res,
        snaps=snaps,
        a_pl_at=np.zeros((nb, n_out)),
        hist=np.empty((n_steps + 1, 4 * nb)),
        ends=np.empty((8, nb, n_steps)),
        wn_all=theta * step,
        wo_all=(1.0 - theta) * step,
        yreal=yreal,
        # g = W Y' of the closure R_N = g A_pl
        g_all=np.where(yreal, ed["wb"] * ed["ysb"], 0.0),
        r0=_initial_state(ed["la"], ed["wa"], x, w, p0, taus[0], plan.k),
        near=near,
        last=last,
        bnd=bnd,
        wflat=wflat,
    )
    lv.hist[0] = lv.r0[near]
    zero = np.zeros(nb)
    for j in np.flatnonzero(out_at == 0):
        lv.record(lv.r0, zero, int(j), 0)
    return lv


def _finish_level(lv: _Level) -> dict:
    """The level's outputs after the march: snapshots reduced, wall sums added."""
    res = lv.res
    if lv.snaps is not None:
        _reduce_snapshots(res, lv.snaps, lv.ed, lv.x, lv.w, lv.out_at)
    _wall_sums(res, lv.ed, lv.hist, lv.ends, lv.out_at, lv.a_pl_at, lv.yield_wall)
    res["nsteps"] = lv.n_steps
    res["n_nodes"] = lv.nn
    return res


def _outputs(
    nb: int, n_out: int, nn: int, p_out: Array | None, snap: int
) -> tuple[dict, Array | None]:
    """Output arrays of a level, and the state snapshots: reduced after the march (one copy
    per output instead of a dozen small reductions), unless the density is wanted or the
    snapshots would be large (then None: each output is reduced when reached)."""
    res = {key: np.zeros((nb, n_out)) for key in _KEYS}
    want_p = p_out is not None
    res["P"] = np.zeros((nb, n_out, p_out.size)) if want_p else None
    snaps = None if want_p or n_out * nb * nn > snap else np.empty((n_out, nb * nn))
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
    if np.any(ed["wa"] <= 0) or np.any(ed["wb"] <= 0):
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


def _rows(nb: int, nn: int, w: Array) -> tuple[Array, Array, Array, Array]:
    """Rows of the concatenated system: the two nodes at each wall (the solve leaves round-off
    ~ eps on the wall nodes, which the wall fluxes must include for the balance to hold to
    round-off), the last rows, the identity rows (the walls) and the control volumes (0 there)."""
    rows = np.arange(nb) * nn  # first node of each load in the concatenated system
    near = np.concatenate([rows, rows + 1, rows + nn - 2, rows + nn - 1])
    last = rows + nn - 1
    bnd = np.concatenate([rows, last])  # identity rows (the walls)
    wflat = np.tile(w, nb)
    wflat[bnd] = 0.0
    return near, last, bnd, wflat


def _basis(xf: Array, dxf: Array) -> Array:
    """Face functions ``1, x_f, 1/dx_f`` (3, nodes); the last slot (no face) is 0."""
    nf = xf.size
    basis = np.zeros((3, nf + 1))
    basis[0, :nf] = 1.0
    basis[1, :nf] = xf
    basis[2, :nf] = 1.0 / dxf
    return basis


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
    lv = np.hstack([la[:, :1], lb])[:, out_at]
    wv = np.hstack([wa_[:, :1], wb_])[:, out_at]
    res["area"] = (R @ w).T
    res["load"] = lv * res["area"] + wv * (R @ (x * w)).T


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
    zero = np.zeros((nb, 1))
    abs_l = np.hstack([zero, np.cumsum(np.where(rl, f_new0 + f_old0, 0.0), axis=1)])
    mom_l = np.hstack([zero, np.cumsum(np.where(rl, lb * f_new0 + la * f_old0, 0.0), axis=1)])
    res["abs_l"], res["mom_l"] = abs_l[:, out_at], mom_l[:, out_at]
    if yield_wall:
        res["abs_u"] = a_pl_at
        ends_ = np.hstack([la[:, :1] + wa_[:, :1], lb + wb_])[:, out_at]
        res["mom_u"] = ends_ * a_pl_at
    else:
        out_hi = -(f_new1 + f_old1)
        mom = (lb + wb_) * f_new1 + (la + wa_) * f_old1
        res["abs_u"] = np.hstack([zero, np.cumsum(np.where(ru, out_hi, 0.0), axis=1)])[:, out_at]
        res["mom_u"] = -np.hstack([zero, np.cumsum(np.where(ru, mom, 0.0), axis=1)])[:, out_at]
