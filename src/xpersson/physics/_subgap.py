"""Sub-problems of the interface physics at a magnification ``zeta`` (private): the mean
separation of the apparent contact at ``q_a = zeta q_L`` under ``p0/A`` (virtual work of the
roughness finer than ``q_a``, :cite:p:`almqvist2011,persson2008leak`) and the rms height of that
roughness.
SI units throughout.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._compiled import PAIRWISE, kernel
from ._curve import _delta_I3, _gauss
from ._fastnum import _block, _exp
from ._phi import _Phi
from ._sub_nodes import applies

_SUB_EDGES = np.concatenate(([0.0], 0.4 ** np.arange(9, -1, -1)))
_SUB_ORDER = 6


def _sub_panels(
    psd: object, qa: NDArray[np.float64], V: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Gauss-Legendre nodes and weights in ``s`` (``q = q_a exp(V s^2)``), per element of ``qa``.

    The graded edges ``_SUB_EDGES`` plus the PSD breakpoints above ``q_a`` (kinks of ``C``, e.g.
    the roll-off ``q_r``): a rule across a kink converges only to first order, which made the
    mean gap of a cut-off inside the plateau 5-7 % low. Breakpoints outside ``(q_a, q_hi)`` give
    panels of zero width (zero weight). Where every cut-off has the same edges, one row of nodes
    and weights, broadcast (read-only) to every cut-off.
    """
    nodes = np.asarray(psd.nodes(), dtype=float)  # type: ignore[attr-defined]
    with np.errstate(divide="ignore", invalid="ignore"):
        sk = np.sqrt(np.clip(np.log(nodes / qa[..., None]) / V[..., None], 0.0, 1.0))
    sk = np.where(V[..., None] > 0.0, sk, 0.0)
    x, w = _gauss(_SUB_ORDER)
    rows = sk.reshape(-1, nodes.size)
    if rows.shape[0] and (rows == rows[0]).all():
        # every cut-off's edges the same (the breakpoints outside its range, e.g. no roll-off):
        # one row's sort and rule, the same numbers as each row's (element by element)
        edges = np.sort(np.concatenate((_SUB_EDGES, rows[0])))
        a, b = edges[:-1, None], edges[1:, None]
        s, ws = (a + (b - a) * x).reshape(-1), ((b - a) * w).reshape(-1)
        return np.broadcast_to(s, qa.shape + s.shape), np.broadcast_to(ws, qa.shape + s.shape)
    base = np.broadcast_to(_SUB_EDGES, qa.shape + _SUB_EDGES.shape)
    edges = np.sort(np.concatenate((base, sk), axis=-1), axis=-1)
    # every panel's start and width repeated over its nodes: long rows for the products (the
    # same operations as ``a + (b - a) x``, ``(b - a) w`` broadcast over the rule)
    a = np.repeat(edges[..., :-1], _SUB_ORDER, axis=-1)
    d = np.repeat(np.diff(edges, axis=-1), _SUB_ORDER, axis=-1)
    n = edges.shape[-1] - 1
    ws = d * np.tile(w, n)
    d *= np.tile(x, n)
    d += a
    return d, ws


