"""``Phi(G)`` of the virtual-work mean gap (private): a spline per load and its look-up table.

``Phi(G) = int_0^G sqrt(G') (-dF)`` per load, a cubic spline in ``s = ln tau_c`` of the node
integrals of the solved curve (:class:`xpersson.physics._curve._Curve`), and its samples on a
uniform grid in ``s`` for the many look-ups of the sub-problems (:mod:`._subgap`). SI units.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from .. import _scratch
from ..cache import Cache
from ._compiled import kernel
from ._curve import _TINY, _Curve, _spline_rows, _tau_c
from ._fastnum import _EXP_ZERO, _exp, _ppoly_at, _row_spline

if TYPE_CHECKING:
    from scipy.interpolate import PPoly

#: Nodes of Phi = 0 (every load) kept in its look-up table before the first non-zero one.
_TABLE_MARGIN = 8


_PHI_WEIGHTS = Cache(
    "physics.phi_weights",
    scope="spectrum",
    maxsize=64,
    doc="Phi's Stieltjes weights on an area curve's nodes and tau_c at its magnifications",
)


def _phi_weights(
    psd: object, E_star: float, cur: _Curve
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """What ``Phi``'s node integrals take from the spectrum alone: the Stieltjes weights
    ``sqrt(tau_c) w`` on the curve's nodes (n_int, m) [Pa] and ``tau_c`` at the
    magnifications (n_zeta,) [Pa^2]."""
    q_L = float(psd.q_L)  # type: ignore[attr-defined]
    xg, wg = cur.stieltjes_nodes()
    sqrt_tau = np.sqrt(_tau_c(psd, E_star, np.exp(xg) * q_L))
    return sqrt_tau * wg, _tau_c(psd, E_star, cur.zeta * q_L)


class _Phi:
    """``Phi(G) = int_0^G sqrt(G') (-dF)`` per load as a spline in ``s = ln tau_c``."""

    def __init__(self, psd: object, E_star: float, p0: NDArray[np.float64], cur: _Curve) -> None:
        q_L = float(psd.q_L)  # type: ignore[attr-defined]
        key = (psd, float(E_star), q_L, cur.zeta)
        weights, tau = _PHI_WEIGHTS.get(key, lambda: _phi_weights(psd, E_star, cur))
        phi = np.empty((cur.n_load, weights.shape[0] + 1))  # (no temporaries: fresh pages
        phi[:, 0] = 0.0  # cost more than the arithmetic)
        inc = cur.dF_weighted(weights, out=phi[:, 1:])
        fn = kernel(inc.size * 8, "phi_cumsum")
        if fn is not None:  # (the same bits in one pass)
            fn(inc, p0)
        else:
            inc /= p0[:, None]
            np.cumsum(inc, axis=1, out=inc)
        self.tau1 = float(tau[1])
        self.s = np.log(tau[1:])
        self.phi = phi
        self.p0 = p0
        self._spl = _row_spline(self.s, phi[:, 1:]) if self.s.size > 1 else None
        self._tab: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None

    def rows(self, sel: NDArray[np.intp]) -> _Phi:
        """``Phi`` of the loads ``sel``: its node integrals and spline sliced, not rebuilt (each
        load's are its own: the same bits as built for these loads alone); its look-up table
        built when first asked, for these loads."""
        out = object.__new__(_Phi)
        out.tau1, out.s, out.phi, out.p0 = self.tau1, self.s, self.phi[sel], self.p0[sel]
        out._spl, out._tab = _spline_rows(self._spl, sel), None
        return out

    @property
    def has_table(self) -> bool:
        """Whether the look-ups go through the uniform table (a spline of >= 2 nodes)."""
        return self._spl is not None

    def at_tau(self, tau: NDArray[np.float64]) -> NDArray[np.float64]:
        """``Phi`` at ``G = tau/p0^2`` for every load (shared ``tau``): (n_load,) + tau.shape."""
        tau = np.asarray(tau, dtype=float)
        if self._spl is not None and tau.ndim == 1:
            return self._at_tau_1d(tau)
        lin = self.phi[:, 1].reshape((-1,) + (1,) * tau.ndim) * np.clip(tau / self.tau1, 0, 1)
        if self._spl is None:
            return lin
        s = np.clip(np.log(np.maximum(tau, _TINY)), self.s[0], self.s[-1])
        return np.where(tau < self.tau1, lin, np.maximum(self._spl(s), 0.0))

    def _at_tau_1d(self, tau: NDArray[np.float64]) -> NDArray[np.float64]:
        """:meth:`at_tau` of 1-D ``tau`` (bit for bit): the spline's values from its
        coefficients, written in the C order of ``self._spl(s)`` (the callers' matrix-vector
        products keep their summation order); the linear first interval where it applies."""
        s = np.clip(np.log(np.maximum(tau, _TINY)), self.s[0], self.s[-1])
        low = tau < self.tau1
        k = int(np.count_nonzero(low))
        if k and low[:k].all():  # the first k (the mean gap's rule: tau increasing): the
            # spline only past them (its values there were replaced), the rest a slice
            out = _scratch.empty((self.phi.shape[0], tau.size))  # (the callers' temporary)
            np.multiply(self.phi[:, 1:2], np.clip(tau[:k] / self.tau1, 0, 1), out=out[:, :k])
            _ppoly_at(self._spl, s[k:], out=out[:, k:])  # type: ignore[arg-type]
            return out
        out = _ppoly_at(self._spl, s)  # type: ignore[arg-type]
        if k:
            out[:, low] = self.phi[:, 1:2] * np.clip(tau[low] / self.tau1, 0, 1)
        return out

    def spline_at_log_tau_per_load(
        self, log_tau: NDArray[np.float64], rows: slice | NDArray
    ) -> NDArray[np.float64]:
        """:meth:`at_log_tau_per_load` from the spline itself, not its look-up table.

        The table's linear look-up is within ~1e-6 of the spline but not smooth in the
        argument; a difference quotient of two look-ups (``separation_at``) magnifies that to
        1e-4-1e-3. Here each value is the spline's (clipped at 0, constant beyond its last
        knot), the linear first interval as there.
        """
        shape = log_tau.shape
        l2 = log_tau.reshape(shape[0], -1)
        if isinstance(rows, slice):
            rows = np.arange(self.phi.shape[0])[rows]
        phi1 = self.phi[rows, 1:2]
        log_tau1 = math.log(self.tau1)
        t = _exp(np.minimum(l2, log_tau1))
        lin = phi1 * np.clip(t / self.tau1, 0.0, 1.0)
        if self._spl is None:
            return lin.reshape(shape)
        b, c = self._spl.x, self._spl.c  # (4, n - 1, n_load)
        s = np.clip(l2, b[0], b[-1])
        k = np.clip(np.searchsorted(b, s, side="right") - 1, 0, b.size - 2)
        d = s - b[k]
        r = np.asarray(rows)[:, None]
        val = ((c[0][k, r] * d + c[1][k, r]) * d + c[2][k, r]) * d + c[3][k, r]
        np.maximum(val, 0.0, out=val)
        return np.where(l2 < log_tau1, lin, val).reshape(shape)

    def at_log_tau_per_load(
        self, log_tau: NDArray[np.float64], rows: slice | NDArray, overwrite: bool = False
    ) -> NDArray:
        """``Phi`` at per-load ``ln tau`` of shape (n_rows, ...) for the loads ``rows``
        (uniform-table look-up, linear below ``tau1``); ``rows`` a slice of the loads or one
        load index per row. ``overwrite``: ``log_tau`` is a temporary of the caller and may be
        used as scratch space.
        """
        shape = log_tau.shape
        l2 = log_tau.reshape(shape[0], -1)
        phi1 = self.phi[rows, 1:2]
        if self._spl is None:
            t = _exp(np.minimum(l2, math.log(self.tau1)))
            return (phi1 * np.clip(t / self.tau1, 0.0, 1.0)).reshape(shape)
        grid, table = self._table()
        n, lo, width = grid.size, self._lo, table.shape[1]
        phi1_zero = not np.any(phi1)
        quiet = phi1_zero and self._first_zero  # below the grid: u = 0 at node 0, val = 0
        u = np.subtract(l2, grid[0], out=l2 if quiet and overwrite else None)
        u *= 1.0 / (grid[1] - grid[0])
        np.clip(u, lo, n - 1.000001, out=u)  # below node lo + 1 the table is 0: same values
        i = u.astype(np.intp)
        u -= i
        if isinstance(rows, slice):
            rows = np.arange(rows.start or 0, (rows.start or 0) + shape[0])
        i += (rows * width - lo)[:, None]  # node i of load l at l width + i - lo
        flat = table.ravel()
        v0 = flat.take(i)
        val = flat[1:].take(i)  # the next nodes, without an array i + 1
        val -= v0
        val *= u
        val += v0
        if quiet:  # the masked copy of 0 below would change nothing
            return val.reshape(shape)
        log_tau1 = math.log(self.tau1)
        low = l2 < log_tau1
        if phi1_zero:  # the linear first interval is 0 (every load in full contact
            np.copyto(val, 0.0, where=low)  # at the first node: the dense grid's 1 + 1e-9)
        elif low.any():  # the linear first interval; its exp where it applies only (as _exp)
            t = np.zeros(l2.shape)
            np.exp(l2, out=t, where=low & (l2 > _EXP_ZERO))
            t /= self.tau1
            np.clip(t, 0.0, 1.0, out=t)
            t *= phi1
            np.copyto(val, t, where=low)
        return val.reshape(shape)

    def _table(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The spline sampled on a uniform grid in ``s`` (linear look-up error ~1e-6).

        ``(grid, table)``: the table (n_load, n_grid - lo) holds the grid's nodes from ``lo =
        self._lo`` on (those below are 0 for every load), loads by rows (each load's look-ups
        read its own contiguous row: the per-load look-ups from its flat view, the compiled
        sums of :mod:`._subgap` and :meth:`sums_at_log_tau`), evaluated from the spline's
        coefficients (as ``self._spl(grid)``, bit for bit). One layout only: a transposed
        copy for the other cost ~0.7 ms at 100 loads (a table beyond the L2 cache).
        """
        if getattr(self, "_tab", None) is None:
            n = int(min(8192, max(1024, 64 * (self.s[-1] - self.s[0]))))
            grid = np.linspace(self.s[0], self.s[-1], n)
            # Phi = 0 at the nodes where every load is in full contact (the dense grid's first
            # nodes); the table is evaluated from _TABLE_MARGIN such nodes before the first
            # non-zero one and is 0 below (the spline's values there are its ringing between
            # zeros, below 1e-30 of Phi: round-off in any look-up); the batch's first non-zero
            # node is the first of its loads' own (theirs: below, for _own_zeros)
            nz = self.phi[:, 1:] != 0.0
            has, first = nz.any(axis=1), np.argmax(nz, axis=1)
            j = max(0, int(first[has].min()) - _TABLE_MARGIN) if has.any() else 0
            g0 = int(np.searchsorted(grid, self.s[j], side="left"))
            # kept from grid node lo = g0 - 2 on: a look-up below it is clipped to node lo, where
            # it takes 0 + 0 (0 - 0), the 0 it took from the zero nodes below (bit for bit)
            lo = max(g0 - 2, 0)
            tab = _scratch.empty((self.phi.shape[0], n - lo))  # (loads, nodes; kept pages)
            zero = self._own_zeros(grid, g0, lo, np.where(has, first, 0))  # as the load alone
            if not _compiled_table(self._spl, grid[g0:], tab, g0 - lo, zero):  # has them
                tab[:, : g0 - lo] = 0.0
                _ppoly_at(self._spl, grid[g0:], out=tab[:, g0 - lo :])  # type: ignore[arg-type]
                for k in np.flatnonzero(zero > g0 - lo):
                    tab[k, : zero[k]] = 0.0
            self._tab, self._lo, self._g0 = (grid, tab), lo, g0
            # every load's node lo is 0 and node lo + 1 finite: a look-up below gives +0.0
            self._first_zero = bool(np.all(tab[:, 0] == 0.0) and np.all(np.isfinite(tab[:, 1])))
        return self._tab

    def _own_zeros(
        self, grid: NDArray[np.float64], g0: int, lo: int, j: NDArray[np.intp]
    ) -> NDArray[np.intp]:
        """Per load, the table's first column (from node ``lo``) not 0 for that load alone:
        ``g0 - lo`` (the batch's) or, where later, the load's own first non-zero node ``j``
        (0 for a load without) less the margin (the batch's first non-zero node is then an
        earlier load's): its columns below are 0, a load's look-ups never depend on the other
        loads."""
        zero = np.full(self.phi.shape[0], g0 - lo, dtype=np.intp)
        if self.phi.shape[0] < 2:
            return zero
        g = np.searchsorted(grid, self.s[np.maximum(j - _TABLE_MARGIN, 0)], side="left")
        return np.maximum(zero, g - lo)

    def sums_at_log_tau(
        self,
        log_tau: NDArray[np.float64],
        kern: NDArray[np.float64],
        need: NDArray[np.bool_] | None = None,
    ) -> NDArray[np.float64]:
        """``sum_m kern[k, m] Phi_l(ln tau = log_tau[k, m])`` for every load ``l``: (n_load, K).

        For arguments shared by every load (a sub-problem in full contact, ``A_a = 1``): the
        look-up positions are found once, and the sums of all loads are one sparse product of
        the interpolation weights with the table, ``kern (1 - u) T[i] + kern u T[i + 1]``: the
        linear look-up of :meth:`at_log_tau_per_load` up to round-off (~1e-16 relative; the
        terms are >= 0). Table nodes that are 0 for every load are left out. ``need``
        (n_load, K): the entries asked for (the others' values unspecified; each entry's sum
        is the same whichever others are asked for).
        """
        out = self._kernel_sums(log_tau, kern, need)
        if out is None:
            out = self._sparse_sums(log_tau, kern)
        phi1 = self.phi[:, 1:2]
        low = log_tau < math.log(self.tau1)  # the linear first interval
        if low.any() and np.any(phi1):
            t = np.zeros(log_tau.shape)
            np.exp(log_tau, out=t, where=low & (log_tau > _EXP_ZERO))
            t /= self.tau1
            np.clip(t, 0.0, 1.0, out=t)
            out += phi1 * np.sum(kern * t, axis=-1)
        return out

    def _kernel_sums(
        self,
        log_tau: NDArray[np.float64],
        kern: NDArray[np.float64],
        need: NDArray[np.bool_] | None = None,
    ) -> NDArray[np.float64] | None:
        """:meth:`_sparse_sums` by the compiled :func:`~._phi_sums.table_sums` (its bits,
        without the CSR matrix's ~0.1 ms of construction per call); None where not built or
        an argument is not finite."""
        grid, tab = self._table()
        fn = kernel(tab.size, "table_sums")
        if fn is None or kern.shape != log_tau.shape or not np.all(np.isfinite(log_tau)):
            return None
        inv = 1.0 / (grid[1] - grid[0])
        at = np.array([grid[0], inv, self._lo, grid.size - 1.000001, self._g0], dtype=float)
        out = np.empty((tab.shape[0], log_tau.shape[0]))
        need = np.ones(out.shape, dtype=bool) if need is None else np.ascontiguousarray(need)
        fn(np.ascontiguousarray(log_tau), np.ascontiguousarray(kern), tab, at,
           math.log(self.tau1), out, need)  # fmt: skip
        return out

    def _sparse_sums(
        self, log_tau: NDArray[np.float64], kern: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        """The table part of :meth:`sums_at_log_tau` as one sparse product (n_load, K)."""
        from scipy.sparse import csr_array  # lazily (imported with scipy.interpolate)

        grid, tab = self._table()
        n, lo = grid.size, self._lo
        u = np.subtract(log_tau, grid[0])
        u *= 1.0 / (grid[1] - grid[0])
        np.clip(u, lo, n - 1.000001, out=u)
        i = u.astype(np.intp)
        u -= i
        low = log_tau < math.log(self.tau1)  # the linear first interval, added below
        keep = ~low & (i + 1 >= self._g0)  # nodes i, i + 1 not both 0 for every load
        w1 = kern[keep] * u[keep]
        data = np.stack((kern[keep] - w1, w1), axis=-1).ravel()
        col = i[keep] - lo
        cols = np.stack((col, col + 1), axis=-1).ravel()
        ptr = np.concatenate(([0], np.cumsum(2 * np.count_nonzero(keep, axis=1))))
        w = csr_array((data, cols, ptr), shape=(log_tau.shape[0], tab.shape[1]))
        return np.ascontiguousarray((w @ tab.T).T)  # (scipy multiplies a C-ordered copy)


def _compiled_table(
    spl: PPoly, xs: NDArray[np.float64], tab: NDArray[np.float64], col0: int, zero: NDArray
) -> bool:
    """:meth:`_Phi._table`'s values by the compiled :func:`~._phi_sums.table_values`: the
    spline at ``xs`` (the grid from node ``g0`` on: columns ``col0`` on of ``tab``) as
    :func:`~._fastnum._ppoly_at` (its bits), each load's columns below ``zero`` 0 and not
    evaluated; False (nothing written) where the kernel is not built or off."""
    c = spl.c
    fn = kernel(c.shape[2] * xs.size, "table_values")
    if fn is None or not c.flags.c_contiguous:
        return False
    b = spl.x
    i = np.clip(np.searchsorted(b, xs, side="right") - 1, 0, b.size - 2)
    fn(c, i, xs - b[i], tab, col0, zero)
    return True
