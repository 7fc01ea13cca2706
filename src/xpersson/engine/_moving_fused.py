"""The whole march of one ``cn`` grid level in one compiled call (the compiled path's level).

The numpy path (:mod:`._moving`) builds the operators of a block of steps at once
(:func:`._moving_block.block_system`), marches the steps, keeps the rows next to the walls and
the end faces' coefficients, and sums the wall fluxes after the march
(:func:`._moving._wall_sums`). On the small grids an accurate error control leaves (tens of
nodes, hundreds of steps) those numpy calls, not the node-steps, were most of a level's time.
Here the face coefficients are the same one BLAS product (:func:`._moving_block.face_ops`), and
:func:`level_march` does the rest per step in one loop, in the numpy path's order: the end
faces, the diagonal and the yield closure's rows, the explicit half in flux form, the
tridiagonal solve as LAPACK ``dgtsv`` does it (:func:`._cnstep._solve_factor`, which also
eliminates the next step's system beside the back substitution: the two chains of divisions
run side by side; with the per-step overheads cut, 18-20 -> 9.5-11 ns per node-step, the C
march's ~10: ``benchmarks/results/cn_nodestep.md``), the wall fluxes summed as it goes (as
``numpy.cumsum`` sums them) and the states at the outputs, reduced as the numpy path reduces
them: the outputs are the numpy path's bit for bit (also on generated
problems, ``tests/engine/test_compiled_generated.py``).

Used when the compiled march is in force (:func:`._compiled.kernel`) and the level wants no
densities, no progress reports and no outputs beyond the snapshot size of the numpy path
(those take the per-block compiled steps). Units as in :mod:`._moving`: tau in Pa^2, window
edges in Pa, their speeds in 1/Pa.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ._cnstep import _factor, _solve_factor
from ._level import Level, Outputs, level_grid
from ._moving_block import symmetric_steps, symmetrize

__all__ = ["face_coefficients", "fused_level", "level_march"]  # (and _level_steps: compiled)

Array = NDArray[np.float64]

_OPS = 1 << 16  # face coefficients built at once (steps x 4 x loads x nodes; 2^16 doubles,
# 512 kB, stay in the cache until the march reads them; at 2^18 the fused level's own time,
# mostly this product, was 4.0-7.3 ms per load on plastic_design.py's seed 7036 "roll H=0.40
# 5dec", at 2^16 2.7-5.3, 2^15 and 2^17 no better; the same product per row: results bitwise)

_SNAP = 1 << 20  # largest output snapshot array (outputs x loads x nodes), both paths


def fused_level(fns: tuple[Callable[..., int], Callable[..., None]], inp: Any, r0: Array,
                stretch: float, coef_all: Array | None = None) -> Level | None:  # fmt: skip
    """The outputs of the level ``inp`` (:class:`._moving.LevelInputs`) marched from the state
    ``r0`` (the loads concatenated) by ``fns``: :func:`level_march` and
    :func:`face_coefficients` (compiled, or as Python); None where the outputs' states would be
    too many to keep (the caller marches). ``coef_all``: every step's face coefficients
    (steps, 4, loads, 3) if already made (:func:`._cn_lean.level_setup`)."""
    march, coefficients = fns
    win, nodes = inp.window, inp.nodes
    s, e = win.start, win.end
    nb, nn, n_out = inp.p0.shape[0], nodes.x.size, inp.out_at.size
    if n_out * nb * nn > _SNAP:
        return None
    grid = inp.grid if inp.grid is not None else level_grid(nb, nn - 1, stretch)
    rows, basis = grid.rows, grid.basis
    snaps, sums = np.empty((n_out, nb * nn)), np.zeros((7, nb, n_out))
    zs = np.zeros((9, nb))  # (z and acc in one buffer; r0 is the caller's fresh state)
    carry = (r0, zs[:5], zs[5:], np.zeros(1, np.int64))
    n_steps = inp.taus.size - 1
    block = max(1, min(_OPS // (4 * nb * nn), n_steps))
    # (the loads' rows concatenated: the march takes each step's four rows with no reshape)
    coef = np.empty((block, 4, nb, 3)) if coef_all is None else coef_all
    ops = np.empty((block, 4, nb * nn))
    sym = symmetric_steps(win, inp.yield_wall)
    if sym is not None:  # (the weights as the numpy path's: np.diff, then theta)
        step = np.diff(inp.taus)
        wn, wo = inp.theta * step, (1.0 - inp.theta) * step
    for m0 in range(0, n_steps, block):
        c = min(block, n_steps - m0)
        if coef_all is None:
            coefficients(m0, m0 + c, inp.taus, inp.theta, s.width, s.lower_speed,
                         s.width_speed, e.width, e.lower_speed, e.width_speed, coef)  # fmt: skip
            cf = coef[:c]
            if sym is not None:  # (as face_ops: the same numbers)
                sl = slice(m0, m0 + c)
                symmetrize(cf, sym[:, sl].T, wn[sl], wo[sl], s.width[:, sl].T, e.width[:, sl].T)
        else:
            cf = coef_all[m0 : m0 + c]
        # the face coefficients: the numpy path's BLAS product (face_ops), the same numbers
        np.matmul(cf.reshape(-1, 3), basis, out=ops[:c].reshape(-1, nn))
        info = march(
            m0, m0 + c, ops, nodes.w, rows.volumes, rows.walls, rows.last, inp.yield_wall,
            win.real_lower, win.real_upper, e.yield_speed, s.lower, s.width, e.lower, e.width,
            inp.out_at, *carry, snaps, sums,
        )  # fmt: skip
        if info != 0:
            return Level(None, 0, nn, f"tridiagonal solve failed (info={info})")
    if n_steps == 0:  # (outputs at the start only)
        snaps[:] = r0
    edges = sums[5:] if n_steps else None  # (the window at the outputs, as marched)
    area, load = _reduce_snapshots(snaps, win, nodes.x, nodes.w, inp.out_at, edges)
    a_pl, abs_l, abs_u, mom_l, mom_u = sums[:5]
    mom_u = -mom_u
    if inp.yield_wall:  # the plastic area is what the yield wall holds, at its position
        up = np.hstack([s.lower[:, :1] + s.width[:, :1], e.lower + e.width])[:, inp.out_at]
        abs_u, mom_u = a_pl, up * a_pl
    return Level(Outputs(area, abs_l, abs_u, load, mom_l, mom_u, None), n_steps, nn)


def _reduce_snapshots(
    snaps: Array, win: Any, x: Array, w: Array, out_at: Array, edges: Array | None = None
) -> tuple[Array, Array]:
    """Area ``int R dx`` and load ``int p R dx`` (``p = l + W x``) per output (``edges``:
    the window's lower edge and width at the outputs, (2, loads, outputs) [Pa], as the fused
    march records them; taken from ``win`` unless given)."""
    n_out, nb = snaps.shape[0], win.start.lower.shape[0]
    R = snaps.reshape(n_out, nb, x.size)
    if edges is None:
        lv = _at_outputs(win.start.lower, win.end.lower, out_at)
        wv = _at_outputs(win.start.width, win.end.width, out_at)
    else:
        lv, wv = edges
    area = (R @ w).T
    return area, lv * area + wv * (R @ (x * w)).T


def _at_outputs(start: Array, end: Array, out_at: Array) -> Array:
    """A window edge at the output steps: ``start[:, 0]`` at step 0, else ``end[:, m - 1]``
    (``np.hstack([start[:, :1], end])[:, out_at]`` without building the whole)."""
    v = end[:, out_at - 1]
    if out_at.size and out_at[0] == 0:  # (sorted: only the first can be the start)
        v[:, 0] = start[:, 0]
    return v


def face_coefficients(  # noqa: PLR0913 - the window's arrays, as the Window holds them
    i0: int,
    i1: int,
    taus: Any,
    theta: Any,
    s_width: Any,
    s_lv: Any,
    s_wv: Any,
    e_width: Any,
    e_lv: Any,
    e_wv: Any,
    coef: Any,
) -> None:  # pragma: no cover - compiled (the numpy path is the reference)
    """The weights of the face functions ``1, x_f, 1/dx_f`` in the steps ``i0 .. i1 - 1``
    into ``coef`` (block, 4, loads, 3), as :func:`._moving_block.face_ops` builds them (the
    same operations): ``wn (A - D)``, ``-wn (A + D)`` at the end of each step, ``wo (A - D)``,
    ``wo (A + D)`` at its start, ``wn = theta dt``, ``wo = (1 - theta) dt`` [Pa^2]; the
    windows' widths and speeds (loads, steps) [Pa, 1/Pa] at the start (``s_``) and end
    (``e_``) of every step."""
    for i in range(i0, i1):
        dt = taus[i + 1] - taus[i]
        th_n, th_o = theta[i] * dt, (1.0 - theta[i]) * dt
        c = coef[i - i0]
        for k in range(s_width.shape[0]):
            width = e_width[k, i]
            a_ = th_n * (e_lv[k, i] / (2.0 * width))
            b_ = th_n * (e_wv[k, i] / (2.0 * width))
            d_ = th_n / (width * width)
            c[0, k, 0], c[0, k, 1], c[0, k, 2] = a_, b_, -d_
            c[1, k, 0], c[1, k, 1], c[1, k, 2] = -a_, -b_, -d_
            width = s_width[k, i]
            a_ = th_o * (s_lv[k, i] / (2.0 * width))
            b_ = th_o * (s_wv[k, i] / (2.0 * width))
            d_ = th_o / (width * width)
            c[2, k, 0], c[2, k, 1], c[2, k, 2] = a_, b_, -d_
            c[3, k, 0], c[3, k, 1], c[3, k, 2] = a_, b_, d_


def level_march(  # noqa: PLR0913, PLR0912, PLR0915, C901 - one compiled loop, numpy's order
    i0: int,
    i1: int,
    ops: Any,
    w: Any,
    volumes: Any,
    walls: Any,
    last: Any,
    yield_wall: bool,
    real_lower: Any,
    real_upper: Any,
    yield_speed: Any,
    la: Any,
    wa: Any,
    lb: Any,
    wb: Any,
    out_at: Any,
    r: Any,
    z: Any,
    acc: Any,
    pos: Any,
    snaps: Any,
    sums: Any,
) -> int:  # pragma: no cover - compiled (the numpy path is the reference)
    """March the steps ``i0 .. i1 - 1`` of a level (the work arrays made here, the steps by
    :func:`_level_steps`); returns LAPACK's ``info`` of the first failed solve (0: all
    succeeded).

    ``ops`` (block, 4, loads x nodes): the face coefficients of the steps from ``i0`` on
    (:func:`._moving_block.face_ops`); ``w`` the control volumes, ``volumes``, ``walls``,
    ``last`` the rows of the loads' systems (:func:`._level.system_rows`); ``yield_wall``
    whether the upper wall is a yield wall; ``real_lower``, ``real_upper`` (loads, steps)
    whether the lower, upper wall is real in the step; ``yield_speed`` its speed [1/Pa] at the
    end of the step (the closure's ``g = W Y'``); ``la``, ``wa``, ``lb``, ``wb`` the window's
    lower edge and width at the start and the end of every step [Pa]; ``out_at`` the steps
    after which the outputs are taken.  Carried from block to block: ``r`` the state (loads
    x nodes), ``z`` (5, loads) the yield rows (``R_{N-1}, R_N`` before the step, ``A_pl``,
    ``R_{N-1}, R_N`` after it), ``acc`` (4, loads) the running wall sums, ``pos[0]`` the
    next output.
    Written at the outputs: ``snaps`` the states, ``sums`` (7, loads, outputs) the plastic
    area, the probabilities absorbed by the lower and upper walls and their moments (the
    upper one negated), the window's lower edge and width.
    """
    nb, m = last.shape[0], r.shape[0]
    b = np.empty(m)  # the state and the next one swap buffers
    # each step's system is eliminated during the step before (_solve_factor): two of each
    dg, fact, swap = np.empty((2, m)), np.empty((2, m)), np.empty((2, m), np.bool_)
    ends, g, yields = np.empty((2, 8, nb)), np.empty((2, nb)), np.zeros(2, np.bool_)
    return _level_steps(i0, i1, ops, w, volumes, walls, last, yield_wall, real_lower,  # noqa: F821
                        real_upper, yield_speed, la, wa, lb, wb, out_at, r, z, acc, pos, snaps,
                        sums, b, dg, fact, swap, ends, g, yields)  # fmt: skip


def _level_steps(  # noqa: PLR0913, PLR0912, PLR0915, C901 - one compiled loop, numpy's order
    i0: int,
    i1: int,
    ops: Any,
    w: Any,
    volumes: Any,
    walls: Any,
    last: Any,
    yield_wall: bool,
    real_lower: Any,
    real_upper: Any,
    yield_speed: Any,
    la: Any,
    wa: Any,
    lb: Any,
    wb: Any,
    out_at: Any,
    r: Any,
    z: Any,
    acc: Any,
    pos: Any,
    snaps: Any,
    sums: Any,
    b: Any,
    dg: Any,
    fact: Any,
    swap: Any,
    ends: Any,
    g: Any,
    yields: Any,
) -> int:  # pragma: no cover - compiled (the numpy path is the reference)
    """The steps of :func:`level_march` (its arguments, then its work arrays: ``b`` (loads x
    nodes) the next state, ``dg``, ``fact``, ``swap`` (2, loads x nodes) two steps' diagonal
    and elimination, ``ends`` (2, 8, loads), ``g`` (2, loads), ``yields`` (2,) their end
    faces and closures). Compiled without numba's reference counting (``_nrt=False``, see
    :mod:`._compiled`): it makes no arrays, and the counts of the views a step takes were
    ~0.3 us a step, a third of a small level's march; the same operations."""
    nb, nn = last.shape[0], w.shape[0]
    m, n_out = nb * nn, out_at.shape[0]
    w_last = w[nn - 1]
    state = r
    j_out = pos[0]
    while i0 == 0 and j_out < n_out and out_at[j_out] == 0:
        _record(state, z, acc, snaps, sums, j_out, la[:, 0], wa[:, 0])
        j_out += 1
    if i1 <= i0:
        return 0
    c = ops[0]
    _system(i0, c, dg[0], w, ends[0], g[0], yields, 0, yield_wall, real_upper, wb, yield_speed)
    info = _factor(c[0, : m - 1], dg[0], c[1, : m - 1], fact[0], swap[0])
    for i in range(i0, i1):
        if info != 0:
            return info
        cur, nxt = (i - i0) % 2, (i - i0 + 1) % 2
        c = ops[i - i0]  # (the block's own: the solve overwrites its diagonals in place)
        dl, du, fl, fh = c[0], c[1], c[2], c[3]
        e, gs = ends[cur], g[cur]
        _explicit(b, state, fl, fh, volumes, walls, nb)
        if yields[cur]:
            _yield_rows(state, b, z, last, e, gs, w_last)
        more = i + 1 < i1
        c2 = ops[i - i0 + 1] if more else c
        if more:
            _system(i + 1, c2, dg[nxt], w, ends[nxt], g[nxt], yields, nxt, yield_wall,
                    real_upper, wb, yield_speed)  # fmt: skip
        dl2, du2 = c2[0], c2[1]
        info = _solve_factor(
            dl[: m - 1], dg[cur], du[: m - 1], fact[cur], swap[cur], b,
            dl2[: m - 1], dg[nxt], du2[: m - 1], fact[nxt], swap[nxt], more,
        )  # fmt: skip
        for k in range(nb):
            if yields[cur]:
                _yield_gain(b, z, last, e, gs, w_last, k, yield_wall and real_upper[k, i])
            _wall_fluxes(state, b, k * nn, nn, e, k, acc, real_lower[k, i], real_upper[k, i],
                         la[k, i], wa[k, i], lb[k, i], wb[k, i])  # fmt: skip
        state, b = b, state
        while j_out < n_out and out_at[j_out] == i + 1:
            _record(state, z, acc, snaps, sums, j_out, lb[:, i], wb[:, i])
            j_out += 1
    if (i1 - i0) % 2 == 1:  # the last state is in the other buffer
        for q in range(m):
            r[q] = state[q]
    pos[0] = j_out
    return 0


