"""Wall descriptions for the diffusion engine (positions in Pa, diffusion time tau in Pa^2)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._wall_table import WallTable

PositionLike = float | Callable[[NDArray[np.float64]], ArrayLike]

__all__ = ["Wall"]


@dataclass(frozen=True)
class Wall:
    """A boundary of the diffusion domain.

    Build walls with the class methods :meth:`absorbing`, :meth:`linear`,
    :meth:`yield_closure` and :meth:`reflecting`; pass ``None`` instead of a wall for an open
    upper side.  :func:`~xpersson.engine.solve` takes absorbing and yield walls;
    :func:`~xpersson.engine.solve_sourced` takes a reflecting lower wall.

    Attributes
    ----------
    kind : {"absorbing", "yield_closure", "reflecting"}
        Boundary condition.
    position : float or callable
        Wall position [Pa]; a callable maps diffusion time tau [Pa^2] (numpy array) to positions.
    dposition : callable or None
        ``dY/dtau`` [1/Pa] for the yield closure wall.
    motion : tuple of float or None
        ``(p_start, velocity)`` [Pa, 1/Pa] when the motion is known to be
        ``p = p_start + velocity * tau`` (enables the exact path of
        :doc:`/theory/03_absorbing_wall`).
    breakpoints : tuple of float
        Diffusion times [Pa^2] where the motion is not smooth: the wall starts moving, has a
        kink, or leaves a position with a square-root onset ``p ~ sqrt(tau - tau_b)``
        (unbounded speed).  Optional; the ``cn`` path makes them step boundaries, grades its
        steps after each one (uniform in ``(tau - tau_b)^(1/4)``) and moves its mesh with the
        steps' chord speeds from the first one on, which keeps it second order across them.
    still_until : float
        Diffusion time [Pa^2] up to which a moving absorbing wall stays at its position at
        ``tau = 0`` (0: not declared; a wall whose motion starts at an onset).  The ``cn`` path
        then starts from the one-wall closed form (the image solution) at that time, or where
        the other wall enters the window if earlier, instead of marching the fixed-wall stretch.
    kinks : tuple of float
        Diffusion times [Pa^2] where a smooth (C^1) motion's speed has a kink (e.g. at the
        knee of a roll-off spectrum, through the clock).  The ``cn`` path makes them step
        boundaries: a kink inside a step leaves an error that is irregular in the step, which
        Richardson extrapolation cannot cancel.
    table : WallTable or None
        The moving position as a clipped piecewise polynomial (the compiled wall protocol,
        :class:`~xpersson.engine.WallTable`), equal to ``position``: where the compiled code
        runs, the engine evaluates the table itself (positions and window-edge kinks) instead
        of calling ``position``. Optional; not part of the wall's equality.
    """

    kind: Literal["absorbing", "yield_closure", "reflecting"]
    position: PositionLike
    dposition: Callable[[NDArray[np.float64]], ArrayLike] | None = None
    motion: tuple[float, float] | None = None
    breakpoints: tuple[float, ...] = ()
    still_until: float = 0.0
    kinks: tuple[float, ...] = ()
    table: WallTable | None = field(default=None, compare=False, repr=False)

    # -- constructors ------------------------------------------------------------------------
    @classmethod
    def absorbing(
        cls,
        position: PositionLike,
        breakpoints: ArrayLike = (),
        still_until: float = 0.0,
        table: WallTable | None = None,
    ) -> Wall:
        """Absorbing wall: ``P = 0`` at the wall, the mass reaching it is absorbed (counted).

        Parameters
        ----------
        position : float or callable
            Fixed position [Pa], or a vectorised callable ``tau [Pa^2] -> p [Pa]`` (prescribed
            motion).
        breakpoints : array_like of float, optional
            Diffusion times [Pa^2] > 0 where a moving wall's motion is not smooth (see the class
            attributes); ignored for a fixed wall.
        still_until : float, optional
            Diffusion time [Pa^2] >= 0 up to which a moving wall stays at its position at
            ``tau = 0`` (see the class attributes); ignored for a fixed wall.
        table : WallTable, optional
            The same motion as a clipped piecewise polynomial (see the class attributes),
            evaluated by the engine in compiled code; ignored for a fixed wall.
        """
        if not callable(position):
            return cls("absorbing", float(position))
        still = float(still_until)
        if not still >= 0.0:
            raise ValueError(f"still_until [Pa^2] must be >= 0; got {still_until!r}")
        if table is not None and not isinstance(table, WallTable):
            raise ValueError(f"table of a wall must be a WallTable or None; got {table!r}")
        bps = _breakpoints(breakpoints)
        return cls("absorbing", position, breakpoints=bps, still_until=still, table=table)

    @classmethod
    def reflecting(cls, position: float = 0.0) -> Wall:
        """Fixed reflecting wall: zero flux ``dP/dp = 0``, no mass leaves (no re-contact).

        Parameters
        ----------
        position : float
            Fixed, finite position [Pa] (or the unit of the caller's coordinate).
        """
        try:
            position = float(position)
        except (TypeError, ValueError):
            raise ValueError(
                f"position [Pa] of a reflecting wall must be a finite float; got {position!r}"
            ) from None
        if not np.isfinite(position):
            raise ValueError(f"position [Pa] of a reflecting wall must be finite; got {position!r}")
        return cls("reflecting", position)

    @classmethod
    def linear(cls, p_start: float, velocity: float) -> Wall:
        """Absorbing wall moving as ``p_w(tau) = p_start + velocity * tau``.

        Parameters
        ----------
        p_start : float
            Position at tau = 0 [Pa].
        velocity : float
            ``dp_w/dtau`` [1/Pa].  A lower wall ``-(s0 + c tau)`` is ``linear(-s0, -c)``.
        """
        p_start, velocity = float(p_start), float(velocity)
        if velocity == 0.0:
            return cls("absorbing", p_start)

        def pos(tau: NDArray[np.float64]) -> NDArray[np.float64]:
            return p_start + velocity * np.asarray(tau, dtype=float)

        return cls("absorbing", pos, None, (p_start, velocity))

    @classmethod
    def yield_closure(
        cls,
        position: PositionLike,
        dposition: Callable[[NDArray[np.float64]], ArrayLike] | None = None,
        kinks: ArrayLike = (),
    ) -> Wall:
        """Moving yield wall (Lambert 2025), upper walls only.

        ``P(Y, tau) = A_pl(tau) dY/dtau`` and ``dA_pl/dtau = -dY/dtau P(Y) - dP/dp(Y)``
        (:cite:p:`lambert2025` in diffusion time).  For ``dY/dtau -> 0`` this is the absorbing wall
        ``P(Y) = 0`` with ``A_pl`` the probability absorbed there.

        Parameters
        ----------
        position : float or callable
            ``Y(tau)`` [Pa], non-decreasing.
        dposition : callable, optional
            ``dY/dtau`` [1/Pa] (>= 0), vectorised.  Required when ``position`` is a callable.
        kinks : array_like of float, optional
            Diffusion times [Pa^2] > 0 where ``dY/dtau`` has a kink (see the class
            attributes); ignored for a fixed wall.
        """
        if not callable(position):
            return cls("yield_closure", float(position), None)
        if dposition is None:
            raise ValueError(
                "dposition: a moving yield wall needs dY/dtau [1/Pa] (>= 0) as a callable"
            )
        return cls("yield_closure", position, dposition, kinks=_breakpoints(kinks, "kinks"))

    def with_breakpoints(self, breakpoints: ArrayLike) -> Wall:
        """The same wall with ``breakpoints`` [Pa^2] declared (see the class attributes)."""
        return replace(self, breakpoints=_breakpoints(breakpoints))

    # -- evaluation --------------------------------------------------------------------------
    @property
    def is_fixed(self) -> bool:
        """True when the position is a constant."""
        return not callable(self.position)

    def at(self, tau: ArrayLike) -> NDArray[np.float64]:
        """Positions [Pa] at diffusion times ``tau`` [Pa^2] (same shape as ``tau``)."""
        t = np.asarray(tau, dtype=float)
        if self.table is not None and callable(self.position):  # the compiled wall protocol,
            found = self.table.compiled(t)  # where the compiled code runs
            if found is not None:
                return found
        if self.is_fixed:
            return np.full(t.shape, float(self.position))
        out = np.asarray(self.position(t), dtype=float)
        if out.shape == t.shape:
            return out.copy()  # (a copy: the callable may return an array it keeps)
        return np.broadcast_to(out, t.shape).astype(float, copy=True)

    def speed(self, tau: ArrayLike) -> NDArray[np.float64]:
        """``dY/dtau`` [1/Pa] of a yield closure wall (0 for fixed walls)."""
        t = np.asarray(tau, dtype=float)
        if self.is_fixed or self.dposition is None:
            return np.zeros(t.shape)
        out = np.asarray(self.dposition(t), dtype=float)
        return np.broadcast_to(out, t.shape).astype(float, copy=True)

    @property
    def acts_absorbing(self) -> bool:
        """True when the wall is ``P = 0`` at all times (absorbing, or a fixed yield wall)."""
        return self.kind == "absorbing" or (self.kind == "yield_closure" and self.is_fixed)

    def linear_motion(self, tau_max: float) -> tuple[float, float] | None:
        """``(p_start, velocity)`` if the wall is absorbing and moves linearly, else None.

        Walls built with :meth:`linear` declare it; other callables are probed at 257 times on
        ``[0, tau_max]`` and accepted only if affine to 1e-13 relative.
        """
        if self.kind != "absorbing" or self.is_fixed:
            return None
        if self.motion is not None:
            return self.motion
        t = np.concatenate([np.linspace(0.0, tau_max, 129), tau_max * np.logspace(-12, 0, 128)])
        y = self.at(t)
        if not np.all(np.isfinite(y)) or tau_max <= 0:
            return None
        v = (y[128] - y[0]) / tau_max
        resid = y - (y[0] + v * t)
        scale = max(np.max(np.abs(y)), abs(v) * tau_max, 1e-300)
        if np.max(np.abs(resid)) <= 1e-13 * scale:
            return float(y[0]), float(v)
        return None


def _breakpoints(values: ArrayLike, name: str = "breakpoints") -> tuple[float, ...]:
    """Sorted, unique, finite, positive diffusion times [Pa^2] (ValueError naming ``name``
    otherwise)."""
    if isinstance(values, tuple | list) and not values:
        return ()  # (no breakpoints, the common case: without numpy's calls, ~6 us)
    if type(values) is np.ndarray and values.size == 0:
        return ()  # (the same, given as an empty array: e.g. a wall without onsets)
    b = np.atleast_1d(np.asarray(values, dtype=float)).ravel()
    if b.size and not (np.all(np.isfinite(b)) and np.all(b > 0)):
        raise ValueError(
            f"{name} [Pa^2] of a wall must be finite diffusion times > 0; got {b.tolist()}"
        )
    return tuple(float(t) for t in np.unique(b))
