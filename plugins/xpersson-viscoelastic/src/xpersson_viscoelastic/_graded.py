"""The friction integral on graded Gauss-Legendre panels where the output grid misses the area.

Where the contact area of a stiff rubber drops from 1 to ``~ (zeta - 1)^(-1/2)`` just above
``zeta = 1`` (:mod:`~xpersson_viscoelastic._resolve`), ``mu_visc`` is integrated as the kernel
:func:`~xpersson_viscoelastic._curve.friction_curve` integrates it (verified to ~1e-9 against
an independent quadrature, ``benchmarks/verify_friction.py``): Gauss-Legendre panels graded
towards ``q_L`` (two per decade of ``q - q_L`` in ``ln(q - q_L)``, the first panel linear in
``q`` and ending where ``G <= 5e-4``), the spectrum's log grid and breakpoints above ``2 q_L``,
and every output magnification up to the dense top as a panel edge (so the running integral
is read there exactly). ``tau`` at every node comes from the spectral running integral of
``q^3 C <|E|^2>`` (no ``I3(q)``: it loses digits where ``q - q_L`` nears the round-off of
``q``), the area at the nodes from the same solve (the engine at those ``tau``), and
``int P S dL`` from the nodes' ``dL``.

Points whose panels coincide (the same dense top and number of rungs: the edges depend on
nothing else for a Prony model) are evaluated together: one modulus evaluation and one
engine call for the group, so a stacked block and the point-by-point path give the same
numbers.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from xpersson.cache import content_key

from ._gauss import spectral_rule as _rule
from ._panels import node_counts
from .kernel import NODES, PANELS_PER_DECADE, _checked_nu, panel_edges

__all__ = [
    "FIRST_G",
    "Layout",
    "rungs",
    "layout",
    "known_nodes",
    "integrals",
    "integrals_and_top",
    "running",
    "graded_runs",
]

Array = NDArray[np.float64]

#: ``G`` at the end of the first panel (bounded from the mean slope over the first output
#: interval): the area is 1 to round-off there (``erf(1 / (2 sqrt(5e-4))) = 1 - 1e-220``).
FIRST_G = 5e-4


def rungs(zeta: Array, G: Array, top: int) -> int:
    """Number of graded rungs (two per decade of ``zeta - 1``) below ``1 + min(1, zeta[top] - 1)``
    for loads with ``G`` rows (n_sel, n_zeta) [1]: down to where ``G <= FIRST_G``, rounded up
    to an even number (a block's points then share their panels in fewer groups)."""
    t = min(1.0, float(zeta[top]) - 1.0)
    z1 = float(zeta[1]) - 1.0
    slope = float(np.max(G[:, 1])) / z1
    d0 = min(t, FIRST_G / slope) if slope > 0 else t
    n = max(1, int(np.ceil(2.0 * np.log10(t / d0) - 1e-9)))
    return n + n % 2


@dataclass(frozen=True)
class Layout:
    """Graded panels and their nodes (ascending in ``q``; panel ``p`` holds the nodes
    ``start[p] .. start[p + 1] - 1``)."""

    edges: Array  #: panel edges [1/m], (P + 1,)
    out: NDArray[np.intp]  #: indices of the output magnifications ``zeta[: top + 1]`` in edges
    qn: Array  #: nodes [1/m], (N,)
    wq: Array  #: weights ``dq`` [1/m], (N,)
    jac: Array  #: ``dq/du`` at the nodes (``u``: the panel's variable)
    start: NDArray[np.intp]  #: first node of each panel, (P,)
    counts: NDArray[np.intp]  #: nodes of each panel, (P,)
    base: Array  #: the output grid's q panel edges [1/m] (the coefficient's)
    block: NDArray[np.intp]  #: the panel of ``base`` each panel is (-1: none), (P,)
    groups: tuple[tuple[NDArray[np.intp], NDArray[np.intp], Array, Array], ...]
    #: per node count m: (panels, node positions (n_p, m), half-widths (n_p,), Q (m, m))

    @property
    def zeta(self) -> Array:
        """Node magnifications [1]."""
        return self.qn / self.edges[0]


def layout(psd: Any, zeta: Array, top: int, n: int, ppd: int, base: Array | None = None) -> Layout:
    """The panels of output grid ``zeta`` [1] up to ``zeta[top]`` with ``n`` graded rungs
    (:func:`rungs`) and above ``2 q_L`` the output grid's q panels (``ppd`` log panels per
    decade; ``base``: their edges [1/m] computed already)."""
    q_L = float(psd.q_L)
    t = min(1.0, float(zeta[top]) - 1.0)
    q_out = np.asarray(zeta[: top + 1], dtype=float) * q_L
    ladder = q_L * (1.0 + t * 10.0 ** (-np.arange(n, -1, -1) / 2.0))
    if base is None:  # the output grid's q panels
        base = panel_edges(psd, np.asarray(zeta, dtype=float) * q_L, ppd)
    nodes = np.asarray(psd.nodes(), dtype=float)
    inner = nodes[(nodes > q_L) & (nodes < ladder[-1])]
    above = base[(base >= ladder[-1]) & (base <= q_out[-1])]
    extra = np.unique(np.concatenate([ladder, above, inner]))
    near = np.searchsorted(q_out, extra).clip(1, q_out.size - 1)
    gap = np.minimum(np.abs(extra - q_out[near - 1]), np.abs(extra - q_out[near]))
    # an edge within round-off of an output magnification would make an empty panel
    edges = np.unique(np.concatenate([extra[gap > 1e-10 * extra], q_out]))
    a, b = edges[:-1], edges[1:]
    kind = np.zeros(a.size, dtype=int)  # 0: ln q, 1: ln(q - q_L), 2: q (the first panel)
    kind[(a > q_L) & (b <= 2.0 * q_L)] = 1
    kind[(a <= q_L) & (b <= 2.0 * q_L)] = 2
    shift = np.where(kind == 1, q_L, 0.0)
    with np.errstate(divide="ignore"):
        lo = np.where(kind == 2, a, np.log(a - shift))
        hi = np.where(kind == 2, b, np.log(b - shift))
    mid, half = 0.5 * (hi + lo), 0.5 * (hi - lo)
    counts = np.full(a.size, NODES, dtype=np.intp)
    counts[kind == 0] = node_counts(half[kind == 0], NODES)  # narrow ln q panels: fewer nodes
    start = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.intp)
    N = int(counts.sum())
    qn, wq, jac = np.empty(N), np.empty(N), np.empty(N)
    groups = []
    for m in np.unique(counts):
        sel = np.flatnonzero(counts == m)
        x, w, Q = _rule(int(m))
        u = mid[sel, None] + half[sel, None] * x
        first = kind[sel, None] == 2
        with np.errstate(over="ignore"):
            eu = np.exp(np.where(first, 0.0, u))
        qs = np.where(first, u, eu + shift[sel, None])  # q_L + e^u, u or e^u
        js = np.where(first, 1.0, np.where(kind[sel, None] == 1, eu, qs))
        pos = start[sel, None] + np.arange(int(m))
        qn[pos], jac[pos], wq[pos] = qs, js, half[sel, None] * w * js
        groups.append((sel, pos, half[sel], Q))
    out = np.searchsorted(edges, q_out)
    at = np.searchsorted(base, a).clip(0, base.size - 2)
    same = (kind == 0) & (base[at] == a) & (base[at + 1] == b)
    block = np.where(same, at, -1).astype(np.intp)
    return Layout(edges, out, qn, wq, jac, start, counts, base, block, tuple(groups))