def _yield_rows(
    state: Any, b: Any, z: Any, last: Any, e: Any, g: Any, w_last: float
) -> None:  # pragma: no cover - compiled
    """The yield closure's rows of a step's right-hand side ``b`` (every load's last row:
    ``g (w_N R_N + A_pl - wo F_{N-1/2})``, ``g`` 0 where no yield wall is real; ``e`` the
    step's end faces), and the rows ``R_{N-1}, R_N`` of the ``state`` before it into
    ``z[:2]``."""
    for k in range(last.shape[0]):
        gk = g[k]
        z[0, k] = state[last[k] - 1]
        z[1, k] = state[last[k]]
        rhs = (-gk * e[6, k]) * z[0, k] + (gk * (w_last - e[7, k])) * z[1, k]
        b[last[k]] = rhs + gk * z[2, k]


def _yield_gain(
    b: Any, z: Any, last: Any, e: Any, g: Any, w_last: float, k: int, real: bool
) -> None:  # pragma: no cover - compiled
    """Load ``k``'s plastic area after a step with a yield wall (``real``: whether its own is
    real there): ``A_pl' = A_pl - wo F_{N-1/2} - wn F'_{N-1/2} + w_N (R_N - R_N')``, with the
    new rows ``R_{N-1}, R_N`` of ``b`` into ``z[3:]``, as the numpy path sums it."""
    z[3, k] = b[last[k] - 1]
    z[4, k] = b[last[k]]
    yr = 1.0 if real else 0.0
    gain = (-e[6, k] * yr) * z[0, k]
    gain += ((w_last - e[7, k]) * yr) * z[1, k]
    gain += (0.0 * g[k] * yr) * z[2, k]
    gain += (-e[2, k] * yr) * z[3, k]
    gain += (-(e[3, k] + w_last) * yr) * z[4, k]
    z[2, k] += gain