def _sub_prep(
    psd: object, E_star: float, q_a: NDArray[np.float64], q_hi: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``(ln tau_c,a, kernel)`` on the nodes of every ``q_a`` (shape ``q_a.shape + (m,)``).

    Element by element in ``q_a``: the prepared nodes of a subset of cut-offs are the same
    subset (bit for bit) of those of all cut-offs.
    """
    qa = np.asarray(q_a, dtype=float)
    V = np.log(np.maximum(q_hi / qa, 1.0))
    fast = _compiled_prep(psd, E_star, qa, V, (_SUB_EDGES, *_gauss(_SUB_ORDER)))
    if fast is not None:  # (the kernels: the same bits)
        return fast
    s, ws = _sub_panels(psd, qa, V)
    vs = V[..., None] * s
    q = np.exp(vs * s)
    q *= qa[..., None]
    vs *= 2.0  # (2 V) s: a doubling, exact
    dq = q * vs
    dq *= ws
    dI3, C = _sub_dI3_C(psd, qa, q)
    kern = np.multiply(dq, q * q, out=dq)
    kern *= C
    # ln tau_eq = ln(tau_c,a) + 2 ln A_a: logs of the small factors, not of the tensor
    log_tc = np.log(0.25 * np.pi * E_star**2 * dI3)
    dI3 *= np.pi
    kern /= np.sqrt(dI3, out=dI3)
    return log_tc, kern


def _compiled_prep(
    psd: object,
    E_star: float,
    qa: NDArray[np.float64],
    V: NDArray[np.float64],
    rule: tuple[NDArray[np.float64], ...],
) -> tuple[NDArray[np.float64], NDArray[np.float64]] | None:
    """:func:`_sub_prep`'s ``(ln tau_c,a, kernel)`` of the cut-offs ``qa`` [1/m] (``V =
    ln(q_hi/q_a)``; ``rule``: the graded panel edges in ``s`` and the Gauss nodes and weights
    on ``[0, 1]``) by the kernels of :mod:`._sub_nodes`, the same bits (nodes outside the
    spectrum's support, e.g. the zero-width panel at ``s = 1`` rounded above ``q_1``: ``I3``
    clipped and ``C = 0``, as ``PowerSpectrum.I3`` and ``C``); None where they do not apply
    (kernels off or not built yet, a spectrum without :func:`~._sub_nodes.applies`' segments,
    a NaN node): then the numpy path."""
    fn = kernel(0.0, "node_segments")  # (built already or not: callers count the work)
    if fn is None or qa.size == 0 or not applies(psd):
        return None
    p: Any = psd
    edges, x, w = rule
    flat = qa.reshape(-1)
    with np.errstate(divide="ignore"):  # (_sub_panels' breakpoints: numpy's log)
        lb = np.log(p._nodes / flat[:, None])
    m = (edges.size + lb.shape[1] - 1) * x.size
    n = flat.size
    ws, vs, g, q, dq, r, ex, sx = np.empty((8, n, m))
    kernel(0.0, "node_panels")(lb, edges, x, w, V.reshape(-1), ws, vs, g)
    np.exp(g, out=g)
    e, a = p._e, p._a
    es = np.stack((e, 3.0 + e + 1.0))  # (_I3_and_C's per-segment factors)
    idx, small = np.empty((n, m), dtype=np.intp), np.empty((5, n * m))
    bounds = (p._nodes[1:-1], p.q_L, p.q_1, a, es)
    count = fn(g, flat, vs, ws, *bounds, q, dq, r, idx, ex, sx, small)
    if count < 0:
        return None
    # numpy's functions on the arrays _I3_and_C and _delta_I3 have (element by element)
    pw = r**ex
    L = np.log(r)
    sL = np.multiply(sx, L, out=sx)
    em = np.expm1(sL)
    small = small[:, :count]
    qm = small[1]  # the midpoint form: qm**3 and C(qm)'s power, as _delta_I3
    q3, pm = qm**3, small[2] ** small[3]
    seg = np.stack((p._Ca, p._Ca * a**4.0, p._cumulative(3.0)[:-1]))
    i3a = np.asarray(p.running_moment(3.0, flat), dtype=float)
    k0, tiny = 0.25 * np.pi * E_star**2, float(np.finfo(float).tiny)
    mid = (small[0], q3, pm, small[4])
    kernel(0.0, "node_kernel")(idx, pw, L, sL, em, seg, i3a, flat, q, dq, *mid, k0, tiny, g, ex)
    return np.log(ex).reshape(qa.shape + (m,)), g.reshape(qa.shape + (m,))


def _sub_dI3_C(
    psd: object, qa: NDArray[np.float64], q: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``(int_{q_a}^q q'^3 C dq', C(q))`` on the nodes ``q`` (``qa.shape + (m,)``) [1, m^4]:
    :func:`~._curve._delta_I3` and ``psd.C``, bit for bit, with ``I3`` and ``C`` from one
    segment search (:meth:`~._spectrum.PowerSpectrum._I3_and_C`) where the spectrum has it."""
    qf = q.reshape(-1)
    both = getattr(psd, "_I3_and_C", lambda q: None)(qf)
    if both is None:
        C = np.asarray(psd.C(qf), dtype=float).reshape(q.shape)  # type: ignore[attr-defined]
        return _delta_I3(psd, qa[..., None], q), C
    i3, C = both
    # I3 itself (the base class's, as _I3_and_C found): the moments without I3's grid cache
    i3a = psd.running_moment(3.0, qa.reshape(-1))  # type: ignore[attr-defined]
    i3, i3a = i3.reshape(q.shape), i3a.reshape(qa.shape + (1,))
    return _delta_I3(psd, qa[..., None], q, i3, i3a), C.reshape(q.shape)