def known_nodes(last: Any, v: Array, aT: Array, index: Any) -> Any:
    """``(rows, keep)``: the node values a coefficient kept from its output-grid integrals
    (``last = (v, aT, keep)`` of its block on the same spectrum and Poisson ratio, see
    :func:`~xpersson_viscoelastic.kernel._cumulative_at`) for the block's points ``index``
    with speeds ``v`` [m/s] and shift factors ``aT`` [1]; ``None`` where they do not apply."""
    if last is None or index is None:
        return None
    v0, aT0, keep = last
    rows = np.asarray(index, dtype=np.intp)
    if rows.size == 0 or int(rows.max()) >= v0.size:
        return None
    if not (np.array_equal(v0[rows], v) and np.array_equal(aT0[rows], aT)):
        return None
    return rows, keep


def _parts(model: Any, lay: Layout, w: Array, known: Any) -> tuple[Array, Array]:
    """``model.parts(w)`` (K, N), the nodes of panels the output grid's integrals evaluated
    already (``known``, :func:`known_nodes`) taken from there."""
    if known is None or not np.array_equal(known[1].get("edges"), lay.base):
        return model.parts(w)
    rows, keep = known
    excess, loss = np.empty(w.shape), np.empty(w.shape)
    fresh = np.ones(w.shape[1], dtype=bool)
    every = rows.size == next(iter(v[1] for m, v in keep.items() if m != "edges")).shape[0]
    every = every and bool(np.all(rows == np.arange(rows.size)))  # the block's points in order
    for m, (sel, ex, lo) in ((m, v) for m, v in keep.items() if m != "edges"):
        at = np.full(lay.base.size - 1, -1)
        at[sel] = np.arange(sel.size)
        p = np.flatnonzero((lay.block >= 0) & (lay.counts == m))
        j = at[lay.block[p]]
        p, j = p[j >= 0], j[j >= 0]
        if not p.size:
            continue
        pos = (lay.start[p, None] + np.arange(m)).ravel()  # consecutive panels: one slice
        cut = slice(pos[0], pos[-1] + 1) if pos[-1] - pos[0] + 1 == pos.size else pos
        pick = (slice(None), j) if every else np.ix_(rows, j)
        excess[:, cut] = ex[pick].reshape(w.shape[0], -1)
        loss[:, cut] = lo[pick].reshape(w.shape[0], -1)
        fresh[cut] = False
    if fresh.any():
        excess[:, fresh], loss[:, fresh] = model.parts(w[:, fresh])
    return excess, loss


