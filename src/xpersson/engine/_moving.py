"""The march of one grid level of the ``cn`` method: front-fixed finite-volume Crank-Nicolson
for a batch of loads between moving walls (absorbing, or the yield closure).  See :mod:`._cn`
for the scheme and :mod:`._level` for the level's nodes, outputs and their combination.

Units: diffusion time ``tau`` in Pa^2, pressures in Pa, window speeds in 1/Pa; the unknown
``R = W P`` (mass per unit of the mapped coordinate ``x``) is dimensionless.

The step (theta = 1/2 Crank-Nicolson, 1 implicit Euler; ``wn = theta dt``,
``wo = (1 - theta) dt``), on nodes ``p_j = l + W x_j`` with control volumes ``w_j``:

* face fluxes ``F_{j+1/2} = D (R_{j+1} - R_j) + A (R_j + R_{j+1})``,
  ``D = 1 / (W^2 dx_f)``, ``A = (l' + x_f W') / (2 W)`` (with a real yield wall ``D = 1 /
  (W_start W_end dx_f)`` in both halves: :func:`._moving_block.symmetric_steps`);
* explicit half, in flux form: ``b_j = w_j R_j + wo (F_{j+1/2} - F_{j-1/2})`` (start of step);
* implicit half: ``w_j R_j' - wn (F'_{j+1/2} - F'_{j-1/2}) = b_j`` (end of step), one
  tridiagonal solve for every load (the loads' systems concatenated: the walls' rows are
  identity rows ``R_0 = R_N = 0``, so they do not couple);
* yield closure (a real yield wall ``Y`` at the upper edge): ``R_N = g A_pl`` with
  ``g = W Y'``, and the half cell plus the plastic area conserve mass,
  ``w_N R_N' + A_pl' + wn F'_{N-1/2} = w_N R_N + A_pl - wo F_{N-1/2}``: the last row is
  ``g (w_N + wn (A + D)) R_N' + R_N' + g wn (A - D) R_{N-1}' = g (w_N R_N + A_pl - wo
  F_{N-1/2})`` and ``A_pl' = A_pl - wo F_{N-1/2} - wn F'_{N-1/2} + w_N (R_N - R_N')``;
* wall fluxes: a real wall absorbs ``wn F'_{1/2} + wo F_{1/2}`` (lower) and
  ``-(wn F'_{N-1/2} + wo F_{N-1/2})`` (upper) per step; they are summed after the march from
  the nodes next to the walls and the end faces' coefficients the solve used.

Cost: the operators of a block of steps are built at once (one BLAS product, see
:func:`._moving_block.block_system`); a step is then about ten numpy calls on preallocated
buffers (their count is its cost on the small grids of the method).  With the compiled march
in force a level is a few compiled calls instead (:mod:`._moving_fused`, the same numbers).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import CubicSpline
from scipy.special import erf

from . import _compiled
from ._cn_lean import lean_level, lean_ok
from ._cn_plan import Window, _edges_batch, _level_times, _Plan
from ._cnstep import tridiagonal_solve
from ._level import Level, LevelInputs, Outputs, SystemRows, level_grid
from ._moving_block import Block, block_system, symmetric_steps
from ._moving_fused import _SNAP, _reduce_snapshots, fused_level
from ._problem import Problem
from ._progress import report as report_progress
from ._progress import reported as progress_reported

__all__ = ["LevelInputs", "level_inputs", "march_level", "_march"]

Array = NDArray[np.float64]


_REPORT_EVERY = 64  # time steps between progress reports (see _progress)


_BLOCK = 1 << 16  # operator entries built at once per array (steps x loads x nodes)


def level_inputs(
    pbs: list[Problem], plan: _Plan, n: int, nsub: int, stretch: float, n_ie: int
) -> LevelInputs:
    """The inputs of the level of ``n`` intervals (clustering ``stretch``) on ``plan``'s time
    sequence subdivided ``nsub`` times with ``n_ie`` implicit-Euler half steps first, for the
    loads ``pbs`` (one batch: they share their walls and output times)."""
    taus, theta = _level_times(plan.base, nsub, n_ie, plan.zones, _compiled.built("times"))
    pb0 = pbs[0]
    outs = plan.outs if plan.outs is not None else pb0.tau[pb0.tau > plan.tau_s]
    out_at = np.searchsorted(taus, outs)
    p0 = np.array([pb.p0 for pb in pbs])[:, None]
    window = _edges_batch(pbs, plan, taus, _compiled.built("edges"), _compiled.built("tracks"))
    grid = level_grid(len(pbs), n, stretch)
    return LevelInputs(
        taus, theta, out_at, grid.nodes, window, p0, plan.k, plan.yield_wall, plan.image, grid
    )


@dataclass
class _Record:
    """What the march keeps for the outputs (filled as it goes, reduced after it)."""

    area: Array
    """``(loads, outputs)``: ``int R dx`` (filled per output unless snapshots are kept)."""
    load: Array
    """``(loads, outputs)``: ``int p R dx`` [Pa] (idem)."""
    P: Array | None
    """``(loads, outputs, len(p_out))`` density [1/Pa], or None."""
    snaps: Array | None
    """``(outputs, loads x nodes)`` states at the outputs, reduced after the march (one
    copy per output instead of a dozen small reductions), or None (each output reduced when
    reached: the density is wanted, or the snapshots would be large)."""
    a_pl_at: Array
    """``(loads, outputs)``: the plastic area at the outputs."""
    near: Array
    """``(steps + 1, 4 loads)``: the state at the rows next to the walls after every step."""
    ends: Array
    """``(8, loads, steps)``: the end faces' coefficients the solve used (see
    :func:`._moving_block.block_system`)."""


@dataclass
class _State:
    """The state of the march: the solution after the last step and the yield wall's rows."""

    r: Array
    """``R`` of every load, concatenated (a row of the block's state buffer)."""
    z: Array
    """``(5, loads)``: the yield wall's last rows ``(R_{N-1}, R_N)`` before the step, the
    plastic area ``A_pl``, ``(R_{N-1}, R_N)`` after it: the vectors the closure's
    coefficients multiply."""
    next_out: int = 0
    """The next output to record."""
    info: int = 0
    """LAPACK's ``info`` of the solves so far, or-ed (0: every solve succeeded)."""

    @property
    def a_pl(self) -> Array:
        """The plastic area ``A_pl`` of every load (a view into ``z``)."""
        return self.z[2]


