"""Compiled set-up of the sub-problems' nodes (numba, private): :func:`~._subgap._sub_prep`
in three loops between numpy's transcendental functions; bit for bit.

``_sub_prep`` makes ~40 numpy passes over the (cut-offs, nodes) tensor (the panels, the nodes,
``I3`` and ``C`` from one segment search, ``_delta_I3`` and its midpoint form at the nodes
within ``1e-6 q_a`` of their cut-off, ~22 % of them, the kernel): the 200 cut-offs (78 nodes
each) of :meth:`~._solved_contact.SolvedContact.separation_at` at 100 loads took 0.5-0.8 ms
of a leak solve's ~10 ms, mostly passes, gathers and boolean masks rather than the functions
(``exp``, ``pow``, ``log``, ``expm1``). Here the work between those functions is three loops
(:func:`node_panels`, :func:`node_segments`, :func:`node_kernel`), each element by the numpy
path's operations in its order (products, quotients, sums, comparisons, ``sqrt``: IEEE, the
same bits); numpy still computes every ``log``, ``exp``, ``pow`` and ``expm1``, each on the
same values as the numpy path (element by element). Built and gated with the kernels of
:mod:`._compiled` (:data:`KERNELS`), called by :func:`~._subgap._compiled_prep` once they are
built; plain Python without numba.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ._spectrum import PowerSpectrum

__all__ = ["KERNELS", "applies", "node_kernel", "node_panels", "node_segments"]


def applies(psd: object) -> bool:
    """Whether ``psd`` has :meth:`~._spectrum.PowerSpectrum._I3_and_C`'s segments (the base
    class's ``C``, ``I3`` and moments on ``_set_segments``' power laws)."""
    cls = type(psd)
    return (
        isinstance(psd, PowerSpectrum)
        and "_nodes" in psd.__dict__
        and cls.C is PowerSpectrum.C
        and cls.I3 is PowerSpectrum.I3
        and cls.running_moment is PowerSpectrum.running_moment
    )


def node_panels(
    lb: Any, edges: Any, x: Any, w: Any, V: Any, ws: Any, vs: Any, arg: Any
) -> None:  # pragma: no cover - compiled (its plain-Python form is tested)
    """Every cut-off's panel weights ``ws``, ``vs = V s`` and ``arg = vs s`` of its nodes
    ``s`` (n_cut, m), as :func:`~._subgap._sub_panels`: the panels between the sorted union
    of ``edges`` and the spectrum's breakpoints ``sqrt(clip(lb / V, 0, 1))`` (0 where not
    ``V > 0``; ``lb`` (n_cut, n_b): their ``ln(q_k / q_a)``), Gauss nodes ``x`` and weights
    ``w`` on each: ``s = a + (b - a) x``, ``ws = (b - a) w``."""
    n, nb = lb.shape
    ne, o = edges.size, x.size
    e = np.empty(ne + nb)
    for i in range(n):
        Vi = V[i]
        e[:ne] = edges
        for t in range(nb):  # insertion into the sorted edges (np.sort: the same numbers)
            v = 0.0
            if Vi > 0.0:
                v = lb[i, t] / Vi
                if v == v:  # np.clip(v, 0, 1): NaN kept, -0.0 -> 0.0
                    v = v if v > 0.0 else 0.0
                    v = v if v < 1.0 else 1.0
                v = math.sqrt(v)
            j = ne + t
            while j > 0 and e[j - 1] > v:
                e[j] = e[j - 1]
                j -= 1
            e[j] = v
        for pnl in range(ne + nb - 1):
            lo = e[pnl]
            h = e[pnl + 1] - lo
            for k in range(o):
                c = pnl * o + k
                s = lo + h * x[k]
                ws[i, c] = h * w[k]
                y = Vi * s
                vs[i, c] = y
                arg[i, c] = y * s


def node_segments(
    g: Any, qa: Any, vs: Any, ws: Any, inner: Any, lo: float, hi: float, a: Any, es: Any,
    q: Any, dq: Any, r: Any, idx: Any, ex: Any, sx: Any, small: Any,
) -> int:  # fmt: skip  # pragma: no cover - compiled (its plain-Python form is tested)
    """The nodes ``q = g q_a`` (``g = exp(V s^2)``), ``dq = q (2 V s) ws`` (``vs = V s``),
    each node's spectrum segment ``j`` (``np.searchsorted(inner, q, side="right")``, ``inner``
    the inner breakpoints; ``-1 - j`` outside the support ``[lo, hi]``, where ``C`` is 0),
    ``r = q_c / a_j`` (``q_c``: ``q`` clipped to the support, as ``I3`` clips it) and the
    segment's ``e_j`` and ``3 + e_j + 1`` (``es``: (2, n_seg)), written into ``q``, ``dq``,
    ``r``, ``idx``, ``ex``, ``sx`` (n_cut, m); the nodes within ``1e-6 q_a`` of their cut-off,
    in order, into ``small`` (5, n): flat index, midpoint ``q_m = q_a + (q - q_a) / 2``, its
    ``q_m / a_j``, ``e_j`` and ``j`` (``-1 - j`` outside; as floats). Returns their count, or
    -1 where a node is NaN (then nothing written is used)."""
    n, m = g.shape
    ni = inner.size
    count = 0
    for i in range(n):
        qi = qa[i]
        for k in range(m):
            qk = g[i, k] * qi
            if qk != qk:
                return -1
            q[i, k] = qk
            dq[i, k] = (qk * (vs[i, k] * 2.0)) * ws[i, k]
            qc = qk if qk > lo else lo  # I3's clip to the support (C: 0 outside)
            qc = qc if qc < hi else hi
            j = 0
            while j < ni and inner[j] <= qc:
                j += 1
            idx[i, k] = j if qk >= lo and qk <= hi else -1 - j
            r[i, k] = qc / a[j]
            ex[i, k] = es[0, j]
            sx[i, k] = es[1, j]
            d = qk - qi
            if d < 1e-6 * qi:
                qm = qi + 0.5 * d
                jm = 0
                while jm < ni and inner[jm] <= qm:
                    jm += 1
                small[0, count] = i * m + k
                small[1, count] = qm
                small[2, count] = qm / a[jm]
                small[3, count] = es[0, jm]
                small[4, count] = jm if qm >= lo and qm <= hi else -1 - jm
                count += 1
    return count


def node_kernel(
    idx: Any, pw: Any, L: Any, sL: Any, em: Any, seg: Any, i3a: Any, qa: Any, q: Any,
    dq: Any, at: Any, q3: Any, pm: Any, js: Any, k0: float, tiny: float, kern: Any, targ: Any,
) -> None:  # fmt: skip  # pragma: no cover - compiled (its plain-Python form is tested)
    """``kern = dq q^2 C / sqrt(pi dI3)`` and ``targ = k0 dI3`` (n_cut, m) from ``pw = r^e``,
    ``L = ln r``, ``sL = (3 + e + 1) L`` and ``em = expm1(sL)``: ``C = C_j pw`` (0 where
    ``idx`` marks a node outside the support), ``dI3 = I3(q) - I3(q_a)`` (``I3`` as
    :meth:`~._spectrum.PowerSpectrum.running_moment`; ``i3a`` (n_cut,): ``I3(q_a)``), at the
    flat indices ``at`` (in order) the midpoint form ``(q - q_a) q_m^3 C(q_m)`` of
    ``_delta_I3`` (``q3 = q_m^3``, ``pm = (q_m / a_j)^e_j``, ``js``: ``j``), floored at
    ``tiny``. ``seg`` (3, n_seg): ``C_j``, ``C_j a_j^4``, the cumulative ``I3`` at ``a_j``.
    ``pw`` is overwritten (``C``)."""
    n, m = q.shape
    for i in range(n):
        base = i3a[i]
        for k in range(m):
            j = idx[i, k]
            if j < 0:  # outside the support: C = 0, I3 at its end
                j = -1 - j
                pw[i, k] = 0.0
            else:
                pw[i, k] = seg[0, j] * pw[i, k]  # C
            x = sL[i, k]
            f = em[i, k] / x if x != 0.0 else 1.0  # _expm1_over_x (1 at 0)
            targ[i, k] = (seg[2, j] + (seg[1, j] * L[i, k]) * f) - base
    for c in range(at.size):
        t = int(at[c])
        i, k = t // m, t - (t // m) * m
        jm = int(js[c])
        C = seg[0, jm] * pm[c] if jm >= 0 else 0.0
        targ[i, k] = ((q[i, k] - qa[i]) * q3[c]) * C
    for i in range(n):
        for k in range(m):
            d = targ[i, k]
            d = d if (d > tiny or d != d) else tiny  # np.maximum(d, tiny)
            qk = q[i, k]
            targ[i, k] = k0 * d
            kern[i, k] = ((dq[i, k] * (qk * qk)) * pw[i, k]) / math.sqrt(d * math.pi)


#: The kernels of this module, for :func:`._compiled._build`.
KERNELS = (node_panels, node_segments, node_kernel)
