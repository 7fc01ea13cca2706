"""Error control of the ``cn`` method: which grid levels to solve and how to combine them.

Levels are keyed ``(n_base, mult, dense)``: ``n_base mult`` intervals on the time plan of
``n_base`` intervals at ``dense`` times the pilot's steps per decade per interval, each base
step subdivided ``mult`` times (so the levels of one ``(n_base, dense)`` have their space and
time steps in the exact ratios ``1/mult``: their errors share one expansion in even powers of
the step, which Richardson extrapolation cancels).

* Second order (mode ``R``): the pair ``mult = 1, 2``; the finer level is the answer, its error
  estimate ``2 |R_2 - R_1| / 3`` (twice the asymptotic value).  Used while the grid it predicts
  is at most ``R_MAX_REFINE`` times the last pair's.
* Fourth order (mode ``E``): the triple ``mult = 1, 2, 4``, answer ``E(2, 4)``, estimate
  ``2 |E(2, 4) - E(1, 2)| / 15`` (twice the asymptotic value).
* Sixth order (mode ``S``; moving walls without declared breakpoints and without densities,
  where the fourth order's grid would be large): four levels ``mult = 1, 2, 3, 4`` at twice
  the pilot's steps per node (the time error dominates the space error of these problems:
  measured on the yield-wall and ``jkr`` scenes of ``benchmarks/cn_walls.py``, this halves the
  work for a given error).  Two Richardson combinations cancel the ``h^2`` and ``h^4`` terms:
  ``S_a`` of levels 1, 2, 3 and ``S_b`` of levels 2, 3, 4 (weights :func:`richardson_weights`).
  The answer is ``S_b``, its error estimate ``|S_b - S_a|``: asymptotically the ``h^6`` error
  of ``S_a``, which is 16x that of ``S_b`` (the constants ``sum w m^-6 = prod m^-2`` are 1/36
  and 1/576); so the estimate is ~15x the asymptotic error of the answer, a margin kept for
  the pre-asymptotic and non-smooth parts of the error (kinks of tabulated walls: measured
  actual / estimate <= 0.6 on those scenes, against their reference solutions).  A miss is
  answered by the next level of the same grid (``mult = 5, 6, ...``: the last three levels
  answer, the estimate stays ``S_MARGIN`` x asymptotic) or a new grid, whichever is predicted
  cheaper (:func:`_sixth_next`); a round that misses its prediction by ``S_MISS`` returns to
  the fourth order.  Where the sixth order may follow (and ``rtol <= S_RTOL``), the pilot pair
  and the fourth-order levels take its steps per node, so that they share levels.  A
  fourth-order triple that misses is followed by the quadruple's one missing level (``mult =
  3``, ``S_FIRST``), cheaper than any new grid (at a looser rtol a trial on the triple's steps).

Where a yield wall makes the window stiff (:mod:`._stiff`: the time plans then resolve the
decay of the window's slowest mode), the high-order levels take ``DENSE_STIFF`` steps per
node, and at ``rtol <= S_RTOL`` :mod:`._cn_odd` controls the error (odd powers of the step).
Elsewhere a moving yield wall's sixth-order round that misses goes on at ``DENSE_STIFF``
steps per node (:func:`_denser`; the time error dominated on seed 7041 "roll H=0.85 3dec"
of ``benchmarks/plastic_design.py``: 6.4 x the tolerance at 2 steps per node, 1.0 at 4).

A yield wall that has left every load's window by the last output is released from it
(:func:`_release`) where the pilot level shows its plastic area negligible: a hardness
growing faster than the diffusion length otherwise drags the window, and its nodes, far
beyond the support of ``P``.

An accepted estimate is reported as a uniform fraction of the tolerance per load, the largest
estimated (a difference of levels may cross zero), at least ``EST_FLOOR`` (an unresolved tail).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from . import _compiled
from ._cn_budget import _finest_pair
from ._cn_odd import _weights_of, odd_rounds
from ._cn_outputs import EST_FLOOR, fitted_of, fourth_of, judged, load_scale
from ._level import Outputs, combine, weighted
from ._problem import Problem
from ._stiff import stiff_at_end

__all__ = ["_Fit", "_control", "richardson_weights"]

Array = NDArray[np.float64]

_EPS = float(np.finfo(float).eps)


AIM = 0.5  # the next grid is aimed at an error estimate of AIM x tolerance (about half the
# estimate is the actual error: AIM/2 x rtol expected; 0.5 leaves a factor 2 for the prediction)


R_MAX_REFINE = math.sqrt(16.0 / 5.0)  # (1.79) largest refinement of the second-order mode: a
# pair grown further (5 n^2, see E_WORK) costs more than the triple's missing level (16 n^2)


R_SKIP = 64.0  # a second-order pilot asking for a refinement beyond R_SKIP has the sixth-order
# pilot first
# (where it fits), the fourth-order one only if the sixth order would cost more


DENSE = 2  # steps per node of the sixth-order levels, in units of the pilot's


DENSE_STIFF = 4  # the same where a yield wall makes the window stiff (:mod:`._stiff`): there
# the time error dominates (measured on "roll H=0.39 4dec" and "roll H=0.31 5dec" of
# benchmarks/summary.py at 24 nodes: the sixth-order estimate falls 12-17x from 2 to 4 steps
# per node, 1.2-9x more from 4 to 8; benchmarks/plastic_steps.py)


S_GROW = 2.0  # a fourth-order pilot asking for a grid more than S_GROW x finer: sixth order


E_WORK, S_WORK = 21.0, 60.0  # node-steps of a triple / quadruple over (n^2 x the pilot's steps
# per node): sum of mult^2 over the levels (1 + 4 + 16; 1 + 4 + 9 + 16 at twice the steps)


S_RTOL = 1e-5  # the pilot pair takes the sixth order's steps per node at rtol <= S_RTOL only


S_MARGIN = 15.0  # the sixth order's estimate: S_MARGIN x the asymptotic error of its answer

S_LMAX = 8  # most levels of one sixth-order grid

S_MISS = 2.0  # a sixth-order round missing its prediction by more: back to the fourth order

S_FAVOR = 2.0  # the sixth order taken over a fourth-order round predicted S_FAVOR x dearer


S_FIRST = True  # a fourth-order triple that misses, where the sixth order fits and shares
# its levels: the quadruple's one missing level (mult 3) first (on the jkr scenes of
# benchmarks/jkr_control.py the worst one-load solve 9.8e4 -> 4.7e4 node-steps)


S_ORDER = 4.0  # order assumed when growing the sixth-order grid (measured: 4-6 pre-asymptotic)


E_GRADED = 1.0 / 3.0  # the fourth order's estimate factor when the march crosses a declared
# breakpoint: after a square-root onset the combination E converges at order ~2.4, not 4
# (measured on the jkr onset scene of benchmarks/summary.py: |E - exact| = 0.234 |E(2, 4) -
# E(1, 2)| at n = 32..256, where 2/15 assumed order 4); 1/3 is its order-2 bound


E_GRADED_ORDER = 3.0  # the order its grids then grow with (at GRADED_STRETCH 3-3.5; 2.4 at 1)


@dataclass
class _Fit:
    """The accepted combination of levels, its error estimate and the outcome."""

    err: Array
    best: Outputs | None = None
    n_used: int = 0
    status: str = "success"
    message: str = ""


def richardson_weights(mults: tuple[int, ...] | list[int]) -> Array:
    """Weights ``w`` [1] of levels with steps ``h / m`` (``m`` in ``mults``) whose combination
    ``sum w_i R(h / m_i)`` cancels the error terms ``h^2, h^4, ..., h^(2 (len - 1))``.

    They solve ``sum_i w_i = 1``, ``sum_i w_i m_i^(-2 k) = 0`` for ``k = 1 .. len - 1`` (a
    Vandermonde system in ``m^-2``).  For ``(1, 2)``: ``(-1/3, 4/3)``.
    """
    m = np.asarray(mults, dtype=float)
    if m.ndim != 1 or m.size < 1 or np.any(m <= 0) or np.unique(m).size != m.size:
        raise ValueError(f"mults [1] must be distinct positive numbers; got {mults!r}")
    return _weights(tuple(m.tolist())).copy()


def _weights(m_: tuple[float, ...]) -> Array:
    """:func:`richardson_weights` of checked ``m_`` (read-only; memoised with the odd
    control's, :func:`._cn_odd._weights_of`, which solves the same Vandermonde system in
    ``m^-2``: the controller asks for the same few level sets at every solve)."""
    return _weights_of(m_, False)[0]


def _round_grid(n: float) -> int:
    """Even grid size >= 8 (the coarse partner of a pair is n // 2)."""
    return max(8, 2 * int(math.ceil(n / 2.0)))


class _Judge:
    """Error estimates of candidate answers against the tolerance (area and load identity)."""

    def __init__(
        self, pb: Problem, scale: Array, graded: bool = False, stiff: bool = False
    ) -> None:
        self.pb, self.scale = pb, scale
        # the fourth order's estimate factor and the order its grids grow with
        self.e_factor, self.e_order = (E_GRADED, E_GRADED_ORDER) if graded else (2.0 / 15.0, 4.0)
        # steps per node of the second- and fourth-order levels: where the sixth order may follow
        # (and rtol is tight enough for it to pay), its levels' (more if stiff, see DENSE_STIFF)
        self.stiff = stiff
        self.six_dense = DENSE_STIFF if stiff else DENSE
        self.dense = self.six_dense if _sixth_order_fits(pb) and pb.rtol <= S_RTOL else 1

    def tol(self, area: Array) -> Array:
        return self.pb.rtol * np.abs(area) + self.pb.atol

    def ratio(self, a: Outputs, b: Outputs, factor: float) -> tuple[Array, float]:
        """Estimate ``factor |a - b|`` of the area, and the worst estimate / tolerance of the
        area and of the load identity of ``a``."""
        pb = self.pb
        got = judged(_compiled.built("judge"), a, b, self.scale, factor, pb)
        if got is not None:  # (one compiled pass)
            return got
        err = factor * np.abs(a.area - b.area)
        la_ = a.load + a.moment_lower + a.moment_upper
        lb_ = b.load + b.moment_lower + b.moment_upper
        load = float((factor * np.abs(la_ - lb_) / self.scale).max()) / (pb.rtol + pb.atol)
        return err, max(float((err / self.tol(a.area)).max()), load)


def _refine(lv: Any, pb: Problem, aim: float, scale: Array) -> _Fit | None:
    """Second-order pairs, then fourth- or sixth-order Richardson combinations, until the
    estimate fits (None: a budget ended the search, ``lv.stop`` says which)."""
    judge = _Judge(pb, scale, lv.graded, stiff_at_end(lv.pbs, lv.opts.window_k))
    _release(lv, judge)
    if judge.stiff and judge.dense > 1:  # odd powers of the step too (:mod:`._cn_odd`)
        got = odd_rounds(lv, judge, lv.opts.nodes, aim)
        return None if got is None else _Fit(*got)
    n_base, rounds = lv.opts.nodes, 0
    while True:  # mode R
        pair = lv.levels(n_base, (1, 2), judge.dense)
        if pair is None:
            return None
        l1, l2 = pair
        e_r, ratio = judge.ratio(l2, l1, 2.0 / 3.0)  # ~2x error of R(2n)
        if ratio <= 1.0:
            return _Fit(e_r, combine(l2, l1, False), 2 * n_base)
        # after a missed prediction (slower than second order, e.g. kinks of a tabulated
        # wall) grow at least 1.25x, so that the grids keep advancing
        rounds += 1
        grown = _round_grid(n_base * max(math.sqrt(ratio / aim), 1.0 if rounds == 1 else 1.25))
        if grown > R_MAX_REFINE * n_base:
            break
        n_base = grown
    far = math.sqrt(ratio / aim) > R_SKIP
    return _high_order(lv, judge, n_base, aim, far)


RELEASE = 1e-3  # a yield wall that left the window is released where the pilot level's
# plastic area stays below RELEASE x the smallest area tolerance (see _release)


def _release(lv: Any, judge: _Judge) -> None:
    """Release the yield wall from the window once it has left it (``_Plan.release``) where
    its plastic area is negligible: at most ``RELEASE`` x the smallest area tolerance on the
    pilot level (``lv.opts.nodes``, not flagged: the levels start again on the new plans).

    A yield wall stays real once it entered the window, since it carries the plastic area
    it releases.  A hardness growing faster than the diffusion length (``Y ~ zeta^n`` with
    ``tau ~ zeta^(2 - 2H)``: ``Y ~ tau^(n / (2 - 2H))``, 2.8 on "flat H=0.93 5dec" of seed
    7037 of ``benchmarks/plastic_design.py``) then runs far ahead of the support of ``P``
    (there 11x at the last output), and the window's nodes with it: the pilot's error was
    1.7e5 tolerances, the control needed 2.3e7 node-steps, where the wall's plastic area
    never exceeded 5e-13 (a tail the window entered by 0.6 ``sqrt(2 tau)``).  Released, the
    window keeps the support (4.3e5 node-steps) and drops at most that plastic area.

    The plastic area is judged on the released pilot level (where the wall stays real the
    pilot is not accurate enough to measure it: on that scene 1.2e-6 at 24 nodes), whose
    plastic area stops growing where the wall leaves the window: the area the wall would
    have carried on.  Where it is not negligible the plans are made again as before (the
    pilot level is spent).
    """
    pbs, k = lv.pbs, lv.opts.window_k
    pb = pbs[0]
    if pb.upper is None or pb.upper.acts_absorbing or lv.release:
        return
    t = float(pb.tau_max)
    up = float(pb.wall_positions(np.array([t]))[1][0])
    if not all(up > p.p0 + k * math.sqrt(2.0 * t) for p in pbs):
        return  # the wall is inside some window at the end: nothing to release
    lv.release = True
    lv.plans.clear()
    first = lv.level(lv.opts.nodes, 1, judge.dense)
    if first is None:
        return  # (a budget ended the search: lv.stop says which)
    lv.solved.clear()
    if float(np.abs(first.absorbed_upper).max()) > RELEASE * judge.tol(first.area).min():
        lv.release = False  # not negligible: the wall stays real (the plans as before)
        lv.plans.clear()


def _fourth(lv: Any, judge: _Judge, n: int) -> tuple[_Fit, float] | None:
    """The fourth-order triple at ``n`` (answer ``E(2n, 4n)``, estimate ~2x asymptotic, or
    its order-2 bound after a breakpoint: ``judge.e_factor``) and its estimate / tolerance
    (None: a budget ended the search)."""
    triple = lv.levels(n, (1, 2, 4), judge.dense)
    if triple is None:
        return None
    l1, l2, l4 = triple
    got = fourth_of(_compiled.built("fourth"), l4, l2, l1, judge.scale, judge.e_factor, judge.pb)
    if got is not None:  # (one compiled call: the answer, its estimate and ratio)
        return _Fit(got[0], Outputs(*got[1], None), 4 * n), got[2]
    e_b, e_a = combine(l4, l2, True), combine(l2, l1, True)
    err, ratio = judge.ratio(e_b, e_a, judge.e_factor)
    return _Fit(err, e_b, 4 * n), ratio


def _k6(mults: tuple[int, ...]) -> float:
    """``sum w m^-6`` of the sixth-order weights of three levels: ``prod m^-2`` [1]."""
    k = 1.0  # (on floats: numpy's product of m ** -2.0, the same numbers for every m <= 16)
    for m in mults:
        k *= float(m) ** -2.0
    return k


def _sixth(
    lv: Any, judge: _Judge, n: int, top: int = 4, dense: int = 0
) -> tuple[_Fit, float] | None:
    """The sixth-order combinations of the levels ``top - 2 .. top`` (the answer) and
    ``top - 3 .. top - 1`` of grid ``n`` (see the module), and the estimate / tolerance.

    The estimate is ``S_MARGIN`` times the asymptotic error of the answer, ``|S_b - S_a| K_b /
    (K_a - K_b)`` (``K = prod m^-2``: for ``top = 4`` it is ``|S_b - S_a|``).  ``dense``: the
    levels' steps per node (0: ``judge.six_dense``).  None: a budget ended the search.
    """
    ma, mb = tuple(range(top - 3, top)), tuple(range(top - 2, top + 1))
    lvs = lv.levels(n, tuple(range(top - 3, top + 1)), dense or judge.six_dense)
    if lvs is None:
        return None
    s_b = weighted(lvs[1:], _weights(tuple(map(float, mb))))
    s_a = weighted(lvs[:3], _weights(tuple(map(float, ma))))
    ka, kb = _k6(ma), _k6(mb)
    err, ratio = judge.ratio(s_b, s_a, S_MARGIN * kb / (ka - kb))
    return _Fit(err, s_b, top * n), ratio


def _sixth_next(
    top: int, ratio: float, aim: float, dense: float = DENSE
) -> tuple[float, bool, float]:
    """The cheaper way on from a sixth-order estimate / tolerance ``ratio`` at ``top``:
    (work [pilot node-steps per n^2], extend, grid growth).  Extending adds the level
    ``top + 1`` (the asymptotic error falls by ``K(top + 1) / K(top) = ((top - 2) /
    (top + 1))^2``), as often as predicted to reach ``aim`` (at most ``S_LMAX``); a new grid
    (four levels) grows by ``(ratio K(2, 3, 4) / K(top) / aim)^(1 / S_ORDER)``, at least 1.25x.
    ``dense``: steps per node of the levels."""
    # a new grid starts again with levels 2-4, whose constant K is larger than K(top)
    r4 = ratio * _k6((2, 3, 4)) / _k6((top - 2, top - 1, top))
    grow = max((r4 / aim) ** (1.0 / S_ORDER), 1.25)
    new = dense * S_WORK / 2.0 * grow**2  # S_WORK counts the four levels at twice the steps
    work, r, t = 0.0, ratio, top
    while t < S_LMAX:
        t += 1
        work += dense * t**2
        r *= ((t - 3.0) / t) ** 2
        if r <= aim:
            return (work, True, 1.0) if work < new else (new, False, grow)
    return new, False, grow


def _high_order(lv: Any, judge: _Judge, n_base: int, aim: float, far: bool) -> _Fit | None:
    """Fourth-order triples, or sixth-order quadruples where a moving wall makes the fourth
    order's grid large and the sixth order's pilot predicts less work, until the estimate
    fits (see the module).  ``far``: the second-order pilot asked for a grid so fine that the
    sixth order's pilot comes first (the fourth order's is solved only if it is needed).
    None: a budget ended the search (``lv.stop`` says which)."""
    six = _sixth_order_fits(judge.pb)
    sixth = None
    if six and far:
        sixth = _sixth(lv, judge, n_base)
        if sixth is None or sixth[1] <= 1.0:
            return None if sixth is None else sixth[0]
        near = E_WORK * judge.dense * S_GROW**2
        if _sixth_next(4, sixth[1], aim, judge.six_dense)[0] <= near:  # the sixth order is near
            s_fit = _sixth_rounds(lv, judge, n_base, sixth[1], aim)
            if s_fit is not None or lv.stop is not None:
                return s_fit
            six = False
    fourth = _fourth(lv, judge, n_base)
    if fourth is None:
        return None
    grow = (fourth[1] / aim) ** (1.0 / judge.e_order)
    if S_FIRST and fourth[1] > 1.0 and six and sixth is None:
        # the triple's levels are the quadruple's but one (mult 3: 9 of the triple's 21 units),
        # cheaper than any new round (>= 21 x 1.25^2): the sixth order first (a trial if at
        # steps per node other than its own)
        first = _sixth(lv, judge, n_base, dense=judge.dense)
        if first is None or first[1] <= 1.0:
            return None if first is None else first[0]
        sixth = first if judge.dense == judge.six_dense else None
    if fourth[1] > 1.0 and grow > S_GROW and six:
        if sixth is None:
            sixth = _sixth(lv, judge, n_base)
            if sixth is None or sixth[1] <= 1.0:
                return None if sixth is None else sixth[0]
        # the work of the next round, the sixth order's at least S_FAVOR x less (it may miss)
        s_work = _sixth_next(4, sixth[1], aim, judge.six_dense)[0]
        if S_FAVOR * s_work < E_WORK * judge.dense * grow**2:
            s_fit = _sixth_rounds(lv, judge, n_base, sixth[1], aim)
            if s_fit is not None or lv.stop is not None:
                return s_fit
    return _fourth_rounds(lv, judge, n_base, fourth, aim)


def _fourth_rounds(
    lv: Any, judge: _Judge, n_base: int, fourth: tuple[_Fit, float], aim: float
) -> _Fit | None:
    """Fourth-order triples on grids grown from ``n_base`` (whose triple gave ``fourth``)
    until the estimate fits (None: a budget ended the search)."""
    fit, ratio = fourth
    grow = (ratio / aim) ** (1.0 / judge.e_order)
    rounds = 0
    while ratio > 1.0:
        rounds += 1
        n_base = _round_grid(n_base * max(grow, 1.0 if rounds == 1 else 1.25))
        nxt = _fourth(lv, judge, n_base)
        if nxt is None:
            return None
        fit, ratio = nxt
        grow = (ratio / aim) ** (1.0 / judge.e_order)
    return fit


def _sixth_rounds(lv: Any, judge: _Judge, n: int, ratio: float, aim: float) -> _Fit | None:
    """Sixth-order rounds after the quadruple at ``n`` (estimate / tolerance ``ratio``): the
    next level of the same grid, or a new grid, whichever :func:`_sixth_next` finds
    cheaper, until the estimate fits; None (back to the fourth order) when a round misses
    its prediction by more than ``S_MISS`` (the error is not in its sixth-order regime; a
    moving yield wall's first miss: the quadruple of the grid at ``DENSE_STIFF`` steps per
    node first, see :func:`_denser`), or when a budget ended the search (``lv.stop`` set)."""
    top = 4
    while True:
        _, extend, grow = _sixth_next(top, ratio, aim, judge.six_dense)
        if extend:
            top += 1
            predicted = ratio * ((top - 3.0) / top) ** 2
        else:
            k_ratio = _k6((2, 3, 4)) / _k6((top - 2, top - 1, top))
            n, top, predicted = _round_grid(n * grow), 4, ratio * k_ratio / grow**S_ORDER
        sixth = _sixth(lv, judge, n, top)
        if sixth is None:
            return None
        fit, ratio = sixth
        if ratio <= 1.0:
            return fit
        if ratio > S_MISS * max(predicted, aim):
            if not _denser(judge):
                return None
            sixth = _sixth(lv, judge, n)  # the quadruple of this grid at DENSE_STIFF
            if sixth is None or sixth[1] <= 1.0:
                return None if sixth is None else sixth[0]
            ratio, top = sixth[1], 4


def _denser(judge: _Judge) -> bool:
    """Whether a missed sixth-order round goes on at ``DENSE_STIFF`` steps per node (a moving
    yield wall at fewer: then ``judge`` takes them).  Decided by the miss: the scenes the
    sixth order answers at ``DENSE`` pay nothing (``DENSE_STIFF`` for every yield wall cost
    1.6-1.9x on 17 of 38 such scenes of seeds 7036-7041 of ``benchmarks/plastic_design.py``)."""
    up = judge.pb.upper
    if up is None or up.acts_absorbing or judge.six_dense >= DENSE_STIFF:
        return False
    judge.six_dense = DENSE_STIFF
    return True


def _sixth_order_fits(pb: Problem) -> bool:
    """Whether the sixth-order mode may be used for ``pb``: a wall moves (on fixed walls the
    fourth order keeps the error aimed at the request: the sixth order's estimate is
    conservative), no wall declares breakpoints (the graded steps after them give a clean
    second-order expansion only) and no density is wanted (it is interpolated on the nodes,
    whose spacing the sixth-order levels do not refine as far)."""
    lo, up = pb.lower, pb.upper
    if pb.p_out is not None or (lo is not None and lo.breakpoints):
        return False
    if up is not None and up.breakpoints:
        return False
    return (lo is not None and not lo.is_fixed) or (up is not None and not up.is_fixed)


def _control(lv: Any, pb: Problem, aim: float, tau_num: Array, lo_at: Array | None = None) -> _Fit:
    """Levels until the error estimate meets the tolerance (or a budget ends the search).

    ``lv``: the grid levels (``_cn._Grids``: ``levels(n_base, mults, dense)``, ``solved``,
    ``stop``, ``opts``, ``pbs``); ``lo_at``: the lower wall at ``tau_num`` [Pa] if known.
    """
    scale = load_scale(lv.pbs, tau_num, lo_at, _compiled.built("scale"))
    fit = _refine(lv, pb, aim, scale)
    if fit is None:  # a budget ended the search: the finest solved pair, flagged
        status, message = lv.stop
        fit = _Fit(np.full((len(lv.pbs), tau_num.size), np.inf), None, 0, status, message)
    if fit.best is None and lv.solved:
        _finest_pair(lv.solved, fit)
    # a probability projected onto [0, 1] is off by at most 1: no estimate (a single
    # level) is reported as 1, never as inf; round-off of the sums over the grid (the level
    # difference cannot see it) added (``c |area|``)
    c = 16.0 * _EPS * math.sqrt(max(fit.n_used, 1))
    fast = _compiled.built("fitted") if fit.best is not None and fit.status == "success" else None
    tols = (pb.rtol, pb.atol, EST_FLOOR)
    got = None if fast is None else fitted_of(fast, fit.err, fit.best.area, c, *tols)
    if got is not None:  # (the steps below in one compiled pass)
        fit.err = got
        return fit
    fit.err = np.minimum(fit.err, 1.0)
    if fit.best is None:
        return fit
    a = np.abs(fit.best.area)
    fit.err = fit.err + c * a
    tol = pb.rtol * a + pb.atol
    if fit.status == "success" and np.count_nonzero(fit.err > tol):
        fit.status = "tolerance_not_met"
    if fit.status == "success":
        # reported as a uniform fraction of the tolerance per load, the largest estimated:
        # a difference of levels crosses zero where the actual error need not; at least
        # EST_FLOOR (the error the level differences cannot see)
        fit.err = tol * np.maximum((fit.err / tol).max(axis=-1, keepdims=True), EST_FLOOR)
    if fit.status != "success":
        i = np.unravel_index(int(np.argmax(fit.err / tol)), fit.err.shape)
        fit.message = (fit.message + "; " if fit.message else "") + (
            f"the error estimate {fit.err[i]:.2e} exceeds the tolerance at tau = "
            f"{tau_num[i[1]]:.6g} Pa^2"
        )
    return fit