def integrals(
    psd: Any, model: Any, nu: float, lay: Layout, w: Array, known: Any = None
) -> tuple[Array, Array]:
    """``tau`` [Pa^2] at the nodes and the nodes' ``dL`` [Pa] (each (K, N)) of K points from
    one evaluation of the Prony modulus at ``w = q v a_T`` [rad/s] (K, N) of the nodes
    (``known``: node values evaluated already, :func:`known_nodes`)."""
    return integrals_and_top(psd, model, nu, lay, w, known)[:2]


def integrals_and_top(
    psd: Any, model: Any, nu: float, lay: Layout, w: Array, known: Any = None
) -> tuple[Array, Array, Array]:
    """:func:`integrals` and ``tau`` [Pa^2] at the last panel edge, (K,)."""
    f = _checked_nu(nu)
    q3C = lay.qn**3 * np.asarray(psd.C(lay.qn), dtype=float)
    excess, loss = _parts(model, lay, w, known)  # (K, N)
    mean_sq = excess + model.E_r**2
    ends = np.add.reduceat(mean_sq * (q3C * lay.wq), lay.start, axis=-1)  # (K, P)
    before = np.concatenate([np.zeros((w.shape[0], 1)), np.cumsum(ends, axis=-1)[:, :-1]], -1)
    dens = mean_sq * (q3C * lay.jac)  # the integrand in each panel's variable u
    tau = np.empty_like(dens)
    for sel, pos, half, Q in lay.groups:
        within = half[:, None] * np.einsum("ij,kpj->kpi", Q, dens[:, pos])
        tau[:, pos] = before[:, sel, None] + within
    tau = np.maximum((np.pi / 4.0) * tau / (f * f), 0.0)
    top = np.maximum((np.pi / 4.0) * (before[:, -1] + ends[:, -1]) / (f * f), 0.0)
    return tau, q3C * lay.wq * loss / f, top


def running(g: Array, dL: Array, lay: Layout, p0: Array) -> Array:
    """``(1 / (2 p0)) int_1^zeta g dL`` at the output magnifications of the layout, rows of
    ``g`` (R, N) [1] with their ``dL`` (R, N) [Pa] and loads ``p0`` (R,) [Pa]."""
    panel = np.add.reduceat(g * dL, lay.start, axis=-1)
    cum = np.concatenate([np.zeros((g.shape[0], 1)), np.cumsum(panel, axis=-1)], axis=-1)
    return cum[:, lay.out] / (2.0 * np.asarray(p0, dtype=float)[:, None])


def _rows_of(members: list[tuple[int, Array]]) -> NDArray[np.intp]:
    """The member index of every (point, load) row of a group."""
    return np.concatenate([np.full(loads.size, i) for i, (_, loads) in enumerate(members)])


