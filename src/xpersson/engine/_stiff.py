"""Time steps of the ``cn`` march where a narrow window makes the diffusion stiff.

Between two real walls (the absorbing wall at ``p = 0`` and a yield wall ``Y``) the window
``W`` stops growing while the diffusion length ``sqrt(2 tau)`` keeps growing.  Its slowest
mode then decays at the rate ``pi^2 / W^2`` [1/Pa^2]: in units of the time plan's own clock
(``ln tau``), at the rate ``sigma = pi^2 tau / W^2`` [1].  Where ``sigma`` passes from about
1 to about 10 the elastic area collapses onto its quasi-steady value (fed by the yield wall's
release) within a few of these decay times: steps geometric in ``tau`` do not resolve that
transient, and Crank-Nicolson, which does not damp the stiff modes (its amplification tends
to -1), carries the transient's error to every later output as a ringing that Richardson
extrapolation cannot cancel.  Measured on the roll-off scene "roll H=0.39 4dec" of
``benchmarks/summary.py`` (``benchmarks/plastic_steps.py``): at 24 nodes the fourth-order
estimate was 1.4e3 x the tolerance with the error at the last outputs, and the controller
needed 4.6e7 node-steps for three loads.

:func:`stiff_refined` subdivides every base step on which ``sigma < STIFF_END`` so that
its substeps advance ``ln tau`` by at most ``STIFF_STEP / max(1, sigma)`` geometric base steps
(the decay per substep, ``sigma d ln tau``, stays below ``STIFF_STEP`` base steps' worth of
``ln tau``): the levels of a plan still subdivide one base sequence, so they stay nested and
the Richardson control is unchanged.  Beyond ``STIFF_END`` the transient has decayed and the
quasi-steady solution is smooth in ``ln tau``; there every base step is split in
``STIFF_LATE`` substeps, which damps the ringing of the stiff modes that Crank-Nicolson keeps
(measured on "roll H=0.39 4dec": the sixth-order estimate at 24 nodes fell from 6.6 to 0.86
of the tolerance for 15 % more work, where twice the steps everywhere cost 95 % more).
Where the outputs reach deep into the quasi-steady regime (``sigma`` up to 1e4-1e5, scenes
with outputs up to ``q_1`` of the held-out design ``benchmarks/plastic_design.py``) halving
was not enough: the level errors at the last outputs fell 30-50x per halving of the step, far
from the ``m^-2`` expansion the Richardson control assumes, and the control refined to 4e7
node-steps (262 ms/load); four substeps took those scenes to 1-8e6 node-steps.  Those level
errors carry odd powers of the step (the yield closure's half cell, and Crank-Nicolson's
undamped stiff modes): :mod:`._cn_odd` controls them where the window is stiff.

Where a real yield wall closes the window the diffusion weights of both halves of a step are
``1 / (W_start W_end)`` (:func:`._moving_block.symmetrize`): with ``1 / W^2`` at either end,
Crank-Nicolson
amplifies a mode far stiffer than the step by ``-(W_end / W_start)^2`` per step, so a window
that widens (the yield wall running up) grows it by the square of its widening over the stiff
regime (seed 151 index 694 of ``benchmarks/fuzz.py``: ``Y`` up 1.8e5x, the coarsest level's
elastic area 99 instead of 7.7e-9, the control out of its work budget).

Only plans with a yield wall change (elsewhere the window grows with ``sqrt(tau)``, and
``sigma`` stays far below 1).

:func:`wall_kinks`: the times a wall declares where its speed has a kink (``Wall.kinks``: the
knee of a roll-off spectrum for a scale-dependent yield wall) are step boundaries of every
level (see the function).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from numpy.typing import NDArray

from ._cn_plan import _edges_batch, _Plan
from ._problem import Problem

__all__ = ["STIFF_END", "STIFF_STEP", "stiff_at_end", "stiffness", "stiff_refined", "wall_kinks"]

Array = NDArray[np.float64]


STIFF_STEP = 0.5  # largest decay of the window's slowest mode per substep, in geometric base
# steps of ln tau (measured on "roll H=0.39 4dec": 0.5 and 0.25 give the same error, 1 a
# 2x larger one at the transient's end)


STIFF_LATE = 4  # substeps per base step beyond STIFF_END (measured on the held-out design of
# benchmarks/plastic_design.py: 2 -> 4 took its worst marching scenes from 89-262 to 22-57
# ms/load with every achieved error within the tolerance; 8 cost more on most scenes).  Keep
# it even: Crank-Nicolson's stiff modes ring with amplification ~ -1 per substep, so with an
# odd count the levels of odd and even mult end a base step on opposite signs, an error
# alternating in the level that Richardson extrapolation cannot cancel (seed 7036 "roll
# H=0.40 5dec": 4 and 6 took 4.1e6 and 5.4e6 node-steps, error 0.011 of the tolerance; 3
# and 5 took 1.6e8 and 2.1e8, errors 11 and 14 tolerances, 5-17x their estimates)


STIFF_END = 10.0  # sigma beyond which the base steps are kept (measured: 10, 20 and 50 give
# the same error; the work grows with it)


def stiffness(pbs: list[Problem], plan: _Plan) -> Array:
    """``sigma = pi^2 tau / W^2`` [1] on every base step of ``plan`` (at its geometric
    midpoint, with the narrowest window of the loads at either end of the step)."""
    base = plan.base
    win = _edges_batch(pbs, plan, base)
    width = np.minimum(win.start.width, win.end.width).min(axis=0)
    mid = np.sqrt(base[:-1] * base[1:])
    with np.errstate(divide="ignore"):
        return np.where(width > 0, math.pi**2 * mid / np.square(width), 0.0)


def stiff_refined(pbs: list[Problem], plan: _Plan, per_decade: float) -> _Plan:
    """``plan`` with its base steps subdivided where the window is stiff (see the module);
    ``plan`` itself when nothing changes (no yield wall, or ``sigma`` below 1 throughout).

    ``per_decade`` [1/decade] is the plan's geometric step density (``ln tau`` advances by
    ``ln 10 / per_decade`` per base step).
    """
    if not plan.yield_wall or plan.base.size < 2 or plan.zones:
        return plan
    base = plan.base
    sigma = stiffness(pbs, plan)
    step = math.log(10.0) / max(per_decade, 4.0)  # the geometric base step in ln tau
    dln = np.log(base[1:] / base[:-1])
    stiff = (sigma > STIFF_STEP) & (sigma < STIFF_END)
    sub = np.where(stiff, np.ceil(dln * sigma / (STIFF_STEP * step) - 1e-9), 1.0)
    sub = np.where(sigma >= STIFF_END, STIFF_LATE, np.maximum(sub, 1.0)).astype(int)
    if not np.any(sub > 1):
        return plan
    # substep j of base step i at base[i] + (base[i + 1] - base[i]) j / sub[i]
    i = np.repeat(np.arange(sub.size), sub)
    j = np.arange(i.size) - np.repeat(np.cumsum(sub) - sub, sub) + 1
    new = np.concatenate([base[:1], base[i] + (base[i + 1] - base[i]) * (j / sub[i])])
    new[np.cumsum(sub)] = base[1:]  # the base times themselves, exactly (outputs, kinks)
    out_index = np.searchsorted(new, base[plan.out_index])
    return dataclasses.replace(plan, base=new, out_index=out_index)


def stiff_at_end(pbs: list[Problem], k: float) -> bool:
    """Whether a yield wall makes the window of some load stiff (``sigma > STIFF_STEP``) at
    the last output time, where ``sigma`` is largest: then :func:`stiff_refined` changes the
    plans of the loads ``pbs`` (window half-width ``k`` [1] in units of ``sqrt(2 tau)``)."""
    pb = pbs[0]
    if pb.upper is None or pb.upper.acts_absorbing:
        return False
    t = float(pb.tau_max)
    s = math.sqrt(2.0 * t)
    lo, up = (float(v[0]) for v in pb.wall_positions(np.array([t])))
    p0 = np.array([p.p0 for p in pbs], dtype=float)
    width = np.minimum(up, p0 + k * s) - np.maximum(lo, p0 - k * s)
    width = width[width > 0]
    return bool(width.size and math.pi**2 * t / float(np.min(width)) ** 2 > STIFF_STEP)


def wall_kinks(pb: Problem, tau_s: float, tau_end: float) -> list[float]:
    """The declared kinks of the walls' speeds (``Wall.kinks`` [Pa^2]) inside
    ``(tau_s, tau_end)``: step boundaries of every level's time plan.

    A yield wall ``Y(zeta(tau))`` moves at ``dY/dtau = Y'(zeta) / f(zeta)``: where ``f``
    has a kink (the knee of a roll-off spectrum, every node of a tabulated one) so has the
    speed, and the closure row ``R_N = W Y' A_pl`` with it.  Inside a step the kink leaves
    a local error that depends on where in the step it falls, irregular in the level's
    subdivision: measured on "roll H=0.36 5dec" (seed 110 of ``benchmarks/plastic_steps.py``)
    the levels' errors had a component irregular in the subdivision of 7 tolerances / m^2,
    which the sixth-order combinations amplified to 1-5 tolerances; with the knee a step
    boundary it is 0.003 tolerances / m^2.
    """
    if not pb.lower.kinks and (pb.upper is None or not pb.upper.kinks):
        return []  # (no declared kink: the common case, without the set's set-up)
    times = {t for w in (pb.lower, pb.upper) if w is not None for t in w.kinks}
    return sorted(t for t in times if tau_s < t < tau_end)
