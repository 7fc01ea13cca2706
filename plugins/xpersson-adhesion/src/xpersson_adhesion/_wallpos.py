"""The adhesive wall's position as a function of diffusion time: the clipped PCHIP table of
sigma_a(tau), its onset times (where the wall starts to move) and :class:`DetachmentWall`, the
position callable given to ``Wall.absorbing``.

Two walls built from the same content (the same table key) compare equal, so the engine solves
the loads of a scene together whether the walls were asked once (``FastPaths(shared_walls=True)``)
or once per load (the plain path): both paths give the same numbers bit for bit.
"""

from __future__ import annotations

from collections.abc import Callable, Hashable
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from xpersson.engine import WallTable

try:  # the compiled loop behind PPoly.__call__ (called directly: see _ppoly_values)
    from scipy.interpolate._ppoly import evaluate as _ppoly_evaluate
except ImportError:  # pragma: no cover - another scipy layout: PPoly.__call__ then
    _ppoly_evaluate = None

__all__ = ["DetachmentWall", "onset_times", "starts_at_zero"]

Array = NDArray[np.float64]


def _ppoly_values(poly: Any, t: Array) -> Array:
    """``poly(t)`` of a one-dimensional scipy ``PPoly`` at the float times ``t``: its own
    compiled loop called directly (the same numbers; ``PPoly.__call__``'s checks and
    reshapes cost more than evaluating the few hundred times of a ``cn`` level), or
    ``poly(t)`` where the table is not such a PPoly."""
    c, x = getattr(poly, "_c", None), getattr(poly, "_x", None)
    extrapolate = getattr(poly, "extrapolate", None)
    plain = (
        _ppoly_evaluate is None
        or not isinstance(c, np.ndarray)
        or not isinstance(x, np.ndarray)
        or c.ndim != 2
        or c.dtype != np.float64
        or not c.flags.c_contiguous
        or extrapolate not in (True, False)
    )
    if plain:
        return np.asarray(poly(t), dtype=float)
    flat = np.ascontiguousarray(t.ravel(), dtype=np.float64)
    out = np.empty((flat.size, 1))
    _ppoly_evaluate(c.reshape(c.shape[0], c.shape[1], 1), x, flat, 0, bool(extrapolate), out)
    return out.reshape(t.shape)


class _Pchip:
    """Picklable clipped PCHIP evaluation ``tau [Pa^2] -> sigma_a [Pa]``."""

    def __init__(self, spline: Callable[[Array], Array], t_lo: float, t_hi: float) -> None:
        self.spline, self.t_lo, self.t_hi = spline, t_lo, t_hi
        self.onsets: Array | None = None  # see onset_times
        self.starts_at_zero: bool | None = None  # see starts_at_zero
        self._tables: tuple | None = None  # see wall_table

    def wall_table(self, negate: bool) -> WallTable | None:
        """This table (negated with ``negate``) as the engine's compiled wall protocol,
        :class:`xpersson.engine.WallTable` (built once), or None where the table is not a plain
        PPoly (then only the numpy path evaluates it)."""
        if self._tables is None:
            sp = self.spline
            root = type(sp) is _SqrtPos
            poly = sp.poly if root else sp
            c, x = getattr(poly, "_c", None), getattr(poly, "_x", None)
            ext = getattr(poly, "extrapolate", None)
            plain = (
                isinstance(c, np.ndarray)
                and isinstance(x, np.ndarray)
                and c.ndim == 2
                and c.dtype == np.float64
                and x.dtype == np.float64
                and ext in (True, False)
                and x.size == c.shape[1] + 1
                and x.size >= 2
                and bool(np.all(x[1:] > x[:-1]))  # one interval per time (see WallTable)
            )
            self._tables = (
                tuple(WallTable(c, x, self.t_lo, self.t_hi, bool(ext), root, n) for n in (0, 1))
                if plain
                else (None, None)
            )
        return self._tables[bool(negate)]

    def values(self, tau: ArrayLike, negate: bool) -> Array | None:
        """``self(tau)`` (``-self(tau)`` with ``negate``) by the engine's compiled loop, or
        None where it does not run (:meth:`xpersson.engine.WallTable.compiled`; the same
        numbers either way)."""
        table = self.wall_table(negate)
        return None if table is None else table.compiled(tau)

    def __call__(self, tau: ArrayLike) -> Array:
        found = self.values(tau, False)
        if found is not None:
            return found
        # np.clip's definition, without its dispatch
        t = np.minimum(np.maximum(np.asarray(tau, dtype=float), self.t_lo), self.t_hi)
        sp = self.spline
        if type(sp) is _SqrtPos:  # (the model's table: its PPoly evaluated directly)
            v = _ppoly_values(sp.poly, t)
            return np.sqrt(np.maximum(v, 0.0, out=v), out=v)
        return _ppoly_values(sp, t)