def _system(
    i: int, c: Any, dg: Any, w: Any, ends: Any, g: Any, yields: Any, slot: int,
    yield_wall: bool, real_upper: Any, wb: Any, yield_speed: Any,
) -> None:  # fmt: skip  # pragma: no cover - compiled
    """Step ``i``'s system (as :func:`._moving_block.block_system` makes it) on its face
    coefficients ``c`` (4, loads x nodes: ``dl``, ``du`` overwritten, ``fl``, ``fh``), every
    load's rows: its end faces' coefficients into ``ends[:, k]``, the diagonal ``dg``, and the
    closure ``R_N = g A_pl`` in its last row (``g = W Y'`` into ``g``, 0 where no yield wall is
    real; whether one is into ``yields[slot]``)."""
    nb, nn = real_upper.shape[0], w.shape[0]
    dl, du, fl, fh = c[0], c[1], c[2], c[3]
    nf = nn - 1
    yields[slot] = False
    for k in range(nb):
        yr = yield_wall and real_upper[k, i]
        gk = wb[k, i] * yield_speed[k, i] if yr else 0.0
        g[k] = gk
        yields[slot] = yields[slot] or yr
        base = k * nn
        ends[0, k], ends[1, k] = dl[base], -du[base]
        ends[2, k], ends[3, k] = dl[base + nf - 1], -du[base + nf - 1]
        ends[4, k], ends[5, k] = fl[base], fh[base]
        ends[6, k], ends[7, k] = fl[base + nf - 1], fh[base + nf - 1]
        # (on views from 0: with indices offset by a variable ``base`` the compiled loop ran
        # 4x slower, each access checked and none vectorised)
        out, lo, up = (
            dg[base + 1 : base + nn - 1],
            dl[base + 1 : base + nn - 1],
            du[base : base + nn - 2],
        )
        for j in range(nn - 2):
            out[j] = w[j + 1] - lo[j] - up[j]
        dg[base] = 1.0
        dg[base + nn - 1] = 1.0 + gk * (w[nn - 1] + ends[3, k])
        dl[base + nf - 1] = gk * ends[2, k]
        du[base] = 0.0


