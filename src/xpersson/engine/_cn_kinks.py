"""The kinks of the window edges of the ``cn`` method: the times where a real wall enters or
leaves the window ``p0 -/+ k sqrt(2 tau)``, found by a bracketed root-finder (all brackets at
once, or, for a few, each on Python floats: the same operations, the same roots).  See
:mod:`._cn` for the scheme.  Units: tau in Pa^2, pressures in Pa."""

from __future__ import annotations

import bisect
import math

import numpy as np
from numpy.typing import NDArray

from ._grid import decades
from ._problem import Problem
from ._wall_table import kernels
from ._walls import Wall

__all__ = ["KINK_GAP", "_bracketed_roots", "_switch_times_batch", "kinks_apart"]

Array = NDArray[np.float64]


def _switch_times_batch(pbs: list[Problem], k: float, t_lo: float, t_hi: float) -> list[float]:
    """Times where a real wall enters/leaves the window (kinks of the window edges) for every
    load of a batch (they share their walls): the edge gaps sampled at 513 log-spaced times,
    every sign change then polished to ``1e-15 tau`` by one vectorised bracketed root-finder
    over all loads and walls (:func:`_bracketed_roots`); a wall with a table by one compiled
    call (:func:`._wall_table.edge_roots`, the same roots)."""
    if not t_hi > t_lo:
        return []
    cand = t_lo * decades(math.log10(t_hi / t_lo), 513)
    pb = pbs[0]
    p0 = np.array([p.p0 for p in pbs])
    if pb.upper is None and _tabled(pb.lower):  # (the common case: one compiled call)
        fns = kernels()
        if fns is not None:
            roots = np.empty(p0.size * (cand.size - 1))
            found = fns[1](*pb.lower.table.args(), cand, p0, -k, roots)
            return roots[:found].tolist()
    fns = kernels() if _tabled(pb.lower) or _tabled(pb.upper) else None
    s = None if fns is not None and _tabled(pb.lower) and pb.upper is None else np.sqrt(2.0 * cand)
    out: list[float] = []
    for wall, sign in ((pb.lower, -1.0), (pb.upper, 1.0)):
        if wall is None:
            continue
        if fns is not None and _tabled(wall):  # the table's compiled kinks: the same roots
            roots = np.empty(p0.size * (cand.size - 1))
            found = fns[1](*wall.table.args(), cand, p0, sign * k, roots)
            out.extend(roots[:found].tolist())
            continue
        pos = wall.at(cand)
        g = pos[None, :] - (p0[:, None] + sign * k * s[None, :])
        sg = np.sign(g)
        il, ic = np.nonzero(sg[:, :-1] != sg[:, 1:])
        if il.size == 0:
            continue
        pp = p0[il]

        def gap(t: Array, idx: Array, wall=wall, sign=sign, pp=pp) -> Array:
            return wall.at(t) - (pp[idx] + sign * k * np.sqrt(2.0 * t))

        def gap_one(t: float, i: int, wall=wall, sign=sign, pp=pp) -> float:
            # (gap of one time on floats: the same operations, IEEE sqrt both)
            edge = float(pp[i]) + sign * k * math.sqrt(2.0 * t)
            return float(wall.at(np.array([t]))[0]) - edge

        b = cand[ic + 1]
        fa, fb = g[il, ic], g[il, ic + 1]
        roots = _bracketed_roots(gap, cand[ic], b, fa, fb, 1e-15 * b, gap_one)
        out.extend(float(t) for t in roots[np.isfinite(roots)])
    return out


#: Relative gap [1] within which a kink merges into an output time or a smaller kink. Loads
#: that differ in their last bits (two loads 1 ulp apart in one batch) have kinks a few ulps
#: apart: a base interval that short splits, at a level's subdivision, into steps of zero
#: length, whose chord speeds are 0/0 (NaN areas, "balance_violated"). 1e-11 tau leaves an
#: interval >= 45000 ulps; the kink moved by it shifts one step's edge by ~1e-11 of the
#: wall's position there (below the smallest rtol, 1e-12, over the step's share of the run).
KINK_GAP = 1e-11