def _march(pbs: list[Problem], plan: _Plan, n: int, nsub: int, stretch: float, n_ie: int) -> Level:
    """One grid level (``n`` intervals, ``nsub`` substeps per base step) for a batch of loads
    (see :func:`level_inputs`): outputs ``(loads, outputs)`` at the numerical output times,
    or the reason the level failed."""
    lean = _compiled.built("lean")
    if lean is not None and lean_ok(pbs, plan, nsub) and not progress_reported():
        level = lean_level(lean, _compiled.built("fused"), pbs, plan, n, nsub, stretch, n_ie)
        if level is not None:
            return level
    inp = level_inputs(pbs, plan, n, nsub, stretch, n_ie)
    win, nn = inp.window, inp.nodes.x.size
    if np.count_nonzero(win.start.width <= 0) or np.count_nonzero(win.end.width <= 0):
        return Level(None, 0, nn, "the walls swept the whole window (area 0)")
    return march_level(inp, pbs[0].p_out, stretch)


def march_level(inp: LevelInputs, p_out: Array | None, stretch: float) -> Level:
    """The march of one level on ``inp`` (densities at ``p_out`` [Pa] if given; ``stretch``
    the nodes' clustering, which names the level's memoised rows): the start, then blocks of
    steps (operators by :func:`._moving_block.block_system`, steps by :func:`_steps`), then
    the outputs; a failed solve ends the march with ``Level.failure`` set."""
    win, x, w = inp.window, inp.nodes.x, inp.nodes.w
    nb, nn, n_out, n_steps = inp.p0.shape[0], x.size, inp.out_at.size, inp.taus.size - 1
    n = nn - 1
    r0 = _initial_state(win, x, w, inp.p0, inp.taus[0], inp.k, inp.image)
    fast = _compiled.kernel(nb * nn * n_steps, n_steps, nb * nn)
    if fast is not None and p_out is None and not progress_reported():
        fused = _compiled.built("fused")  # the whole level in a few compiled calls
        level = None if fused is None else fused_level(fused, inp, r0, stretch)
        if level is not None:
            return level
    step = np.diff(inp.taus)
    wn_all, wo_all = inp.theta * step, (1.0 - inp.theta) * step
    yreal = win.real_upper & inp.yield_wall
    g_all = np.where(yreal, win.end.width * win.end.yield_speed, 0.0)  # closure R_N = g A_pl
    grid = inp.grid if inp.grid is not None else level_grid(nb, n, stretch)
    rows, basis = grid.rows, grid.basis
    rec = _record_for(nb, n_out, nn, n_steps, p_out)
    st = _State(r0, np.zeros((5, nb)))
    rec.near[0] = st.r[rows.near]
    out_steps = inp.out_at.tolist() + [-1]
    while st.next_out < n_out and out_steps[st.next_out] == 0:
        _record(rec, st, inp, 0, p_out)
    block = max(1, min(_BLOCK // (nb * nn), n_steps))
    sym = symmetric_steps(win, inp.yield_wall)
    # buffers reused by every block: operators, and the states (row 0 the state before it)
    work = (np.empty((block, 4, nb, nn)), np.empty((block, nb, nn)))
    states_buf = np.empty((block + 1, nb * nn))
    for m0 in range(0, n_steps, block):
        ms = slice(m0, min(m0 + block, n_steps))
        g, yr = g_all[:, ms].T, yreal[:, ms].T  # (steps, loads)
        sy = None if sym is None else sym[:, ms].T
        ops = block_system(win, basis, ms, wn_all[ms], wo_all[ms], g, w, rec.ends, yr, work, sy)
        states = states_buf[: ms.stop - m0 + 1]
        states[0] = st.r
        st.r = states[0]
        yields = yreal[:, ms].any(axis=0).tolist()
        _steps(st, rec, inp, ops, states, m0, yields, rows, p_out, fast)
        if st.info != 0:
            return Level(None, 0, nn, f"tridiagonal solve failed (info={st.info})")
        rec.near[m0 + 1 : ms.stop + 1] = states[1:, rows.near]
    report_progress((n_steps % _REPORT_EVERY) * nn * nb)
    area, load = rec.area, rec.load
    if rec.snaps is not None:
        area, load = _reduce_snapshots(rec.snaps, win, x, w, inp.out_at)
    absorbed_lower, absorbed_upper, moment_lower, moment_upper = _wall_sums(
        win, rec, inp.out_at, inp.yield_wall
    )
    outputs = Outputs(area, absorbed_lower, absorbed_upper, load, moment_lower, moment_upper, rec.P)
    return Level(outputs, n_steps, nn)


def _steps(
    st: _State,
    rec: _Record,
    inp: LevelInputs,
    ops: Block,
    states: Array,
    m0: int,
    yields: list[bool],
    rows: SystemRows,
    p_out: Array | None,
    fast: Callable[..., int] | None = None,
) -> None:
    """The steps ``m0 .. m0 + len(states) - 2`` (see the module for the scheme): the state
    after step ``m0 + i`` into ``states[i + 1]`` (``states[0]`` holds the state before).

    ``yields[i]``: whether a real yield wall closes the system in step ``m0 + i``.  The views
    and buffers are made once per block (a step is about ten numpy calls).  ``fast``: the
    compiled march (:func:`._compiled.kernel`), or None (numpy).
    """
    nb, nn = st.z.shape[1], inp.nodes.x.size
    if fast is not None:
        _compiled_steps(fast, st, rec, inp, ops, states, m0, yields, rows, p_out)
        return
    volumes, walls, last = rows.volumes, rows.walls, rows.last
    # the explicit half's face fluxes of the state before each step: R_j, R_{j+1} per face
    r_lo, r_hi, r_in = states[:, :-1], states[:, 1:], states[:, 1:-1]
    flux_lo, flux_hi = ops.flux_lo[:, :-1], ops.flux_hi[:, :-1]
    lower, diag, upper = ops.lower[:, :-1], ops.diag, ops.upper[:, :-1]
    yield_rhs, yield_gain = ops.yield_rhs, ops.yield_gain
    F, F2, dF = np.empty(nb * nn - 1), np.empty(nb * nn - 1), np.empty(nb * nn - 2)
    F_hi, F_lo = F[1:], F[:-1]  # F_{j+1/2}, F_{j-1/2} of the interior rows
    z = st.z
    z_old, a_pl, z_new, z_rhs = z[:2].reshape(-1), z[2], z[3:].reshape(-1), z[:3]
    pair = np.concatenate([last - 1, last])
    out_steps = inp.out_at.tolist() + [-1]
    mul, sub, add_r = np.multiply, np.subtract, np.add.reduce
    r, info, next_out = st.r, 0, out_steps[st.next_out]
    for i in range(states.shape[0] - 1):
        # explicit half (flux form): b = w R + wo (F_{j+1/2} - F_{j-1/2}), F of the old state
        mul(flux_lo[i], r_lo[i], out=F)
        mul(flux_hi[i], r_hi[i], out=F2)
        F += F2
        b = states[i + 1]
        mul(volumes, r, out=b)  # 0 on the walls' identity rows
        sub(F_hi, F_lo, out=dF)
        r_in[i + 1] += dF
        if nb > 1:
            b[walls] = 0.0  # (the loads' differences across their joints)
        if yields[i]:  # yield closure's right-hand side: g (w_N R_N + A_pl - wo F_{N-1/2})
            r.take(pair, out=z_old)  # (the method: no dispatch through np.take)
            b[last] = add_r(yield_rhs[i] * z_rhs, 0)
        # implicit half: (w - wn dF/dR) R' = b, solved in place of b
        info |= tridiagonal_solve(lower[i], diag[i], upper[i], b)
        if yields[i]:  # A_pl' = A_pl - wo F_{N-1/2} - wn F'_{N-1/2} + w_N (R_N - R_N')
            b.take(pair, out=z_new)
            a_pl += add_r(yield_gain[i] * z, 0)
        r = b
        m = m0 + i + 1
        if m == next_out:  # outputs after this step
            st.r = r
            while out_steps[st.next_out] == m:
                _record(rec, st, inp, m, p_out)
            next_out = out_steps[st.next_out]
        if m % _REPORT_EVERY == 0:
            report_progress(_REPORT_EVERY * nn * nb)
    st.r = r
    st.info |= info


def _compiled_steps(
    fast: Callable[..., int],
    st: _State,
    rec: _Record,
    inp: LevelInputs,
    ops: Block,
    states: Array,
    m0: int,
    yields: list[bool],
    rows: SystemRows,
    p_out: Array | None,
) -> None:
    """:func:`_steps` by the compiled march ``fast`` (:mod:`._compiled`), run from one output
    or progress report to the next (the outputs are recorded here, as there)."""
    nb, n = st.z.shape[1], states.shape[0] - 1
    nn = states.shape[1] // nb
    out_steps = inp.out_at.tolist() + [-1]
    no_yield = np.zeros((0, 5, nb)), np.zeros((0, 3, nb))  # (C-ordered: one signature)
    args = (
        states, ops.flux_lo, ops.flux_hi, ops.lower, ops.diag, ops.upper, rows.volumes,
        rows.walls, rows.last, np.array(yields, dtype=bool),
        no_yield[1] if ops.yield_rhs is None else ops.yield_rhs,
        no_yield[0] if ops.yield_gain is None else ops.yield_gain, st.z,
    )  # fmt: skip
    # one call per block where nothing needs the march to pause: an output is a row of the
    # block's states unless the plastic area moves (a real yield wall) or the output is
    # reduced when reached (densities, large snapshots); progress only for a reporter
    by_output = rec.snaps is None or any(yields)
    by_report = progress_reported()
    i = 0
    while i < n:
        nxt = out_steps[st.next_out]
        stop = n
        if by_report:
            stop = min(n, (m0 + i) // _REPORT_EVERY * _REPORT_EVERY + _REPORT_EVERY - m0)
        if by_output and nxt > m0 + i:
            stop = min(stop, nxt - m0)
        info = fast(i, stop, *args)
        st.r, i = states[stop], stop
        if info != 0:
            st.info |= info
            return
        m = m0 + i
        while 0 < out_steps[st.next_out] <= m:
            st.r = states[out_steps[st.next_out] - m0]
            _record(rec, st, inp, out_steps[st.next_out], p_out)
        st.r = states[stop]
        if by_report and m % _REPORT_EVERY == 0:
            report_progress(_REPORT_EVERY * nn * nb)


def _record_for(nb: int, n_out: int, nn: int, n_steps: int, p_out: Array | None) -> _Record:
    """The empty records of a level (see :class:`_Record`)."""
    want_p = p_out is not None
    return _Record(
        area=np.zeros((nb, n_out)),
        load=np.zeros((nb, n_out)),
        P=np.zeros((nb, n_out, p_out.size)) if want_p else None,
        snaps=None if want_p or n_out * nb * nn > _SNAP else np.empty((n_out, nb * nn)),
        a_pl_at=np.zeros((nb, n_out)),
        near=np.empty((n_steps + 1, 4 * nb)),
        ends=np.empty((8, nb, n_steps)),
    )


def _initial_state(
    win: Window, x: Array, w: Array, p0: Array, t0: float, k: float, image: float | None = None
) -> Array:
    """The free Gaussian at ``t0`` [Pa^2] (mass per unit x, the loads concatenated),
    normalised to the window mass ``erf(k / sqrt 2)``; with an absorbing wall at rest at
    ``image`` [Pa], the one-wall image solution, normalised to its exact window mass."""
    la, wa_ = win.start.lower[:, :1], win.start.width[:, :1]
    pn = wa_ * x  # (then + la: la + wa x, the same sum)
    pn += la
    # (numpy scalars: a Python float costs each operation ~0.5 us of conversion)
    c = np.float64(1.0 / math.sqrt(4.0 * math.pi * t0))
    # wa exp(-(pn - p0)^2 / 4 t0) c, in place (the same operations: no temporaries)
    r2 = pn - p0 if image is not None else np.subtract(pn, p0, out=pn)
    np.square(r2, out=r2)
    r2 /= np.float64(-4.0 * t0)  # (-a / b is a / -b, bit for bit: the sign apart)
    np.exp(r2, out=r2)
    r2 *= wa_
    r2 *= c
    mass: float | Array = math.erf(k / math.sqrt(2.0))  # (the same for every load)
    if image is not None:
        r2 -= wa_ * np.exp(-((pn + p0 - 2.0 * image) ** 2) / (4.0 * t0)) * c
        mass = _image_mass(la[:, 0], la[:, 0] + wa_[:, 0], p0[:, 0], image, t0)
    r2[:, :: x.size - 1] = 0.0  # (the walls' rows: first and last)
    r2 *= (mass / (r2 @ w))[:, None]
    return r2.ravel()


def _image_mass(lo: Array, up: Array, p0: Array, wall: float, t0: float) -> Array:
    """``int_lo^up`` of the one-wall image solution at ``t0`` [Pa^2] (wall at ``wall`` [Pa])."""
    s = 2.0 * math.sqrt(t0)
    direct = erf((up - p0) / s) - erf((lo - p0) / s)
    mirror = erf((up + p0 - 2.0 * wall) / s) - erf((lo + p0 - 2.0 * wall) / s)
    return 0.5 * (direct - mirror)


def _record(rec: _Record, st: _State, inp: LevelInputs, m: int, p_out: Array | None) -> None:
    """Output ``st.next_out`` after step ``m`` (the wall terms are added after the march)."""
    j = st.next_out
    st.next_out += 1
    rec.a_pl_at[:, j] = st.a_pl
    if rec.snaps is not None:
        rec.snaps[j] = st.r
        return
    win, x, w = inp.window, inp.nodes.x, inp.nodes.w
    nb, nn = rec.a_pl_at.shape[0], x.size
    r_ = st.r.reshape(nb, nn)
    if m == 0:
        lv, wv = win.start.lower[:, 0], win.start.width[:, 0]
    else:
        lv, wv = win.end.lower[:, m - 1], win.end.width[:, m - 1]
    pm = lv[:, None] + wv[:, None] * x[None, :]
    rec.area[:, j] = r_ @ w
    rec.load[:, j] = (pm * r_) @ w
    if p_out is not None:
        for i in range(nb):
            cs = CubicSpline(pm[i], r_[i] / wv[i])
            inside = (p_out >= pm[i, 0]) & (p_out <= pm[i, -1])
            rec.P[i, j, inside] = cs(p_out[inside])


def _wall_sums(
    win: Window, rec: _Record, out_at: Array, yield_wall: bool
) -> tuple[Array, Array, Array, Array]:
    """Absorbed probabilities and wall moments ``(absorbed_lower, absorbed_upper,
    moment_lower, moment_upper)`` per output, from the rows next to the walls after every
    step (R = 0 on an absorbing wall) and the end faces' coefficients the solve used."""
    nb = rec.a_pl_at.shape[0]
    s, e = win.start, win.end
    la, wa_, lb, wb_ = s.lower, s.width, e.lower, e.width
    # (nb, n_steps + 1) each: R at the first, second, second-to-last and last node
    r0, r1, rm, rn = (rec.near[:, i * nb : (i + 1) * nb].T for i in range(4))
    mb0, pb0, mb1, pb1, ma0, pa0, ma1, pa1 = rec.ends
    # the wall fluxes times the step's weights: new (end of step) and old (start) halves
    f_new0 = mb0 * r0[:, 1:] + pb0 * r1[:, 1:]
    f_old0 = ma0 * r0[:, :-1] + pa0 * r1[:, :-1]
    f_new1 = mb1 * rm[:, 1:] + pb1 * rn[:, 1:]
    f_old1 = ma1 * rm[:, :-1] + pa1 * rn[:, :-1]
    rl, ru = win.real_lower, win.real_upper
    abs_l = _cumsum0(np.where(rl, f_new0 + f_old0, 0.0))[:, out_at]
    mom_l = _cumsum0(np.where(rl, lb * f_new0 + la * f_old0, 0.0))[:, out_at]
    if yield_wall:
        ends_ = np.hstack([la[:, :1] + wa_[:, :1], lb + wb_])[:, out_at]
        return abs_l, rec.a_pl_at, mom_l, ends_ * rec.a_pl_at
    out_hi = -(f_new1 + f_old1)
    mom = (lb + wb_) * f_new1 + (la + wa_) * f_old1
    abs_u = _cumsum0(np.where(ru, out_hi, 0.0))[:, out_at]
    return abs_l, abs_u, mom_l, -_cumsum0(np.where(ru, mom, 0.0))[:, out_at]


def _cumsum0(a: Array) -> Array:
    """Running sums along the rows of ``a`` after a column of zeros, ``(nb, 1 + steps)``."""
    out = np.empty((a.shape[0], a.shape[1] + 1))
    out[:, 0] = 0.0
    np.cumsum(a, axis=1, out=out[:, 1:])
    return out
