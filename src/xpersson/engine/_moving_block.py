"""The operators of a block of steps of the ``cn`` march (:mod:`._moving`), built at once.

Every face coefficient of the scheme is a combination of the three face functions
``1, x_f, 1/dx_f`` (:func:`._level.face_basis`) with per-(step, load) weights, so the four
coefficient arrays of a block are one BLAS product (one pass over memory instead of a dozen
broadcasts).  Units: tau in Pa^2, window edges in Pa, their speeds in 1/Pa.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from ._cn_plan import Window

__all__ = ["Block", "block_system", "face_ops", "symmetric_steps", "symmetrize"]

Array = NDArray[np.float64]


class Block(NamedTuple):
    """The systems of a block of steps with the loads concatenated: one row per step, each
    ``(steps, loads x nodes)`` (see :func:`block_system`)."""

    lower: Array
    """Sub-diagonal of the implicit half: ``lower[r]`` (row ``r + 1``) ``= wn (A - D)`` at
    the end of the step (the last slot of each load couples nothing)."""
    diag: Array
    """Diagonal of the implicit half: ``w_j + wn (D - A)_{j+1/2} + wn (A + D)_{j-1/2}``;
    1 on the walls' identity rows, the closure on a real yield wall's last row."""
    upper: Array
    """Super-diagonal of the implicit half: ``upper[r]`` (row ``r``) ``= -wn (A + D)``."""
    flux_lo: Array
    """Explicit half: ``wo (A - D)``, the weight of ``R_j`` in ``wo F_{j+1/2}`` at the start
    of the step."""
    flux_hi: Array
    """Explicit half: ``wo (A + D)``, the weight of ``R_{j+1}`` in ``wo F_{j+1/2}``."""
    yield_rhs: Array | None
    """``(steps, 3, loads)``: a real yield wall's last right-hand side is this times
    ``(R_{N-1}, R_N, A_pl)`` before the step; None where no yield wall is real in the block."""
    yield_gain: Array | None
    """``(steps, 5, loads)``: the gain of ``A_pl`` in the step is this times
    ``(R_{N-1}, R_N, A_pl)`` before and ``(R_{N-1}, R_N)`` after it (0 where the yield wall is
    not real); None where no yield wall is real in the block."""


def block_system(
    win: Window,
    basis: Array,
    ms: slice,
    wn: Array,
    wo: Array,
    g: Array,
    w: Array,
    ends: Array,
    yreal: Array,
    work: tuple[Array, Array],
    sym: Array | None = None,
) -> Block:
    """The systems of the steps ``ms`` (weights ``wn = theta dt``, ``wo = (1 - theta) dt``
    [Pa^2] per step; ``g = W Y'`` per (step, load), 0 where no yield wall is real;
    control volumes ``w``).

    Face fluxes ``F = D (R_{j+1} - R_j) + A (R_j + R_{j+1})`` with ``D = 1 / (W^2 dx_f)``,
    ``A = (l' + x_f W') / (2 W)``.  Interior rows ``j = 1 .. n - 1``:
    ``w_j R_j - wn (F_{j+1/2} - F_{j-1/2}) = w_j R_j^old + wo (F^old_{j+1/2} -
    F^old_{j-1/2})``.  The last row of a real yield wall is the closure ``R_N = g A_pl`` with
    the half cell's mass balance (see :mod:`._moving`).

    The coefficients of the first and last faces, as used, are written into
    ``ends[:, :, ms]`` (order: ``wn (A - D)``, ``wn (A + D)`` at the first face, then at the
    last face; then the same four of the explicit half): the wall fluxes are summed from
    them.  ``work``: buffers (steps, 4, loads, nodes) and (steps, loads, nodes) with
    ``steps >= ms.stop - ms.start`` (reused from block to block: fresh memory would cost a
    page fault per 4 kB on every block).  ``yreal``: (steps, loads) whether the yield wall
    is real.  ``sym``: (steps, loads) where the diffusion weights are symmetric in time
    (:func:`symmetrize`), or None.
    """
    c = ms.stop - ms.start
    nb, nn = g.shape[1], basis.shape[1]
    nf = nn - 1
    ops = face_ops(win, basis, ms, wn, wo, work[0][:c], sym)
    for k, face in enumerate((0, 0, nf - 1, nf - 1)):
        ends[k, :, ms] = ops[:, k % 2, :, face].T
        ends[k + 4, :, ms] = ops[:, 2 + k % 2, :, face].T
    ends[1, :, ms] *= -1.0  # wn(A + D), as the solve used it
    ends[3, :, ms] *= -1.0
    dl, du, Ga, Gp = (ops[:, k] for k in range(4))
    Dg = work[1][:c]
    np.subtract(w[1:-1], dl[..., 1:nf], out=Dg[..., 1:-1])
    Dg[..., 1:-1] -= du[..., : nf - 1]
    Dg[..., 0] = 1.0
    w_last = w[-1]
    # last row of a real yield wall: half cell plus A_pl, closure R_N = g A_pl
    Dg[..., -1] = 1.0 + g * (w_last + ends[3, :, ms].T)
    dl[..., nf - 1] = g * ends[2, :, ms].T
    du[..., 0] = 0.0
    dl, du, Dg, Ga, Gp = (a.reshape(c, nb * nn) for a in (dl, du, Dg, Ga, Gp))
    if not yreal.any():  # no real yield wall in the block: the last-row terms are not used
        return Block(dl, Dg, du, Ga, Gp, None, None)
    # last row of a real yield wall: g (w_N R_N + A_pl - wo F_{N-1/2})
    k_rhs = np.stack([-g * ends[6, :, ms].T, g * (w_last - ends[7, :, ms].T), g], axis=1)
    mb1, pb1, ma1, pa1 = (ends[k, :, ms].T for k in (2, 3, 6, 7))
    k_gain = np.stack([-ma1, w_last - pa1, 0.0 * g, -mb1, -(pb1 + w_last)], axis=1)
    k_gain *= yreal[:, None, :]
    return Block(dl, Dg, du, Ga, Gp, k_rhs, k_gain)


def face_ops(
    win: Window,
    basis: Array,
    ms: slice,
    wn: Array,
    wo: Array,
    out: Array,
    sym: Array | None = None,
) -> Array:
    """The face coefficients of the steps ``ms`` into ``out`` (steps, 4, loads, nodes):
    ``wn (A - D)``, ``-wn (A + D)`` at the end of each step, ``wo (A - D)``, ``wo (A + D)`` at
    its start (weights ``wn``, ``wo`` [Pa^2] per step; see :func:`block_system`), by one BLAS
    product ``(steps 4 loads, 3) x (3, nodes)`` with the face functions ``basis``; ``sym``
    (steps, loads) or None: the steps whose ``D`` is symmetric in time (:func:`symmetrize`)."""
    c, nb, nn = ms.stop - ms.start, win.start.width.shape[0], basis.shape[1]
    coef = np.empty((c, 4, nb, 3))
    for k, (edge, th) in enumerate(((win.end, wn), (win.start, wo))):
        W = edge.width[:, ms].T
        th = th[:, None]
        a_ = th * (edge.lower_speed[:, ms].T / (2.0 * W))
        b_ = th * (edge.width_speed[:, ms].T / (2.0 * W))
        d_ = th / W**2
        coef[:, 2 * k, :, 0], coef[:, 2 * k, :, 1], coef[:, 2 * k, :, 2] = a_, b_, -d_
        sign = -1.0 if k == 0 else 1.0  # the super-diagonal is -wn (A + D)
        coef[:, 2 * k + 1, :, 0], coef[:, 2 * k + 1, :, 1] = sign * a_, sign * b_
        coef[:, 2 * k + 1, :, 2] = sign * d_
    if sym is not None:
        symmetrize(coef, sym, wn, wo, win.start.width[:, ms].T, win.end.width[:, ms].T)
    # (negating every weight negates the product exactly: round to nearest is symmetric)
    np.matmul(coef.reshape(-1, 3), basis, out=out.reshape(-1, nn))
    return out


def symmetric_steps(win: Window, yield_wall: bool) -> Array | None:
    """``(loads, steps)``: the steps whose diffusion weights :func:`symmetrize` makes
    symmetric in time, those where a real yield wall closes the window; or None (none).

    With ``D = 1 / (W^2 dx)`` taken at each end of the step, Crank-Nicolson amplifies a mode
    far stiffer than the step (``dt D >> 1``) by ``-(D_start / D_end) = -(W_end / W_start)^2``
    per step: while the window widens (the yield wall running up) such a mode grows by the
    square of the widening over the steps where it is stiff.  A narrow window between the
    walls is stiff (:mod:`._stiff`), and ``Y ~ zeta^n`` widens it by 1e3-1e5x on the fuzz
    scenes that ended with ``max_steps`` (seed 151 index 694 of ``benchmarks/fuzz.py``: the
    coarsest level's elastic area 99 at the last output instead of 7.7e-9).  Every real
    yield-wall step, not only the stiff ones: a switch inside a base step would fall at a
    place that depends on the level's subdivision, an error irregular in it that Richardson
    extrapolation cannot cancel (``tests/engine/test_stiff.py``); the wall enters the window
    at a kink of its edge, a step boundary of every level."""
    if not yield_wall:
        return None
    flag = win.real_upper
    return flag if np.count_nonzero(flag) else None


def symmetrize(
    coef: Array, sym: Array, wn: Array, wo: Array, s_width: Array, e_width: Array
) -> None:
    """Set the diffusion weights of both halves of the steps ``sym`` (steps, loads) to
    ``1 / (W_start W_end)`` in ``coef`` (steps, 4, loads, 3; see :func:`face_ops`), in place.

    ``wn``, ``wo`` [Pa^2] per step; the window's widths ``s_width``, ``e_width`` (steps,
    loads) [Pa] at the start and end of every step.  ``1 / (W_start W_end)`` differs from
    the mean of ``1 / W_start^2`` and ``1 / W_end^2`` by ``O(dt^2)`` and is symmetric in the
    step's two ends, so the scheme stays second order with an error expansion in even
    powers of the step (Richardson); its stiff modes are amplified by ``-wo / wn = -1``
    (and decay, slowly), not by ``-(W_end / W_start)^2`` (see :func:`symmetric_steps`).
    Both marches (numpy, compiled) call this on their coefficients: the same numbers."""
    i, k = np.nonzero(sym)
    if i.size == 0:
        return
    w2 = s_width[i, k] * e_width[i, k]
    dn, do = wn[i] / w2, wo[i] / w2
    coef[i, 0, k, 2] = -dn
    coef[i, 1, k, 2] = -dn
    coef[i, 2, k, 2] = -do
    coef[i, 3, k, 2] = do
