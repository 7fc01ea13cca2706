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

import numpy as np
from numpy.typing import NDArray
from scipy.linalg.lapack import dgtsv

from ._cn_level import _KEYS, _finish_level, _Level, _setup_level
from ._cn_plan import _Plan
from ._problem import Problem
from ._progress import report as report_progress
from ._scratch import pool

__all__ = ["_march", "_march_levels", "_combine", "_weighted", "_project"]

Array = NDArray[np.float64]


_REPORT_EVERY = 64  # time steps between progress reports (see _progress)


_BLOCK = 1 << 16  # operator entries built at once per array in _march (steps x loads x nodes)


_SNAP = 1 << 20  # largest output snapshot array in _march (outputs x loads x nodes)


def _march(pbs: list[Problem], plan: _Plan, n: int, nsub: int, stretch: float, n_ie: int) -> dict:
    """One grid level (``n`` intervals, ``nsub`` substeps per base step) for a batch of loads:
    per-load outputs ``(n_load, n_out)`` at the numerical output times (see the module)."""
    return _march_levels(pbs, plan, [(n, nsub)], stretch, n_ie)[0]


def _march_levels(
    pbs: list[Problem], plan: _Plan, grids: list[tuple[int, int]], stretch: float, n_ie: int
) -> list[dict]:
    """Several grid levels ``(n, nsub)`` of one plan marched together: while more than one
    has steps left, their systems are concatenated (identity rows on the walls: they do not
    couple, and every level's numbers are those of its own march), so that a step of all of
    them is one set of numpy calls and one ``dgtsv``; per level the outputs of :func:`_march`."""
    lvs = [_setup_level(pbs, plan, n, nsub, stretch, n_ie, _SNAP) for n, nsub in grids]
    states = [lv.r0 for lv in lvs]
    a_pls = [np.zeros(lv.nb) for lv in lvs]
    m = 0
    for end in sorted({lv.n_steps for lv in lvs}):
        if end <= m:
            continue
        act = [i for i, lv in enumerate(lvs) if lv.n_steps >= end]
        r, a_pl = _phase(
            [lvs[i] for i in act], m, end, [states[i] for i in act], [a_pls[i] for i in act]
        )
        for i, ri, ai in zip(act, r, a_pl, strict=True):
            states[i], a_pls[i] = ri, ai
        m = end
    return [_finish_level(lv) for lv in lvs]