def _areas(ctx_of: Any, parts: list[Any]) -> list[Array]:
    """``A/A0`` (R, N) of every (point, load) row of each group at its nodes: one engine call
    for the block (``ctx_of.solve_rows`` of a stacked run; rows padded to the longest with a
    strictly increasing tail that is not read), else each point's ``solve_at``."""
    solve_rows = getattr(ctx_of, "solve_rows", None)
    if solve_rows is not None:
        m = max(lay.qn.size for _, lay, _, _ in parts)
        taus, points, loads = [], [], []
        for members, lay, tau, _ in parts:
            of = _rows_of(members)
            n = lay.qn.size
            t = np.empty((of.size, m))
            t[:, :n] = tau[of]
            t[:, n:] = t[:, n - 1 : n] * (1.0 + 1e-12 * np.arange(1, m - n + 1))
            taus.append(t)
            points.append(np.array([members[i][0] for i in of]))
            loads.append(np.concatenate([ld for _, ld in members]))
        got = solve_rows(np.concatenate(points), np.concatenate(loads), np.concatenate(taus))
        if got is not None:
            got = np.asarray(got, dtype=float)
            ends = np.cumsum([0] + [t.shape[0] for t in taus])
            cut = zip(ends[:-1], ends[1:], parts, strict=True)
            return [got[a:b, : p[1].qn.size] for a, b, p in cut]
    out = []
    for members, lay, tau, _ in parts:
        rows = [
            ctx_of(k).solve_at(lay.zeta, loads, tau=tau[i])["area_fraction"]
            for i, (k, loads) in enumerate(members)
        ]
        out.append(np.concatenate([np.asarray(r, float).reshape(-1, lay.qn.size) for r in rows]))
    return out


def graded_runs(
    ctx_of: Any,
    psd_of: Any,
    items: list[tuple[int, Array, int]],
    zeta: Array,
    G: Any,
    p0: Array,
    factor: Any,
) -> dict[int, Array] | None:
    """``mu_visc_cumulative`` (n_sel, top + 1) at ``zeta[: top + 1]`` of every item
    ``(point k, loads, top)`` on graded panels, or ``None`` where the block's coefficient
    does not give them (``graded_stacked`` of the viscoelastic coefficient, which the caller
    checks the block has) or a point cannot take them (then the dense grids).

    ``psd_of(k)`` gives point k's spectrum as the solved Dataset stores it (the panels are laid
    on it), ``G(k)`` point k's ``G`` (n_load, n_zeta) [1], ``p0`` the loads [Pa] and
    ``factor(A)`` the integrand ``P S`` from the area ``P``.
    """
    coef0 = ctx_of(0).coefficient  # the block's first: it integrated the output grid
    if getattr(ctx_of(items[0][0]), "solve_at", None) is None:
        return None
    # a stacked block's points' contexts without their solve_at (ctx_of(k) builds one)
    light = getattr(ctx_of, "light", ctx_of)
    keys: dict[int, Any] = {}  # content keys of the spectra, once per object
    groups: dict[tuple[Any, ...], list[tuple[int, Array]]] = {}
    for k, loads, top in items:
        n = rungs(zeta, G(k)[loads], top)
        psd = psd_of(k)
        if id(psd) not in keys:
            keys[id(psd)] = content_key(psd)
        groups.setdefault((top, n, keys[id(psd)], light(k).nu), []).append((k, loads))
    parts = []
    bases: dict[Any, Array] = {}  # the output grid's q panels, once per spectrum
    for (top, n, psd_id, _), members in groups.items():
        psd = psd_of(members[0][0])
        # the coefficient integrates over the Dataset's spectrum (the group's one), the same
        # numbers as the scene's bit for bit: what an archive reopened later carries
        ctxs = [dataclasses.replace(light(k), psd=psd) for k, _ in members]
        coefs = [c.coefficient for c in ctxs]
        if any(type(c) is not type(coef0) for c in coefs):
            return None
        if psd_id not in bases:
            bases[psd_id] = panel_edges(psd, zeta * float(psd.q_L), PANELS_PER_DECADE)
        lay = layout(psd, zeta, top, n, PANELS_PER_DECADE, bases[psd_id])
        got = coef0.graded_stacked(ctxs, coefs, lay, np.array([k for k, _ in members]))
        if got is None or not np.all(np.diff(got[0], axis=-1) > 0):
            return None  # not a Prony block, or tau not strictly increasing at the nodes
        parts.append((members, lay, *got))
    out: dict[int, Array] = {}
    for (members, lay, _, dL), A in zip(parts, _areas(ctx_of, parts), strict=True):
        of = _rows_of(members)
        run = running(factor(A), dL[of], lay, p0[np.concatenate([ld for _, ld in members])])
        for i, (k, _) in enumerate(members):
            out[k] = run[of == i]
    return out