def kinks_apart(kinks: list[float], outs: Array) -> list[float]:
    """``kinks`` [Pa^2] without those within :data:`KINK_GAP` (relative) of an output time of
    ``outs`` (sorted) or of a smaller kept kink; ``kinks`` itself where none is (the same
    list: the plan's base, which sorts and merges equal times, is then the same)."""
    if len(kinks) <= _FEW_KINKS:
        return _kinks_apart_few(kinks, outs)
    return _kinks_apart_array(kinks, outs)


def _kinks_apart_array(kinks: list[float], outs: Array) -> list[float]:
    """:func:`kinks_apart` on arrays (many ``kinks``)."""
    t = np.sort(np.asarray(kinks, dtype=float))
    if t.size == 0:
        return kinks
    gap = KINK_GAP * np.abs(t)
    near = np.zeros(t.size, dtype=bool)
    if outs.size:
        j = np.searchsorted(outs, t)
        near |= np.abs(t - outs[np.maximum(j - 1, 0)]) <= gap
        near |= np.abs(outs[np.minimum(j, outs.size - 1)] - t) <= gap
    if not near.any() and bool(np.all(np.diff(t) > gap[1:])):
        return kinks
    kept: list[float] = []
    for tk, g, n in zip(t.tolist(), gap.tolist(), near.tolist(), strict=True):
        if not n and (not kept or tk - kept[-1] > g):
            kept.append(tk)
    return kept


#: Up to this many kinks, :func:`kinks_apart` runs on floats (numpy's calls on arrays this
#: short cost ~60 us a solve; the same comparisons on the same doubles: the same list).
_FEW_KINKS = 32


def _kinks_apart_few(kinks: list[float], outs: Array) -> list[float]:
    """:func:`kinks_apart` on floats: a few ``kinks``, the same results."""
    if not kinks:
        return kinks
    t = sorted(float(x) for x in kinks)
    gap = [KINK_GAP * abs(x) for x in t]
    o = outs.tolist()
    near = [False] * len(t)
    if o:
        last = len(o) - 1
        for i, x in enumerate(t):
            j = bisect.bisect_left(o, x)  # (np.searchsorted's side="left")
            near[i] = abs(x - o[max(j - 1, 0)]) <= gap[i] or abs(o[min(j, last)] - x) <= gap[i]
    apart = all(t[i] - t[i - 1] > gap[i] for i in range(1, len(t)))
    if not any(near) and apart:
        return kinks
    kept: list[float] = []
    for tk, g, n in zip(t, gap, near, strict=True):
        if not n and (not kept or tk - kept[-1] > g):
            kept.append(tk)
    return kept


def _tabled(wall: Wall | None) -> bool:
    """Whether ``wall`` moves and carries a table (:class:`._wall_table.WallTable`)."""
    return wall is not None and wall.table is not None and not wall.is_fixed