def _sub_mean_gap(
    psd: object,
    E_star: float,
    phi: _Phi,
    q_a: NDArray[np.float64],
    area_a: NDArray[np.float64],
    q_hi: float,
    where: NDArray[np.bool_] | None = None,
    prep: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None,
    spline: bool = False,
    needed: NDArray[np.bool_] | None = None,
) -> NDArray[np.float64]:
    """Mean separation [m] of the apparent contact at ``q_a`` (n_load, n_a) under ``p0/A_a``.

    ``u_a = pi int_{q_a}^{q_hi} q^2 C w_a Phi(tau_a(q) A_a^2 / p0^2) dq`` with ``tau_a``, ``w_a``
    counted from ``q_a`` (:cite:p:`almqvist2011,persson2008leak`). Vectorised: ``q = q_a exp(V
    s^2)``,
    ``V = ln(q_hi/q_a)``, graded Gauss-Legendre panels in ``s``. ``where`` (n_load, n_a):
    compute only these entries (the others are 0). ``prep``: :func:`_sub_prep` of ``q_a``,
    when already at hand. ``spline``: ``Phi`` from its spline, not its look-up table (smooth
    in the cut-off: for difference quotients; per-load cut-offs only). ``needed`` (n_load,
    n_a; cut-offs shared by every load, without ``where`` or ``spline``): the entries asked
    for, each by the same operations as without it (the shared ones' sums per cut-off, the
    others' per entry: the same bits); the others not computed (0, or a shared cut-off's
    sums).
    """
    log_tc, kern = _sub_prep(psd, E_star, q_a, q_hi) if prep is None else prep
    with np.errstate(divide="ignore"):
        log_a2 = 2.0 * np.log(np.asarray(area_a, dtype=float))[..., None]
    n = phi.p0.size
    shape = (n,) + np.broadcast_shapes(log_tc.shape, log_a2.shape)[1:]
    shared = None
    one = log_tc.shape[0] == 1 and kern.shape[0] == 1  # cut-offs of one row
    if where is None and not spline and one and phi.has_table:
        # cut-offs shared by every load: where A_a = 1 (ln A_a^2 = 0, full contact at q_a; 70 %
        # of the detachment's edges on the README scene) the arguments are the same for every
        # load, and their sums are one sparse product with Phi's table (never with ``spline``:
        # its per-load cut-offs of one load alone look shared, and would take the table)
        shared = np.broadcast_to(log_a2[..., 0] == 0.0, shape[:-1])
        shared = shared & needed if needed is not None else shared
        shared = shared if shared.any() else None
    need = where if where is not None else (None if shared is None else ~shared)
    if needed is not None and where is None:  # (the per-entry sums: the needed ones only)
        need = needed if need is None else need & needed
    if where is not None:
        out = np.zeros(shape[:-1])
    elif shared is not None:
        out = _shared_sums(phi, log_tc[0], kern[0], shared, needed is not None)
    else:
        out = np.empty(shape[:-1]) if needed is None else np.zeros(shape[:-1])
    if not spline and _compiled_sums(phi, log_tc, kern, log_a2, need, out):
        return math.pi * out
    if spline and need is None and _compiled_spline_sums(phi, log_tc, kern, log_a2, out):
        return math.pi * out
    log_tc, log_a2 = np.broadcast_to(log_tc, shape), np.broadcast_to(log_a2, shape)
    kern = np.broadcast_to(kern, shape)
    step = _block(math.prod(shape[1:]))
    for i in range(0, n, step):  # blocks of loads: the tensor's temporaries stay in cache
        k, c = slice(i, i + step), 0
        if need is not None:  # the needed sums, from the block's first needed column on
            nk = need[k]
            if not nk.any():
                continue
            c = int(np.argmax(nk.any(axis=0)))
        with np.errstate(invalid="ignore"):  # ln A_a = -inf outside `where` (A_a = 0)
            lt = log_tc[k, c:] + log_a2[k, c:]
        if spline:
            vals = phi.spline_at_log_tau_per_load(lt, k)
        else:
            vals = phi.at_log_tau_per_load(lt, k, overwrite=True)
        vals *= kern[k, c:]
        if need is None:
            out[k] = vals.sum(axis=-1)
        else:
            np.copyto(out[k, c:], vals.sum(axis=-1), where=need[k, c:])
    return math.pi * out