def _phase(
    lvs: list[_Level], m_start: int, m_end: int, r_in: list[Array], a_in: list[Array]
) -> tuple[list[Array], list[Array]]:
    """Steps ``m_start .. m_end - 1`` of the levels ``lvs`` (states ``r_in``, plastic areas
    ``a_in``) with their systems concatenated; returns their states and plastic areas."""
    n_rows = [lv.nb * lv.nn for lv in lvs]
    off = np.cumsum([0] + n_rows)
    seg = np.cumsum([0] + [lv.nb for lv in lvs])
    ntot, nseg = int(off[-1]), int(seg[-1])
    last = np.concatenate([lv.last + o for lv, o in zip(lvs, off, strict=False)])
    bnd = np.concatenate([lv.bnd + o for lv, o in zip(lvs, off, strict=False)])
    wflat = np.concatenate([lv.wflat for lv in lvs])
    # the yield wall's last rows: z = (R_{N-1}, R_N before the step, A_pl, R_{N-1}, R_N after)
    z = np.zeros((5, nseg))
    z[2] = np.concatenate(a_in)
    pair = np.concatenate([last - 1, last])
    # outputs in step order: (step, level, index)
    rec = sorted(
        (int(s), k, j)
        for k, lv in enumerate(lvs)
        for j, s in enumerate(lv.out_at)
        if m_start < s <= m_end
    )
    n_steps = m_end - m_start
    block = max(1, min(_BLOCK // ntot, n_steps))
    with pool() as buf:
        for k, lv in enumerate(lvs):  # buffers reused by every block
            lv.work = (
                buf.empty(f"ops{k}", (block, 4, lv.nb, lv.nn)),
                buf.empty(f"dg{k}", (block, lv.nb, lv.nn)),
            )
        ctx = _Steps(lvs, off, seg, wflat, bnd, last, pair, z, rec + [(-1, 0, 0)], ntot, nseg)
        ctx.cat = [buf.empty(f"cat{k}", (block, ntot)) for k in range(5)] if len(lvs) > 1 else []
        states_buf = buf.empty("states", (block + 1, ntot))
        r = np.concatenate(r_in)
        for m0 in range(m_start, m_end, block):
            c = min(m0 + block, m_end) - m0
            r = ctx.block(m0, c, states_buf[: c + 1], r)
        r_out = [r[off[k] : off[k + 1]].copy() for k in range(len(lvs))]
    # the steps not reported in the loop (which reports at every _REPORT_EVERY-th global step)
    e = _REPORT_EVERY
    report_progress((n_steps - e * (m_end // e - m_start // e)) * ntot)
    a_out = [z[2, seg[k] : seg[k + 1]].copy() for k in range(len(lvs))]
    return r_out, a_out


class _Steps:
    """The step loop of a phase of :func:`_march_levels` (see the module)."""

    def __init__(self, lvs, off, seg, wflat, bnd, last, pair, z, rec, ntot, nseg) -> None:
        self.lvs, self.off, self.seg, self.wflat, self.bnd = lvs, off, seg, wflat, bnd
        self.last, self.pair, self.z, self.rec, self.nxt = last, pair, z, rec, 0
        self.nseg, self.cat = nseg, []
        # rows whose right-hand side is reset to 0 at every step: the identity rows between
        # the systems (the flux differences reach them); one pair of rows as a slice
        inner = bnd[(bnd > 0) & (bnd < ntot - 1)]
        pair_ = inner.size == 2 and inner[1] == inner[0] + 1
        self.joints = slice(int(inner[0]), int(inner[1]) + 1) if pair_ else bnd
        # work buffers of a step: face fluxes G, G2 and their differences dG
        self.G, self.G2, self.dG = np.empty(ntot - 1), np.empty(ntot - 1), np.empty(ntot - 2)

    def _system(self, m0: int, c: int) -> tuple[Array, ...]:
        """The concatenated systems of steps ``m0 .. m0 + c - 1`` (see :func:`_block_system`)
        and whether a yield wall is real at each step."""
        ms = slice(m0, m0 + c)
        parts = [
            _block_system(
                lv.ed,
                lv.basis,
                ms,
                lv.wn_all[ms],
                lv.wo_all[ms],
                lv.g_all[:, ms].T,
                lv.w[1:-1],
                lv.w[-1],
                lv.ends,
                lv.yreal[:, ms].T,
                lv.work,
            )
            for lv in self.lvs
        ]
        ys = np.any([lv.yreal[:, ms].any(axis=0) for lv in self.lvs], axis=0).tolist()
        if len(parts) == 1:
            return (*parts[0], ys)
        cat = [a[:c] for a in self.cat]  # (the pool's: no fresh pages at every phase)
        for k in range(5):
            for j, p in enumerate(parts):
                cat[k][:, self.off[j] : self.off[j + 1]] = p[k]
        k_rhs, k_gain = (np.concatenate([p[k] for p in parts], axis=2) for k in (5, 6))
        return (*cat, k_rhs, k_gain, ys)

    def block(self, m0: int, c: int, states: Array, r: Array) -> Array:
        """Steps ``m0 .. m0 + c - 1`` from the state ``r``; the state after them (a view of
        ``states``: row 0 the state before the block, row i + 1 after step m0 + i)."""
        dl, du, Dg, Ga, Gp, k_rhs, k_gain, ys = self._system(m0, c)
        G, G2, dG, z, pair, wflat, last, bnd = (
            self.G,
            self.G2,
            self.dG,
            self.z,
            self.pair,
            self.wflat,
            self.last,
            self.joints,
        )
        G_hi, G_lo = G[1:], G[:-1]
        a_pl, z_old, z_new, z_rhs = z[2], z[:2].reshape(-1), z[3:].reshape(-1), z[:3]  # views
        mul, sub, add_r, info, rec, nxt = (
            np.multiply,
            np.subtract,
            np.add.reduce,
            0,
            self.rec,
            self.nxt,
        )
        joints = self.nseg > 1
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
            if joints:
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
            while rec[nxt][0] == m + 1:
                self._record(rec[nxt], r)
                nxt += 1
            if (m + 1) % _REPORT_EVERY == 0:
                report_progress(_REPORT_EVERY * r.size)
        self.nxt = nxt
        if info != 0:
            raise FloatingPointError(f"tridiagonal solve failed (info={info})")
        for k, lv in enumerate(self.lvs):
            lv.hist[m0 + 1 : m0 + c + 1] = states[1:, lv.near + self.off[k]]
        return r

    def _record(self, item: tuple[int, int, int], r: Array) -> None:
        m, k, j = item
        off, seg = self.off, self.seg
        self.lvs[k].record(r[off[k] : off[k + 1]], self.z[2, seg[k] : seg[k + 1]], j, m)


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
    ``A_pl`` (``k_gain``, (steps, 5, loads), 0 where ``yreal`` (steps, loads) is False).  The
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
    ends[[1, 3], :, ms] *= -1.0  # wn(A + D), as the solve used it
    dl, du, Ga, Gp = (ops[:, k] for k in range(4))
    Dg = work[1][:c]
    np.subtract(wi, dl[..., 1:nf], out=Dg[..., 1:-1])
    Dg[..., 1:-1] -= du[..., : nf - 1]
    Dg[..., 0] = 1.0
    # last row of a real yield wall: half cell plus A_pl, closure R_N = g A_pl
    Dg[..., -1] = 1.0 + g * (w_last + ends[3, :, ms].T)
    dl[..., nf - 1] = g * ends[2, :, ms].T
    du[..., 0] = 0.0
    # last row of a real yield wall: g (w_N R_N + A_pl - wo F_{N-1/2})
    k_rhs = np.stack([-g * ends[6, :, ms].T, g * (w_last - ends[7, :, ms].T), g], axis=1)
    mb1, pb1, ma1, pa1 = (ends[k, :, ms].T for k in (2, 3, 6, 7))
    k_gain = np.stack([-ma1, w_last - pa1, 0.0 * g, -mb1, -(pb1 + w_last)], axis=1)
    k_gain *= yreal[:, None, :]
    dl, du, Dg, Ga, Gp = (a.reshape(c, nb * nn) for a in (dl, du, Dg, Ga, Gp))
    return dl, du, Dg, Ga, Gp, k_rhs, k_gain


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