def _bracketed_roots(f, a: Array, b: Array, fa: Array, fb: Array, xtol: Array, f_one=None) -> Array:
    """Roots of ``f(t, idx)`` (values at ``t`` of the brackets ``idx``) in the brackets
    ``[a, b]`` (``fa``, ``fb`` of opposite signs or 0), to ``|b - a| <= xtol``, all at once;
    ``f_one(t, i)``: the same value for one float time and bracket as a float (for the few
    brackets stepped on floats; from ``f`` unless given).

    Illinois (regula falsi halving the retained end's value: superlinear, and the far end
    moves), with steps of at least ``xtol`` towards the far end (as Brent's method: the
    bracket then closes around the root).  A bracket without a sign change gives NaN.
    """
    if np.size(a) <= 2 * _SCALAR_ROOTS:  # a few brackets: on floats throughout
        few = _few_roots(f_one or _one_of(f), a, b, fa, fb, xtol)
        if few is not None:
            return few
    a, b, fa, fb = (np.array(v, dtype=float) for v in (a, b, fa, fb))
    root = np.where(fb == 0, b, np.where(fa == 0, a, np.nan))
    live = np.isnan(root) & (np.sign(fa) * np.sign(fb) < 0)
    if np.count_nonzero(live) <= _SCALAR_ROOTS:  # a few brackets: the same steps on floats
        xt = np.asarray(xtol, dtype=float)
        for i in np.flatnonzero(live).tolist():
            args = (float(a[i]), float(b[i]), float(fa[i]), float(fb[i]), float(xt[i]))
            root[i] = _illinois(f_one or _one_of(f), i, *args)
        return root
    for _ in range(200):
        idx = np.flatnonzero(live)
        if idx.size == 0:
            break
        a_, b_, fa_, fb_, xt = a[idx], b[idx], fa[idx], fb[idx], xtol[idx]
        c = b_ - fb_ * (b_ - a_) / (fb_ - fa_)
        nudge = np.minimum(xt, 0.5 * np.abs(a_ - b_))
        c = np.where(np.abs(c - b_) < nudge, b_ + np.copysign(nudge, a_ - b_), c)
        fc = np.asarray(f(c, idx), dtype=float)
        flip = np.sign(fc) * np.sign(fb_) < 0  # the root lies between c and b
        new_a = np.where(flip, b_, a_)
        fa[idx] = np.where(flip, fb_, 0.5 * fa_)
        a[idx], b[idx], fb[idx] = new_a, c, fc
        hit = (fc == 0) | (np.abs(c - new_a) <= xt) | ~np.isfinite(fc)
        if hit.any():
            root[idx[hit]] = np.where(np.isfinite(fc[hit]), c[hit], np.nan)
            live[idx[hit]] = False
    return root


_SCALAR_ROOTS = 4  # brackets up to which _bracketed_roots steps each on Python floats


def _sgn(x: float) -> int:
    """``numpy.sign`` of a float as an int (0 for 0 and NaN)."""
    return (x > 0) - (x < 0)


def _few_roots(f_one, a: Array, b: Array, fa: Array, fb: Array, xtol: Array) -> Array | None:
    """:func:`_bracketed_roots` of a few brackets, the set-up too on Python floats (the same
    roots: a bracket end where its value is 0, the float steps where the signs differ, else
    NaN); None where more than ``_SCALAR_ROOTS`` brackets need steps (the array steps)."""
    a_, b_, fa_, fb_, xt = (np.ravel(v).tolist() for v in (a, b, fa, fb, xtol))
    live = [fa_[i] != 0 and fb_[i] != 0 and _sgn(fa_[i]) * _sgn(fb_[i]) < 0 for i in range(len(a_))]
    if sum(live) > _SCALAR_ROOTS:
        return None
    root = [b_[i] if fb_[i] == 0 else (a_[i] if fa_[i] == 0 else math.nan) for i in range(len(a_))]
    for i in range(len(a_)):
        if live[i]:
            root[i] = _illinois(f_one, i, a_[i], b_[i], fa_[i], fb_[i], xt[i])
    return np.array(root, dtype=float)


def _one_of(f):
    """``f_one(t, i)`` of :func:`_bracketed_roots` from its ``f(t, idx)``."""
    return lambda t, i: float(f(np.array([t]), np.array([i]))[0])


def _illinois(f_one, i: int, a: float, b: float, fa: float, fb: float, xt: float) -> float:
    """The root of bracket ``i`` by :func:`_bracketed_roots`' steps on Python floats (the same
    operations, so the same root: without the per-step cost of arrays of one element);
    ``f_one(t, i)`` the function's value at the float ``t`` of bracket ``i``."""
    for _ in range(200):
        try:
            c = b - fb * (b - a) / (fb - fa)
        except ZeroDivisionError:  # (numpy's inf or NaN: no root here)
            return math.nan
        nudge = min(xt, 0.5 * abs(a - b))
        if abs(c - b) < nudge:
            c = b + math.copysign(nudge, a - b)
        fc = f_one(c, i)
        flip = _sgn(fc) * _sgn(fb) < 0  # the root lies between c and b
        new_a = b if flip else a
        fa = fb if flip else 0.5 * fa
        a, b, fb = new_a, c, fc
        if fc == 0 or abs(c - new_a) <= xt or not math.isfinite(fc):
            return c if math.isfinite(fc) else math.nan
    return math.nan
