"""The compiled path's kernels of a ``cn`` solve's outputs after the march, each the numpy
path's operations element by element (bit for bit; the numpy path stays where numba is off or
missing): the error control's estimate and worst ratio (:func:`judge_ratio`), its load
identity's scale (:func:`load_scale`, :func:`scale_kernel`) and the reported estimate of a
successful fit (:func:`fitted_error`), the Richardson combinations of levels
(:func:`combine_fields`, :func:`weighted_fields`; :func:`fourth_ratio` a fourth-order triple's
answer and estimate), a solve's assembled fields (:func:`assembled`: the analytic start, the
projection onto admissible probabilities and the raised estimate in one pass) and a batch's
balances and the screen's reductions (:func:`batch_balances`); the projection alone
(:func:`._level.project`) is numpy's (compiled, it saved less than the timing noise:
``benchmarks/ablation.py``). Where numpy's result would depend on more than the
operations (the sign and payload of a NaN follow the operands' order, which the compiler may
swap; numpy's ``clip``/``maximum`` of ``-0``), a kernel declines and the numpy path answers.
Built by :func:`._compiled._build`. Units: tau in Pa^2, pressures in Pa.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ._problem import Problem

__all__ = [
    "EST_FLOOR",
    "assembled",
    "batch_balances",
    "batch_balances_of",
    "combine_fields",
    "fitted_error",
    "fitted_of",
    "fourth_of",
    "fourth_ratio",
    "judge_ratio",
    "judged",
    "load_scale",
    "scale_kernel",
    "weighted_fields",
]

Array = NDArray[np.float64]

EST_FLOOR = 0.01  # the reported estimate of an accepted ``cn`` fit is at least EST_FLOOR x
# its tolerance (:func:`._cn_control._control`): the level differences do not see the error
# of an unresolved far tail, a wall absorbing a ~1e-9 .. 1e-7 tail of P near full contact on
# grids of 48-96 intervals that all miss most of it, so no factor on them bounds it (``jkr``,
# rtol 1e-3: seed 1313 "roll H=0.51 5dec" of benchmarks/summary_design.held_out, levels 24
# and 48 both lost 2.1-2.3e-10 of the reference's 2.6e-9; seed 2026 "roll H=0.68 4dec",
# 1.2e-9 and 2.8e-8 of 5.9e-8).  Where they missed, the actual error was at most 2.2e-3
# tolerances (seed 2026 "roll H=0.41 5dec", rtol 1e-6; 3e-6 .. 7e-4 on the others of
# benchmarks/rtol_monotone.py and seed 1313).  Below the tolerance: no decision of the
# control and no status changes.


def judge_ratio(  # noqa: PLR0913 - the two answers' fields
    a_area: Any,
    b_area: Any,
    a_load: Any,
    a_ml: Any,
    a_mu: Any,
    b_load: Any,
    b_ml: Any,
    b_mu: Any,
    scale: Any,
    factor: float,
    rtol: float,
    atol: float,
) -> tuple:  # pragma: no cover - compiled (the numpy path is the reference)
    """:meth:`._cn_control._Judge.ratio`'s numbers in one pass (loads, outputs): the estimate
    ``factor |a - b|`` of the area, the largest estimate / tolerance of the area and the
    largest ``factor |load identity a - b| / scale`` [1] (NaN where any is NaN, as numpy's
    ``max``), the same operations element by element."""
    nb, n_out = a_area.shape
    err = np.empty((nb, n_out))
    m_area, m_load = -math.inf, -math.inf
    for q in range(nb):
        for j in range(n_out):
            e = factor * abs(a_area[q, j] - b_area[q, j])
            err[q, j] = e
            r = e / (rtol * abs(a_area[q, j]) + atol)
            la = a_load[q, j] + a_ml[q, j] + a_mu[q, j]
            lb = b_load[q, j] + b_ml[q, j] + b_mu[q, j]
            g = factor * abs(la - lb) / scale[q, j]
            if not r <= m_area:  # (a larger value, or NaN: NaN stays)
                m_area = r if m_area == m_area else m_area
            if not g <= m_load:
                m_load = g if m_load == m_load else m_load
    return err, m_area, m_load


def judged(
    fast: Callable[..., tuple] | None, a: Any, b: Any, scale: Array, factor: float, pb: Problem
) -> tuple[Array, float] | None:
    """:meth:`._cn_control._Judge.ratio` of the answers ``a``, ``b`` (``Outputs``) by
    ``fast`` (:func:`judge_ratio`, compiled), or None where it does not apply (no kernel, or
    fields not shaped as ``scale``: the numpy path answers)."""
    if fast is None or a.area.ndim != 2 or a.area.shape != scale.shape:
        return None
    err, m_area, m_load = fast(a.area, b.area, a.load, a.moment_lower, a.moment_upper, b.load,
                               b.moment_lower, b.moment_upper, scale, factor, pb.rtol,
                               pb.atol)  # fmt: skip
    return err, max(float(m_area), float(m_load) / (pb.rtol + pb.atol))


def fourth_of(  # noqa: PLR0913 - the three levels and the judge's numbers
    fast: Callable[..., tuple] | None,
    fine: Any,
    mid: Any,
    coarse: Any,
    scale: Array,
    factor: float,
    pb: Problem,
) -> tuple[Array, Array, float] | None:
    """:func:`._cn_control._fourth`'s estimate, answer ``E(fine, mid)`` (6, loads, outputs)
    and worst estimate / tolerance of the levels ``fine``, ``mid``, ``coarse`` (``Outputs``)
    by ``fast`` (:func:`fourth_ratio`, compiled), or None where it does not apply or declines
    (the numpy path answers)."""
    if fast is None or fine.P is not None or fine.area.ndim != 2 or fine.area.shape != scale.shape:
        return None
    out = np.empty((6, *fine.area.shape))
    ok, err, m_area, m_load = fast(*fine[:6], *mid[:6], *coarse[:6], out, scale, factor,
                                   pb.rtol, pb.atol)  # fmt: skip
    if not ok:
        return None
    return err, out, max(float(m_area), float(m_load) / (pb.rtol + pb.atol))


def fitted_error(  # noqa: PLR0913 - the fit's numbers
    err: Any, area: Any, c: float, rtol: float, atol: float, floor: float, out: Any
) -> bool:  # pragma: no cover - compiled (the numpy path is the reference)
    """The reported estimate of a successful fit (:func:`._cn_control._control`'s numpy
    operations element by element) into ``out`` (loads, outputs): ``e = min(err, 1) + c
    |area|``, ``tol = rtol |area| + atol``, then ``tol`` times the larger of the row's largest
    ``e / tol`` and ``floor`` [1]; False (``out`` partly written) where a value is not finite
    or some ``e`` exceeds its ``tol`` (the fit then fails: numpy reports it)."""
    nb, n_out = err.shape
    for q in range(nb):
        m = -math.inf
        for j in range(n_out):
            e0, a = err[q, j], abs(area[q, j])
            if not (abs(e0) < math.inf and a < math.inf):
                return False
            e = (e0 if e0 < 1.0 else 1.0) + c * a
            tol = rtol * a + atol
            if e > tol:
                return False
            r = e / tol
            m = r if r > m else m
            out[q, j] = tol
        m = m if m > floor else floor  # (numpy's maximum: m is finite here)
        for j in range(n_out):
            out[q, j] = out[q, j] * m
    return True


def fitted_of(  # noqa: PLR0913 - the fit's numbers
    fast: Callable[..., bool],
    err: Any,
    area: Any,
    c: float,
    rtol: float,
    atol: float,
    floor: float,
) -> Array | None:
    """:func:`fitted_error` by ``fast`` (compiled) of a successful fit's estimate ``err`` and
    answer ``area`` (loads, outputs), at least ``floor`` [1] x the tolerance: the reported
    estimate, or None where it declines (or the shapes differ: the numpy steps answer)."""
    if err.ndim != 2 or area.shape != err.shape:
        return None
    out = np.empty(err.shape)
    return out if fast(err, area, c, rtol, atol, floor, out) else None


def load_scale(
    pbs: list[Problem], tau: Array, lo_at: Array | None = None, fast: Callable | None = None
) -> Array:
    """The load identity's scale per (load, output) of the error control: ``max(|p0|, |lower
    wall|)`` [Pa] at the times ``tau`` [Pa^2] (``lo_at``: the lower wall there, known);
    ``fast``: :func:`scale_kernel` (compiled; the same numbers).

    The upper wall's position is not in it: the identity's terms stay of the order of
    ``|p0| + |lower wall|`` wherever that wall sits (its own term, ``Y A_pl`` or the moment it
    absorbed, is at most that), and that term is what bounds the plastic area. Scaled by a
    far yield wall (``Y/p0`` up to 1e7), the plastic area and the load shares went
    uncontrolled relative to ``p0``: ``benchmarks/fuzz.py --seed 83`` found a force balance
    off by 1.4e-3 of ``p0`` reported as a success (``Y/p0 = 1.9e7``; its cause, a start too
    late, is fixed in :func:`._cn_plan._start_time`, and this scale alone had it flagged,
    ``tests/engine/test_load_scale.py``); on the speed design's plastic scenes at
    ``p0/Y ~ 1e-6`` the error control now refines to a force balance of ~3e-8 (was ~3e-7).
    """
    pb = pbs[0]
    if any(p.lower is not pb.lower or p.upper is not pb.upper for p in pbs[1:]):
        return np.concatenate([load_scale([p], tau) for p in pbs])
    # the loads of a batch share their walls: evaluated once (the same numbers per load)
    lo = pb.lower.at(tau) if lo_at is None else lo_at
    p0 = np.array([[p.p0] for p in pbs], dtype=float)
    if fast is not None and lo.ndim == 1:
        out = np.empty((p0.shape[0], lo.shape[0]))
        if fast(p0, lo, out):
            return out
    sc = np.maximum(np.abs(p0), np.abs(lo))
    return sc if np.count_nonzero(sc > 0) == sc.size else np.where(sc > 0, sc, 1.0)


def scale_kernel(p0: Any, lo: Any, out: Any) -> bool:  # pragma: no cover - compiled
    """:func:`load_scale`: ``max(|p0|, |lo|)`` (loads, outputs) [Pa] of
    the loads ``p0`` (loads, 1) and the lower wall ``lo`` (outputs,) into ``out``; False where
    a value is NaN or a scale not positive (numpy's ``maximum`` and ``where`` decide)."""
    for q in range(p0.shape[0]):
        a = abs(p0[q, 0])
        if a != a:
            return False
        for j in range(lo.shape[0]):
            b = abs(lo[j])
            v = a if a >= b else b
            if not v > 0.0:
                return False
            out[q, j] = v
    return True


_UNSURE = np.full((1, 1), np.nan)  # a non-area the compiled screen leaves to numpy's sum


def batch_balances_of(fast: Callable[..., tuple], problem: Problem, raw: Any, lo: Array) -> tuple:
    """:func:`._result._balances` and the screen's reductions of :func:`._result.finish_batch`
    for a batch ``raw`` of ``problem`` without an upper wall (``lo``: the lower wall's
    positions [Pa], as ``Problem.output_positions`` gives them) by ``fast``
    (:func:`batch_balances`, compiled): ``(prob, loadb, reductions)``."""
    shape = raw.area.shape
    lo2 = lo.reshape(-1, shape[-1]) if lo.ndim else np.full((1, shape[-1]), lo)
    # (the arrays it fills made here: a compiled function's returned arrays cost ~0.6 us each)
    prob, loadb, red = np.empty(shape), np.empty(shape), np.empty(6)
    na = raw.non_area if np.ndim(raw.non_area) == 2 else _UNSURE
    fast(raw.area, raw.absorbed_lower, raw.absorbed_upper, raw.load, raw.wall_term,
         raw.error_estimate, problem.p0, lo2, problem.rtol, na, prob, loadb, red)  # fmt: skip
    return prob, loadb, red


def _nan_max(m: float, v: float) -> float:  # pragma: no cover - compiled
    """The running ``max`` of numpy (NaN once any value is NaN)."""
    if m != m or v != v:
        return math.nan if v != v or m != m else m
    return v if v > m else m


def batch_balances(  # noqa: PLR0913 - the batch's fields
    area: Any,
    abs_l: Any,
    abs_u: Any,
    load: Any,
    wall_term: Any,
    error: Any,
    p0: Any,
    lo: Any,
    rtol: float,
    non_area: Any,
    prob: Any,
    loadb: Any,
    red: Any,
) -> None:  # pragma: no cover - compiled (the numpy path is the reference)
    """:func:`._result._balances` of a batch without an upper wall (``lo`` the lower wall's
    positions (1 or loads, outputs) [Pa], ``p0`` (loads, 1) [Pa]) and the screen's reductions
    of :func:`._result.finish_batch` in one pass, into ``prob``, ``loadb`` (loads, outputs)
    and ``red`` = ``[max prob, -min prob, max loadb, -min loadb, max (error - rtol |area|),
    sure]`` (numpy's NaN-propagating ``max``/``min``), the same operations element by element;
    ``sure`` is 1 where the sum of ``non_area`` is finite in any order (every value finite and
    below ``1e300 / size``), else 0 (then numpy's sum decides)."""
    nb, n = area.shape
    red[:] = -math.inf
    bound = 1e300 / max(non_area.size, 1)
    red[5] = 1.0
    for q in range(non_area.shape[0]):
        for j in range(non_area.shape[1]):
            if not abs(non_area[q, j]) <= bound:
                red[5] = 0.0
    for q in range(nb):
        p = p0[q, 0]
        a = abs(p)
        for j in range(n):
            v = area[q, j] + abs_l[q, j]
            v = v + abs_u[q, j]
            v = v - 1.0
            prob[q, j] = v
            b = abs(lo[q if lo.shape[0] > 1 else 0, j])
            sc = a if a != a else (b if b != b else (b if b > a else a))
            sc = sc if sc > 0 else 1.0
            g = load[q, j] + wall_term[q, j]
            g = g - p
            g = g / sc
            loadb[q, j] = g
            red[0] = _nan_max(red[0], v)
            red[1] = _nan_max(red[1], -v)
            red[2] = _nan_max(red[2], g)
            red[3] = _nan_max(red[3], -g)
            slack = abs(area[q, j]) * -rtol
            red[4] = _nan_max(red[4], slack + error[q, j])


def _same_shape(a: Any, b: Any, c: Any, d: Any, shape: Any) -> bool:  # pragma: no cover
    """Whether ``a .. d`` are all shaped ``shape`` (compiled)."""
    return a.shape == shape and b.shape == shape and c.shape == shape and d.shape == shape


def _combined(a: Any, b: Any, o: Any) -> bool:  # pragma: no cover - compiled
    """``a + (a - b) / 3`` element by element into ``o`` (:func:`._level.combine`'s numpy
    operations: ``d = a - b``, ``d /= 3``, ``a + d``); whether no value is NaN (a NaN's sign
    and payload depend on the operands' order, which the compiler may swap: numpy decides)."""
    for q in range(a.shape[0]):
        for j in range(a.shape[1]):
            d = a[q, j] - b[q, j]
            d = d / 3.0
            v = a[q, j] + d
            if v != v:
                return False
            o[q, j] = v
    return True


def combine_fields(  # noqa: PLR0913 - the two levels' six fields
    a0: Any, a1: Any, a2: Any, a3: Any, a4: Any, a5: Any,
    b0: Any, b1: Any, b2: Any, b3: Any, b4: Any, b5: Any,
    out: Any,
) -> bool:  # fmt: skip  # pragma: no cover - compiled (the numpy path is the reference)
    """:func:`._level.combine`'s Richardson step of the six (loads, outputs) fields ``a``
    (finer) and ``b`` (coarser) into ``out`` (6, loads, outputs); False (the numpy path
    answers) where a field is not shaped as ``out[0]`` or a value is NaN."""
    s = out[0].shape
    if not (_same_shape(a0, a1, a2, a3, s) and _same_shape(a4, a5, b0, b1, s)
            and _same_shape(b2, b3, b4, b5, s)):  # fmt: skip
        return False
    return (_combined(a0, b0, out[0]) and _combined(a1, b1, out[1])
            and _combined(a2, b2, out[2]) and _combined(a3, b3, out[3])
            and _combined(a4, b4, out[4]) and _combined(a5, b5, out[5]))  # fmt: skip


def fourth_ratio(  # noqa: PLR0913 - the three levels' six fields and the judge's numbers
    a0: Any, a1: Any, a2: Any, a3: Any, a4: Any, a5: Any,
    b0: Any, b1: Any, b2: Any, b3: Any, b4: Any, b5: Any,
    c0: Any, c1: Any, c2: Any, c3: Any, c4: Any, c5: Any,
    out: Any, scale: Any, factor: float, rtol: float, atol: float,
) -> tuple:  # fmt: skip  # pragma: no cover - compiled (the numpy path is the reference)
    """:func:`._cn_control._fourth`'s numbers in one call: the answer ``E(a, b)`` of the
    finest levels ``a``, ``b`` (:func:`combine_fields` into ``out``) and
    :func:`judge_ratio` of it against ``E(b, c)``, of which only the area and the load
    identity's three fields are made (the estimate reads no others); ``(ok, err, m_area,
    m_load)``, ok False (the numpy path answers) where :func:`combine_fields` declines or a
    read field of ``E(b, c)`` is not shaped as ``out[0]`` or is NaN."""
    s = out[0].shape
    if not (combine_fields(a0, a1, a2, a3, a4, a5, b0, b1, b2, b3, b4, b5, out)
            and _same_shape(c0, c3, c4, c5, s)):  # fmt: skip
        return False, np.empty((0, 0)), math.nan, math.nan
    ea = np.empty((4, s[0], s[1]))
    if not (_combined(b0, c0, ea[0]) and _combined(b3, c3, ea[1])
            and _combined(b4, c4, ea[2]) and _combined(b5, c5, ea[3])):  # fmt: skip
        return False, np.empty((0, 0)), math.nan, math.nan
    err, m_area, m_load = judge_ratio(out[0], ea[0], out[3], out[4], out[5], ea[1], ea[2],
                                      ea[3], scale, factor, rtol, atol)  # fmt: skip
    return True, err, m_area, m_load


def _summed(ws: Any, a: Any, b: Any, c: Any, o: Any) -> bool:  # pragma: no cover - compiled
    """``0 + ws[0] a + ws[1] b + ws[2] c`` element by element into ``o`` (:func:`._level.
    _weighted`'s numpy operations: ``a * w_0``, ``+= 0``, then ``+= (v * w_i)``); whether no
    value is NaN (see :func:`_combined`)."""
    for q in range(a.shape[0]):
        for j in range(a.shape[1]):
            acc = a[q, j] * ws[0]
            acc = acc + 0.0
            acc = acc + b[q, j] * ws[1]
            v = acc + c[q, j] * ws[2]
            if v != v:
                return False
            o[q, j] = v
    return True


def weighted_fields(  # noqa: PLR0913 - the three levels' six fields
    ws: Any,
    a0: Any, a1: Any, a2: Any, a3: Any, a4: Any, a5: Any,
    b0: Any, b1: Any, b2: Any, b3: Any, b4: Any, b5: Any,
    c0: Any, c1: Any, c2: Any, c3: Any, c4: Any, c5: Any,
    out: Any,
) -> bool:  # fmt: skip  # pragma: no cover - compiled (the numpy path is the reference)
    """:func:`._level.weighted` of three levels' six (loads, outputs) fields ``a``, ``b``,
    ``c`` with the weights ``ws`` (3,) into ``out`` (6, loads, outputs); False (the numpy
    path answers) where a field is not shaped as ``out[0]`` or a value is NaN."""
    s = out[0].shape
    if not (_same_shape(a0, a1, a2, a3, s) and _same_shape(a4, a5, b0, b1, s)
            and _same_shape(b2, b3, b4, b5, s) and _same_shape(c0, c1, c2, c3, s)
            and _same_shape(c4, c5, c0, c0, s)):  # fmt: skip
        return False
    return (_summed(ws, a0, b0, c0, out[0]) and _summed(ws, a1, b1, c1, out[1])
            and _summed(ws, a2, b2, c2, out[2]) and _summed(ws, a3, b3, c3, out[3])
            and _summed(ws, a4, b4, c4, out[4]) and _summed(ws, a5, b5, c5, out[5]))  # fmt: skip


def _plain(v: float) -> bool:  # pragma: no cover - compiled
    """Whether ``v`` is neither NaN nor -0 (where numpy's ``clip``/``maximum`` loops may
    differ in the sign or payload they return)."""
    return v == v and not (v == 0.0 and math.copysign(1.0, v) < 0.0)


def assembled(  # noqa: PLR0913 - the fit's fields and the analytic start's numbers
    area: Any,
    abs_l: Any,
    abs_u: Any,
    load: Any,
    m_lo: Any,
    m_up: Any,
    err: Any,
    p0: Any,
    tau: Any,
    trunc: float,
    bound_off: float,
    check: bool,
    rtol: float,
    atol: float,
    out: Any,
) -> bool:  # pragma: no cover - compiled (the numpy path is the reference)
    """:func:`._cn._assemble`'s fields without a one-wall start, into ``out`` (7, loads,
    outputs): area, absorbed lower and upper, load [Pa], wall term [Pa], error estimate and
    non-area; the first ``n_a = outputs - area.shape[1]`` outputs (times ``tau`` [Pa^2]) the
    analytic start's (loads ``p0`` [Pa]; estimate ``trunc`` where ``tau > 0``, raised to
    ``EST_FLOOR`` x its tolerance ``rtol |1| + atol``: :func:`._cn_assemble._start_floor`'s
    ``maximum``, of finite numbers), the rest the
    fit's (loads, marched outputs) fields projected (:func:`._level.project`) and the estimate
    ``max(err, |area moved|) + trunc``. False (``out`` partly written) where a value is NaN or
    -0 or a sum of the absorbed fractions exceeds 1, ``err`` is NaN, or (``check``) a distance
    moved exceeds ``err + trunc + bound_off``: the numpy path answers (and reports it)."""
    nb, n_m = area.shape
    n_t = out.shape[2]
    n_a = n_t - n_m
    floor = EST_FLOOR * (rtol * 1.0 + atol)  # (the start's area is 1)
    start = trunc if trunc >= floor else floor
    for q in range(nb):
        for j in range(n_a):
            out[0, q, j], out[1, q, j], out[2, q, j] = 1.0, 0.0, 0.0
            out[3, q, j], out[4, q, j], out[6, q, j] = p0[q], 0.0, 0.0
            out[5, q, j] = start if tau[j] > 0 else 0.0
        for m in range(n_m):
            a0, l0, u0, e = area[q, m], abs_l[q, m], abs_u[q, m], err[q, m]
            if not (_plain(a0) and _plain(l0) and _plain(u0)) or e != e:
                return False
            a = a0 if a0 > 0.0 else 0.0  # (numpy's clip, then maximum: as _level.project)
            a = a if a < 1.0 else 1.0
            lo = l0 if l0 >= 0.0 else 0.0
            up = u0 if u0 >= 0.0 else 0.0
            total = lo + up
            if not total <= 1.0:
                return False
            d = abs(a - a0)
            if check:
                bound = e + trunc
                bound = bound + bound_off
                if d > bound or abs(lo - l0) > bound or abs(up - u0) > bound:
                    return False
                if abs(total - (l0 + u0)) > bound:
                    return False
            j = n_a + m
            out[0, q, j], out[1, q, j], out[2, q, j], out[3, q, j] = a, lo, up, load[q, m]
            out[4, q, j] = m_lo[q, m] + m_up[q, m]
            e = e if e >= d else d  # (numpy's maximum, NaN excluded above)
            out[5, q, j] = e + trunc
            out[6, q, j] = total
    return True
