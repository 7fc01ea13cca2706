"""Numerical machinery of :mod:`xpersson.physics.interface` (private).

The solved area curve as splines in ``ln zeta`` (:class:`_Curve`), ``Phi(G)`` of the
virtual-work mean gap (:class:`_Phi`), and the quadrature rules over wavevectors (composite
Gauss-Legendre, exact for the ``(q - q_a)^(-1/2)`` singularity of ``w``). SI units throughout.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..cache import memoize

if TYPE_CHECKING:
    from scipy.interpolate import PPoly

from ._compiled import kernel
from ._fastnum import _EXP_LO, _block, _exp, _exp_inplace, _row_spline

_TINY = 1e-300
_GL_ORDER = 6


# -- quadrature ---------------------------------------------------------------------------------
@memoize("physics.gauss_legendre", scope="process", maxsize=16)
def _gauss(n: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Gauss-Legendre nodes and weights on ``[0, 1]``."""
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (x + 1.0), 0.5 * w


def _panels(edges: NDArray[np.float64], n: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    x, w = _gauss(n)
    a, b = edges[:-1, None], edges[1:, None]
    return (a + (b - a) * x).ravel(), ((b - a) * w).ravel()


@dataclass(frozen=True)
class _QRule:
    q: NDArray[np.float64]  # nodes [1/m]
    weights: NDArray[np.float64]  # [1/m]
    C: NDArray[np.float64]  # C(q) [m^4]
    w: NDArray[np.float64]  # (pi int_{q_a}^q q'^3 C)^(-1/2) [1]
    dI3: NDArray[np.float64]  # int_{q_a}^q q'^3 C [1]


def _q_rule(
    psd: object, q_a: float, q_b: float, *, n_s: int = 36, panels_per_decade: int = 6
) -> _QRule:
    """Composite Gauss-Legendre rule on ``[q_a, q_b]`` exact for the ``w`` singularity at q_a.

    ``[q_a, q_m]`` (``q_m = min(1.5 q_a, next PSD breakpoint)``) with ``q = q_a + s^2`` and
    geometric panels towards ``s = 0``; above, panels uniform in ``ln q`` split at every PSD
    breakpoint (kinks of ``C``).
    """
    qa, qb = float(q_a), float(q_b)
    if qb <= qa * (1.0 + 1e-14):
        e = np.zeros(0)
        return _QRule(e, e, e, e, e)
    nodes = np.asarray(psd.nodes(), dtype=float)  # type: ignore[attr-defined]
    inner = nodes[(nodes > qa * (1.0 + 1e-12)) & (nodes < qb)]
    q_m = min(1.5 * qa, inner[0] if inner.size else qb, qb)
    s_m = math.sqrt(q_m - qa)
    s_edges = np.concatenate(([0.0], s_m * 0.5 ** np.arange(n_s, -1, -1)))
    s, ws = _panels(s_edges, 10)
    parts_q, parts_w = [qa + s * s], [2.0 * s * ws]
    brk = np.unique(np.concatenate(([q_m], inner[inner > q_m], [qb])))
    for lo, hi in zip(brk[:-1], brk[1:], strict=True):
        if hi <= lo * (1.0 + 1e-14):
            continue
        m = max(1, int(np.ceil(panels_per_decade * np.log10(hi / lo))))
        t, wt = _panels(np.linspace(np.log(lo), np.log(hi), m + 1), 10)
        parts_q.append(np.exp(t))
        parts_w.append(wt * np.exp(t))
    q = np.concatenate(parts_q)
    C = np.asarray(psd.C(q), dtype=float)  # type: ignore[attr-defined]
    dI3 = _delta_I3(psd, np.array([qa]), q)
    return _QRule(q, np.concatenate(parts_w), C, 1.0 / np.sqrt(np.pi * dI3), dI3)


def _delta_I3(
    psd: object,
    qa: NDArray[np.float64],
    q: NDArray[np.float64],
    i3: NDArray[np.float64] | None = None,
    i3a: NDArray[np.float64] | None = None,
) -> NDArray[np.float64]:
    """``int_{qa}^{q} q'^3 C dq'`` without cancellation for ``q`` close to ``qa``.

    ``qa`` broadcasts against ``q`` (e.g. one cut-off per row of nodes): ``I3(qa)`` is
    evaluated on ``qa``'s own elements (the same values as on the broadcast ones). ``i3``,
    ``i3a``: ``I3(q)``, ``I3(qa)`` [1] where the caller has them (the same numbers).
    """
    if i3 is None:
        i3 = np.asarray(psd.I3(q.ravel()), dtype=float).reshape(q.shape)  # type: ignore[attr-defined]
    if i3a is None:
        i3a = np.asarray(psd.I3(qa.ravel()), dtype=float).reshape(qa.shape)  # type: ignore[attr-defined]
    d = i3 - i3a
    qa = np.broadcast_to(qa, q.shape)
    dq = q - qa
    small = dq < 1e-6 * qa
    if np.any(small):
        qm = qa[small] + 0.5 * dq[small]
        d[small] = dq[small] * qm**3 * np.asarray(psd.C(qm), dtype=float)  # type: ignore[attr-defined]
    return np.maximum(d, np.finfo(float).tiny, out=d)


def _tau_c(psd: object, E_star: float, q: ArrayLike) -> NDArray[np.float64]:
    return 0.25 * np.pi * E_star**2 * np.asarray(psd.I3(q), dtype=float)  # type: ignore[attr-defined]


def _rows(spl: PPoly, knots: NDArray[np.float64], xq: NDArray[np.float64]) -> NDArray:
    """Evaluate a spline fitted along axis 1 of ``(n_load, n_knot)`` data at per-load points.

    ``xq`` has shape ``(n_load, ...)``; row ``l`` is evaluated with load ``l``'s polynomial
    pieces (clamped to the knots' range).
    """
    shape = xq.shape
    fn = kernel(xq.size * 16, "row_values")
    if fn is not None and spl.c.shape[1:] == (knots.size - 1, shape[0]):
        x2 = xq.reshape(shape[0], -1)
        if shape[0] > 1 and x2.strides[0] == 0:  # points shared by every load (broadcast):
            fn, x2 = kernel(0, "shared_row_values"), x2[0]  # each one's interval found once
        x2 = np.ascontiguousarray(x2)
        if not np.isnan(x2).any():  # one pass, the same bits
            out = np.empty((shape[0], x2.size) if x2.ndim == 1 else x2.shape)
            fn(spl.c, knots, x2, out)  # type: ignore[misc]
            return out.reshape(shape)
    x2 = np.clip(xq.reshape(shape[0], -1), knots[0], knots[-1])
    idx = np.clip(np.searchsorted(knots, x2, side="right") - 1, 0, knots.size - 2)
    c = spl.c  # (4, n_int, n_load)
    load = np.arange(shape[0])[:, None]
    d = x2 - knots[idx]
    val = ((c[0][idx, load] * d + c[1][idx, load]) * d + c[2][idx, load]) * d + c[3][idx, load]
    return val.reshape(shape)


def _spline_rows(spl: PPoly | None, sel: NDArray[np.intp]) -> PPoly | None:
    """The rows ``sel`` of a spline fitted along axis 1 of (n_row, n_knot) data (its
    coefficients ``c`` (4, n_int, n_row) sliced, contiguous)."""
    if spl is None:
        return None
    from scipy.interpolate import PPoly  # lazily: ~0.2 s to import

    c = np.ascontiguousarray(spl.c[:, :, sel])
    return PPoly.construct_fast(c, spl.x, extrapolate=spl.extrapolate, axis=1)


# -- the solved curve ---------------------------------------------------------------------------
#: A jump of ln(1 - F) between two nodes larger than this (a factor e^40) is not a smooth curve
#: but a solver's zero (below its absolute tolerance) next to a resolved value.
_LOG_JUMP = 40.0


def _log_spline(x: NDArray[np.float64], y: NDArray[np.float64]) -> PPoly:
    """Spline of ``y = ln(1 - F)`` per load (rows): cubic where the curve is smooth, monotone
    (PCHIP, no overshoot) for loads with a jump, where a cubic spline would ring up to
    ``1 - F = 1`` (a solver path returning exact zeros below its atol, e.g. ``cn``)."""
    from scipy.interpolate import PchipInterpolator  # lazily: ~0.2 s to import

    cubic = _row_spline(x, y)
    floor = y <= math.log(_TINY) + 1.0  # an exact zero next to a value 1 - F > e^-100: a
    resolved = y > -100.0  # solver's zero below its atol, not the curve passing the magnitudes
    # (such a pair is a jump of >= 589 > _LOG_JUMP in ln(1 - F): no test of the step itself)
    pair = (floor[:, :-1] & resolved[:, 1:]) | (resolved[:, :-1] & floor[:, 1:])
    jump = np.any(pair, axis=1)
    if not jump.any():
        return cubic
    mono = PchipInterpolator(x, y, axis=1)
    cubic.c = np.where(jump[None, None, :], mono.c, cubic.c)  # same layout, axis kept
    return cubic


class _Curve:
    """Per-load curve ``F = A S`` on ``zeta``, interpolated in ``x = ln zeta``.

    ``1 - F`` is represented by a cubic spline of ``ln(1 - F)`` on the nodes after the first
    (exact near full contact, where ``1 - F`` spans decades between nodes) and linearly on the
    first interval (``F(1) = 1``).
    """

    def __init__(
        self,
        zeta: ArrayLike,
        area: ArrayLike,
        s_factor: ArrayLike | None,
        non_area: ArrayLike | None,
    ) -> None:
        z = np.asarray(zeta, dtype=float)
        A = np.atleast_2d(np.asarray(area, dtype=float))
        if z.ndim != 1 or z.size < 2 or A.shape[-1] != z.size:
            raise ValueError(
                f"zeta must be 1-D with >= 2 magnifications and area (..., {z.size}); got "
                f"zeta {z.shape}, area {A.shape}"
            )
        if not (abs(z[0] - 1.0) < 1e-12 and np.all(np.diff(z) > 0)):
            raise ValueError("zeta must increase from 1 (the curve starts at full contact)")
        if A.size and not (A.min() >= 0.0 and A.max() <= 1.0):  # (NaN fails both)
            raise ValueError("area fractions must be finite and lie in [0, 1]")
        N = 1.0 - A if non_area is None else np.atleast_2d(np.asarray(non_area, dtype=float))
        S = None if s_factor is None else np.broadcast_to(s_factor, A.shape)
        if S is not None and S.size and not (S.min() > 0.0 and S.max() <= 1 + 1e-12):
            raise ValueError("s_factor must lie in (0, 1]")
        self.zeta = z
        self.x = np.log(z)
        self.area = A
        # kept as it is where already in [0, 1] (the solved curve's, clipped by its reader):
        # np.clip would copy it unchanged (-0.0 and NaN kept as they are)
        clipped = N.size and N.min() >= 0.0 and N.max() <= 1.0
        self.non_area = N if clipped else np.clip(N, 0.0, 1.0)
        self._S = S
        if S is None:  # 1 - F = 1 - A: its logarithm from the non-area, no (n_load, n) copies
            y = np.maximum(self.non_area, _TINY)
            y[:, 0] = _TINY  # 1 - F = 0 at zeta = 1
            self._nf1 = self.non_area[:, 1] + 0.0  # as non_area + A (1 - 1): -0 -> +0
        else:
            y = self.NF  # (a new array: clamped in place)
            self._nf1 = y[:, 1].copy()
            y = np.maximum(y, _TINY, out=y)
        y = np.log(y, out=y)
        # kept for the S spline's comparison only (1 - A is 1 - F without S)
        self._y = None if S is None else y
        self._dead = y[:, 1:] <= math.log(_TINY)  # 1 - F clamped at the spline's nodes
        self._spl = _log_spline(self.x[1:], y[:, 1:]) if z.size > 2 else None
        # the spline of ln(1 - A): the same as ln(1 - F)'s without S; else built on first use
        self._spl_a_built: Any = self._spl if S is None else False

    def rows(self, sel: NDArray[np.intp]) -> _Curve:
        """The curve of the loads ``sel`` (same magnifications): every per-load array and
        spline sliced, not rebuilt (each load's rows are its own: the same bits as a curve
        built for these loads alone)."""
        out = object.__new__(_Curve)
        out.zeta, out.x = self.zeta, self.x
        out.area, out.non_area, out._nf1 = self.area[sel], self.non_area[sel], self._nf1[sel]
        out._S = None if self._S is None else self._S[sel]
        out._y = None if self._y is None else self._y[sel]
        out._dead = self._dead[sel]
        out._spl = _spline_rows(self._spl, sel)
        a = self._spl_a_built  # ln(1 - A)'s spline: ln(1 - F)'s, not built yet, or its own
        out._spl_a_built = out._spl if a is self._spl else (a is not False and _spline_rows(a, sel))
        return out

    @property
    def F(self) -> NDArray[np.float64]:
        """``F = A S`` [1] at the nodes, (n_load, n_zeta)."""
        return self.area * (1.0 if self._S is None else self._S)

    @property
    def NF(self) -> NDArray[np.float64]:
        """``1 - F`` [1] at the nodes, (n_load, n_zeta) (0 at ``zeta = 1``)."""
        S = 1.0 if self._S is None else self._S
        nf = np.clip(self.non_area + self.area * (1.0 - S), 0.0, 1.0)
        nf[:, 0] = 0.0
        return nf

    @property
    def _spl_a(self) -> Any:
        """Spline of ``ln(1 - A)`` on the nodes after the first (built once, when first asked:
        only the detachment step needs it)."""
        if self._spl_a_built is False:
            yA = np.log(np.maximum(self.non_area, _TINY))
            if np.array_equal(yA[:, 1:], self._y[:, 1:]):  # type: ignore[index]  # S = 1
                self._spl_a_built = self._spl
            else:
                self._spl_a_built = (
                    _log_spline(self.x[1:], yA[:, 1:]) if self.zeta.size > 2 else None
                )
        return self._spl_a_built

    @property
    def n_load(self) -> int:
        return self.area.shape[0]

    def non_area_at(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """``1 - A`` at per-load points ``x = ln zeta`` of shape (n_load, ...)."""
        x = np.asarray(x, dtype=float)
        x1 = self.x[1]
        lin = self.non_area[:, 1].reshape((-1,) + (1,) * (x.ndim - 1)) * np.clip(x / x1, 0, 1)
        if self._spl_a is None:
            return lin
        val = _exp(np.minimum(_rows(self._spl_a, self.x[1:], x), 0.0))
        return np.clip(np.where(x < x1, lin, val), 0.0, 1.0)

    def nf(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """``1 - F`` at ``x = ln zeta`` (any shape), per load: shape ``(n_load,) + x.shape``."""
        x = np.asarray(x, dtype=float)
        x1 = self.x[1]
        lin = self._nf1.reshape((-1,) + (1,) * x.ndim) * np.clip(x / x1, 0.0, 1.0)
        if self._spl is None:
            return np.clip(lin, 0.0, 1.0)
        xs = np.clip(x, x1, self.x[-1])
        ys = np.minimum(self._spl(xs), 0.0)
        return np.where(x < x1, lin, _exp(ys))

    def dF(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """``-dF/dx`` (>= 0) at ``x = ln zeta``, per load."""
        x = np.asarray(x, dtype=float)
        x1 = self.x[1]
        lin = (self._nf1 / x1).reshape((-1,) + (1,) * x.ndim) * np.ones_like(x)
        if self._spl is None:
            return lin
        xs = np.clip(x, x1, self.x[-1])
        ys = np.minimum(self._spl(xs), 0.0)
        dys = np.maximum(self._spl(xs, 1), 0.0)
        return np.where(x < x1, lin, _exp(ys) * dys)

    def dF_weighted(
        self, weights: NDArray[np.float64], out: NDArray[np.float64] | None = None
    ) -> NDArray[np.float64]:
        """``sum_m dF[:, i, m] weights[i, m]`` (n_load, n_int): the node sums of the
        Stieltjes integrals, without keeping the (n_load, n_int, m) tensor (written into
        ``out`` if given)."""
        out = np.empty((self.n_load, weights.shape[0])) if out is None else out
        first = (self._nf1 / self.x[1])[:, None]  # the linear first interval
        if self._spl is not None and kernel(self.n_load * weights.size, "df_sums") is not None:
            return self._dF_compiled(weights, out, first)
        w_t = weights.T  # (m, n_int): the blocks' layout
        for k, start, vals in self._dF_blocks():
            if start:
                out[k, 0] = np.sum(first[k] * weights[0], axis=-1)
                out[k, 1:start] = 0.0
            vals *= w_t[:, start:]
            out[k, start:] = vals.sum(axis=1)  # in node order, as a sum over a last axis
        return out

    def _dF_compiled(
        self, weights: NDArray[np.float64], out: NDArray[np.float64], first: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        """:meth:`dF_weighted` (with the spline) by :func:`~._phi_sums.df_logs` and
        :func:`~._phi_sums.df_sums`, the blocks of :meth:`_dF_blocks` laid out (n, m, rows):
        ``ln(1 - F)`` at the nodes, numpy's ``exp`` of it in place (the only pass of numpy), then
        the slopes computed again in the sums (no slope tensor kept: the same bits)."""
        w_t = np.ascontiguousarray(weights.T)
        first_sums = np.sum(first * weights[0], axis=-1)  # (row sums: each row's own)
        xg, _ = self.stieltjes_nodes()
        own = _first_open_rows(self._dead)  # as in _dF_blocks
        j0 = int(own.min())
        d = np.ascontiguousarray((xg[1 + j0 :] - self.x[1 + j0 : -1, None]).T)  # local: (m, n)
        step = _block(xg.size)
        buf = np.empty(min(step, self.n_load) * d.size)  # ln(1 - F), then 1 - F, of a block
        c, logs, sums = self._spl.c, kernel(0, "df_logs"), kernel(0, "df_sums")  # type: ignore[union-attr]
        for i in range(0, self.n_load, step):
            k = slice(i, i + step)
            jb = int(own[k].min())  # this block's own (later) start
            shape = (d.shape[1] - (jb - j0), d.shape[0], len(range(self.n_load)[k]))
            y = buf[: math.prod(shape)].reshape(shape)
            if logs(c, jb, i, d, jb - j0, y) < _EXP_LO:  # type: ignore[misc]  # min of y
                _exp_inplace(y)
            else:  # (as _exp_inplace, without its pass for the minimum)
                np.exp(y, out=y)
            out[k, 0] = first_sums[k]
            out[k, 1 : 1 + jb] = 0.0
            sums(c, jb, i, d, jb - j0, own[k] - jb, y, w_t, 1 + jb, out)  # type: ignore[misc]
        return out

    def _dF_blocks(self) -> Any:
        """``(rows, start, dF[rows, start:])`` in cache-sized blocks of loads (see
        :meth:`dF_weighted`), each block laid out (rows, m, n_int - start): the long interval
        axis innermost (an inner axis of m = 6 nodes costs numpy a loop call per 6 values).
        For ``start > 0`` interval 0 is the linear first interval and the intervals
        ``1 .. start - 1`` are 0 (every load of the block in full contact)."""
        xg, _ = self.stieltjes_nodes()
        if self._spl is None:
            yield slice(0, self.n_load), 0, self.dF(xg).transpose(0, 2, 1)
            return
        dead = self._dead  # (n_load, n_node - 1): 1 - F clamped
        own = _first_open_rows(dead)  # each load's: its quiet intervals are 0 as it alone
        j0 = int(own.min())  # spline intervals before j0: negligible for every load
        d = np.ascontiguousarray((xg[1 + j0 :] - self.x[1 + j0 : -1, None]).T)  # local: (m, n)
        step = _block(xg.size)
        rows = min(step, self.n_load)
        buf = np.empty((2, rows * d.size))  # y and dy of every block
        cbuf = np.empty(4 * rows * d.shape[1])  # the block's coefficients, loads first
        for i in range(0, self.n_load, step):  # blocks of loads: temporaries stay in cache
            k = slice(i, i + step)
            jb = int(own[k].min())  # this block's own (later) start
            off = jb - j0
            ck = self._spl.c[:, j0 + off :, k]  # (4, n_int - 1 - jb, rows)
            db = d[:, off:]
            shape = (ck.shape[2], *db.shape)
            c = cbuf[: ck.size].reshape(ck.shape[2], 4, 1, ck.shape[1])
            np.copyto(c[:, :, 0, :], np.moveaxis(ck, -1, 0))
            c0, c1, c2, c3 = (c[:, j] for j in range(4))  # (rows, 1, n_int - 1 - jb)
            y = np.multiply(c0, db, out=buf[0, : math.prod(shape)].reshape(shape))
            y += c1
            y *= db
            y += c2
            y *= db
            y += c3
            np.minimum(y, 0.0, out=y)
            dy = np.multiply(3.0 * c0, db, out=buf[1, : y.size].reshape(shape))
            dy += 2.0 * c1
            dy *= db
            dy += c2
            np.maximum(dy, 0.0, out=dy)
            dy *= _exp_inplace(y)
            _quiet_rows(dy, own[k] - jb)
            yield k, 1 + jb, dy  # buffers reused by the next block: consumed before it

    def stieltjes_nodes(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Gauss-Legendre nodes ``x`` (n_int, m) and weights (n_int, m) per interval."""
        t, w = _gauss(_GL_ORDER)
        a, b = self.x[:-1, None], self.x[1:, None]
        return a + (b - a) * t, (b - a) * w


def _first_open_rows(dead: NDArray[np.bool_]) -> NDArray[np.intp]:
    """Per row (n_row,): the first spline interval of ``ln(1 - F)`` whose ``-dF`` is not
    negligible for that row alone.

    ``dead`` (n_row, n_node): ``1 - F`` clamped at 1e-300 (``ln`` = -690.8) at the spline's
    nodes. Near ``zeta = 1`` every load is in full contact (and at high load far beyond):
    ``-dF`` in an interval whose own nodes and both neighbours are clamped is below
    ``exp(-680)``, round-off against any Stieltjes sum (exactly 0 here, not computed). An
    interval is quiet for several rows together where it is quiet for each: their first open
    interval is the smallest of the rows'."""
    n = dead.shape[0]
    pad = np.concatenate((np.ones((n, 1), bool), dead, np.zeros((n, 1), bool)), axis=1)
    quiet = pad[:, :-3] & pad[:, 1:-2] & pad[:, 2:-1] & pad[:, 3:]
    return np.argmin(quiet, axis=1)


def _quiet_rows(dy: NDArray[np.float64], stop: NDArray[np.intp]) -> None:
    """Zero ``dy[r, :, :stop[r]]`` (a block's rows, intervals from the block's start): a row's
    intervals before its own first open one, 0 for it alone, are 0 in any block."""
    for r in np.flatnonzero(stop > 0):
        dy[r, :, : stop[r]] = 0.0


def _q_max(psd: object, zeta: NDArray[np.float64]) -> float:
    return min(float(psd.q_1), float(zeta[-1]) * float(psd.q_L))  # type: ignore[attr-defined]


def _loads(p0: ArrayLike, n_load: int) -> NDArray[np.float64]:
    p = np.atleast_1d(np.asarray(p0, dtype=float)).ravel()
    if p.size != n_load or np.any(~(p > 0)) or np.any(~np.isfinite(p)):
        raise ValueError(f"p0 must hold {n_load} finite positive pressures [Pa], got {p0!r}")
    return p


def _edges(cur: _Curve, zeta_edges: ArrayLike | None) -> tuple[NDArray, NDArray, NDArray]:
    """Bin edges with the contact area there (spline of ``ln(1 - A)`` between the nodes)."""
    if zeta_edges is None:
        return cur.zeta, cur.area, cur.non_area
    z = np.unique(np.clip(np.asarray(zeta_edges, dtype=float), 1.0, cur.zeta[-1]))
    if z[0] != 1.0 or z[-1] != cur.zeta[-1]:
        raise ValueError("zeta_edges must run from 1 to the curve's last magnification")
    x = np.log(z)
    N = cur.non_area_at(np.broadcast_to(x, (cur.n_load, x.size)))
    N = np.maximum.accumulate(N, axis=1)
    N[:, 0] = 0.0
    N[:, -1] = cur.non_area[:, -1]
    return z, 1.0 - N, N