def _shared_sums(
    phi: _Phi,
    log_tc: NDArray[np.float64],
    kern: NDArray[np.float64],
    shared: NDArray[np.bool_],
    some: bool,
) -> NDArray[np.float64]:
    """:meth:`~._phi._Phi.sums_at_log_tau` of the cut-offs (n_a, m) shared by every load,
    (n_load, n_a); ``some``: only the ``shared`` entries, at the cut-offs where some load's
    entry is (the others 0, or unspecified in those cut-offs). Each entry's sum is that of
    the entry alone (its cut-off's own nodes, its own row of the sparse product or of the
    compiled loop), so a subset gives the same bits."""
    if not some:
        return phi.sums_at_log_tau(log_tc, kern)
    cols = np.flatnonzero(shared.any(axis=0))
    out = np.zeros(shared.shape)
    out[:, cols] = phi.sums_at_log_tau(log_tc[cols], kern[cols], shared[:, cols])
    return out


def _compiled_sums(
    phi: _Phi,
    log_tc: NDArray[np.float64],
    kern: NDArray[np.float64],
    log_a2: NDArray[np.float64],
    need: NDArray[np.bool_] | None,
    out: NDArray[np.float64],
) -> bool:
    """The per-load sums of :func:`_sub_mean_gap` (cut-offs shared by every load) written into
    ``out`` by the compiled :func:`~._compiled.sub_sums` (bit for bit the loop below);
    False where it does not apply (no table, per-load cut-offs, NaN areas, more than
    :data:`~._compiled.PAIRWISE` nodes, kernel off, an argument in Phi's linear first interval:
    numpy's ``exp``)."""
    if not phi.has_table or log_tc.shape[0] != 1 or kern.shape[0] != 1 or log_a2.ndim != 3:
        return False
    if log_tc.shape[-1] > PAIRWISE:
        return False
    fn = kernel(out.size * log_tc.shape[-1], "sub_sums")
    if fn is None:
        return False
    la2 = np.ascontiguousarray(np.broadcast_to(log_a2[..., 0], out.shape))
    if np.isnan(la2).any():
        return False
    grid, table = phi._table()  # (loads, nodes)
    mask = np.ones(out.shape, dtype=bool) if need is None else np.ascontiguousarray(need)
    tc, kn = np.ascontiguousarray(log_tc[0]), np.ascontiguousarray(kern[0])
    return fn(
        tc, kn, la2, mask, out, table, grid, phi._lo, phi.tau1, np.ascontiguousarray(phi.phi[:, 1])
    )


def _h2(psd: object, q: ArrayLike, q_hi: float) -> NDArray[np.float64]:
    m_hi = float(psd.running_moment(1.0, q_hi))  # type: ignore[attr-defined]
    m = np.asarray(psd.running_moment(1.0, np.minimum(q, q_hi)), dtype=float)  # type: ignore[attr-defined]
    return np.maximum(2.0 * math.pi * (m_hi - m), 0.0)


def _compiled_spline_sums(
    phi: _Phi,
    log_tc: NDArray[np.float64],
    kern: NDArray[np.float64],
    log_a2: NDArray[np.float64],
    out: NDArray[np.float64],
) -> bool:
    """The sums of :func:`_sub_mean_gap`'s ``spline`` branch (every entry) written into ``out``
    by the compiled :func:`~._spline_sums.spline_sub_sums` (bit for bit the loop there: the
    linear first interval's values from the same numpy operations on its arguments only);
    False where it does not apply (no spline, more than :data:`~._compiled.PAIRWISE` nodes,
    kernel off)."""
    spl = phi._spl
    if spl is None or log_a2.ndim != 3 or log_tc.shape[-1] > PAIRWISE:
        return False
    fn = kernel(out.size * log_tc.shape[-1], "spline_sub_sums")
    if fn is None:
        return False
    shape = out.shape + (log_tc.shape[-1],)
    with np.errstate(invalid="ignore"):  # ln A_a = -inf (A_a = 0)
        lt = np.add(log_tc, log_a2, out=np.empty(shape))
    kr = np.ascontiguousarray(np.broadcast_to(kern, shape))
    log_tau1 = math.log(phi.tau1)
    low = np.flatnonzero(lt < log_tau1)  # the linear first interval, as the numpy path
    t = _exp(lt.ravel()[low])
    t /= phi.tau1
    lin = phi.phi[low // (shape[1] * shape[2]), 1] * np.clip(t, 0.0, 1.0)
    rows = np.arange(out.shape[0])
    fn(lt, kr, lin, spl.x, spl.c, rows, log_tau1, out)
    return True