class _SqrtPos:
    """``sqrt(max(poly(t), 0))`` (picklable)."""

    def __init__(self, poly: Callable[[Array], Array]) -> None:
        self.poly = poly

    def __call__(self, t: ArrayLike) -> Array:
        return np.sqrt(np.maximum(np.asarray(self.poly(t), dtype=float), 0.0))


def onset_times(sigma_of_tau: Callable[[Array], Array]) -> Array:
    """Diffusion times [Pa^2] where the detachment stress leaves 0 (the wall starts moving).

    For the model (``sigma_a^2`` a piecewise cubic in tau, :meth:`ModelLaw.in_tau`): the roots
    of ``sigma_a^2`` where it turns positive, i.e. where gamma_eff crosses 0 and ``sigma_a``
    starts like ``sqrt(tau - tau_c)``.  For a table: the last node of each stretch of zeros.
    Given to the engine as the wall's ``breakpoints`` (graded steps after each).
    """
    if not isinstance(sigma_of_tau, _Pchip):
        return np.zeros(0)
    found = getattr(sigma_of_tau, "onsets", None)  # a table is immutable: found once
    if found is None:
        found = _onset_times(sigma_of_tau)
        found.setflags(write=False)
        sigma_of_tau.onsets = found
        sigma_of_tau.starts_at_zero = float(sigma_of_tau(np.zeros(1))[0]) == 0.0
    return found.copy()


def starts_at_zero(sigma_of_tau: Callable[[Array], Array]) -> bool:
    """Whether ``sigma_a(tau = 0) = 0`` [Pa] (the wall rests at ``p = 0`` until its first
    onset); of a table, found once with its onsets (:func:`onset_times`)."""
    if isinstance(sigma_of_tau, _Pchip):
        onset_times(sigma_of_tau)
        return bool(sigma_of_tau.starts_at_zero)
    return float(sigma_of_tau(np.zeros(1))[0]) == 0.0


def _onset_times(sigma_of_tau: _Pchip) -> Array:
    sp = sigma_of_tau.spline
    t_lo, t_hi = sigma_of_tau.t_lo, sigma_of_tau.t_hi
    if isinstance(sp, _SqrtPos):
        poly = sp.poly
        roots = _cubic_roots(poly)
        roots = roots[np.isfinite(roots) & (roots > t_lo) & (roots < t_hi)]
        span = t_hi - t_lo
        h = 1e-9 * span
        up = (poly(np.minimum(roots + h, t_hi)) > 0) & (poly(np.maximum(roots - h, t_lo)) <= 0)
        return np.unique(roots[up])
    x = np.asarray(getattr(sp, "x", []), dtype=float)
    if x.size < 2:
        return np.zeros(0)
    y = np.asarray(sp(x), dtype=float)
    start = (y[:-1] == 0) & (y[1:] > 0)
    return np.unique(x[:-1][start & (x[:-1] > t_lo)])