def _explicit(
    b: Any, state: Any, fl: Any, fh: Any, volumes: Any, walls: Any, nb: int
) -> None:  # pragma: no cover - compiled
    """The explicit half in flux form, ``b = w R + wo (F_{j+1/2} - F_{j-1/2})`` with the face
    fluxes ``F`` of ``state`` (the walls' identity rows 0), as the numpy path sums it."""
    m = b.shape[0]
    b[0] = volumes[0] * state[0]
    f_prev = fl[0] * state[0] + fh[0] * state[1]
    for q in range(1, m - 1):
        f = fl[q] * state[q] + fh[q] * state[q + 1]
        b[q] = volumes[q] * state[q]
        b[q] += f - f_prev
        f_prev = f
    b[m - 1] = volumes[m - 1] * state[m - 1]
    if nb > 1:
        for q in range(walls.shape[0]):
            b[walls[q]] = 0.0


def _wall_fluxes(
    r: Any, b: Any, base: int, nn: int, ends: Any, k: int, acc: Any, rl: bool, ru: bool,
    la: float, wa: float, lb: float, wb: float,
) -> None:  # fmt: skip  # pragma: no cover - compiled
    """Add the wall fluxes of load ``k`` in a step (old state ``r``, new ``b``; lower, upper
    wall real ``rl``, ``ru``; window edges ``la``, ``wa`` at its start, ``lb``, ``wb`` at its
    end [Pa]) to ``acc``, as :func:`._moving._wall_sums` sums them."""
    f_new0 = ends[0, k] * b[base] + ends[1, k] * b[base + 1]
    f_old0 = ends[4, k] * r[base] + ends[5, k] * r[base + 1]
    f_new1 = ends[2, k] * b[base + nn - 2] + ends[3, k] * b[base + nn - 1]
    f_old1 = ends[6, k] * r[base + nn - 2] + ends[7, k] * r[base + nn - 1]
    if rl:
        acc[0, k] += f_new0 + f_old0
        acc[2, k] += lb * f_new0 + la * f_old0
    if ru:
        acc[1, k] += -(f_new1 + f_old1)
        acc[3, k] += (lb + wb) * f_new1 + (la + wa) * f_old1


def _record(
    r: Any, z: Any, acc: Any, snaps: Any, sums: Any, j: int, lower: Any, width: Any
) -> None:  # pragma: no cover - compiled
    """Output ``j``: the state, the sums, and the window's ``lower`` edge and ``width`` [Pa]
    per load there (for the reduction after the march)."""
    for q in range(r.shape[0]):
        snaps[j, q] = r[q]
    for k in range(z.shape[1]):
        sums[0, k, j] = z[2, k]
        for s in range(4):
            sums[1 + s, k, j] = acc[s, k]
        sums[5, k, j] = lower[k]
        sums[6, k, j] = width[k]