def _cubic_roots(poly: Any) -> Array:
    """Real roots of a piecewise polynomial (``PPoly.roots(extrapolate=False)``), solved only on
    the pieces that can hold one: for cubics, those whose minimum over the piece (ends and
    interior critical points) is <= 0 and maximum >= 0 (a 1000-piece table has ~1 such piece,
    and the full solve of every piece dominated the cost of building the wall)."""
    from scipy.interpolate import PPoly

    c, x = np.asarray(poly.c, dtype=float), np.asarray(poly.x, dtype=float)
    if c.ndim != 2 or c.shape[0] != 4:
        return np.asarray(poly.roots(extrapolate=False), dtype=float)
    h = np.diff(x)
    a3, a2, a1, a0 = c
    ts = [np.zeros_like(h), h]
    # critical points 3 a3 t^2 + 2 a2 t + a1 = 0 (clipped into the piece)
    disc = np.maximum(a2 * a2 - 3.0 * a3 * a1, 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        for sgn in (-1.0, 1.0):
            t = np.where(
                a3 != 0,
                (-a2 + sgn * np.sqrt(disc)) / (3.0 * a3),
                np.where(a2 != 0, -a1 / (2.0 * a2), 0.0),
            )
            ts.append(np.clip(np.nan_to_num(t), 0.0, h))
    vals = np.array([((a3 * t + a2) * t + a1) * t + a0 for t in ts])
    margin = 1e-9 * float(np.max(np.abs(vals))) if vals.size else 0.0
    cand = np.flatnonzero((vals.min(axis=0) <= margin) & (vals.max(axis=0) >= -margin))
    out = [
        np.asarray(PPoly(c[:, i : i + 1], x[i : i + 2]).roots(extrapolate=False), dtype=float)
        for i in cand
    ]
    return np.unique(np.concatenate(out)) if out else np.zeros(0)


class DetachmentWall:
    """Wall position ``p_w(tau) = -sigma_a(zeta(tau))`` [Pa] for ``Wall.absorbing``.

    Parameters
    ----------
    sigma_of_tau : callable, optional
        sigma_a as a function of tau [Pa^2 -> Pa] (table laws).
    law : callable, optional
        sigma_a as a function of zeta [1 -> Pa] (the model), with ``clock``.
    clock : DiffusionClock, optional
        Maps tau to zeta.
    key : hashable, optional
        The content the position derives from (e.g. the key of
        :meth:`ModelLaw.table_and_key`): two walls with equal keys are equal (and hash equal),
        so the engine groups their loads in one batch.
        Without a key a wall equals only itself.
    """

    def __init__(
        self,
        sigma_of_tau: Callable[[Array], Array] | None = None,
        law: Callable[[Array], Array] | None = None,
        clock: object | None = None,
        key: Hashable | None = None,
    ) -> None:
        self.sigma_of_tau = sigma_of_tau
        self.law = law
        self.clock = clock
        self.key = key

    def __eq__(self, other: object) -> bool:
        if self is other:
            return True
        if type(other) is not type(self) or self.key is None:
            return False
        return bool(self.key == other.key)  # type: ignore[attr-defined]

    def __hash__(self) -> int:
        return object.__hash__(self) if self.key is None else hash(self.key)

    def sigma(self, tau: ArrayLike) -> Array:
        """sigma_a [Pa] at diffusion times ``tau`` [Pa^2]."""
        t = np.asarray(tau, dtype=float)
        if self.sigma_of_tau is not None:
            return np.asarray(self.sigma_of_tau(t), dtype=float).reshape(t.shape)
        z = np.asarray(self.clock.zeta_of_tau(t), dtype=float)  # type: ignore[union-attr]
        z = np.clip(z, 1.0, self.clock.zeta_max)  # type: ignore[union-attr]
        return np.asarray(self.law(z), dtype=float).reshape(t.shape)  # type: ignore[misc]

    def wall_table(self) -> WallTable | None:
        """The position as the engine's compiled wall protocol (:class:`WallTable`), or None
        (a model law through its clock, or a table that is not a plain PPoly)."""
        sig = self.sigma_of_tau
        return sig.wall_table(True) if type(sig) is _Pchip else None

    def __call__(self, tau: ArrayLike) -> Array:
        sig = self.sigma_of_tau
        if type(sig) is _Pchip:  # the table's compiled loop, negated in it (when it runs)
            found = sig.values(tau, True)
            if found is not None:
                return found
        return -self.sigma(tau)
