"""Output grids and the per-load ``G`` of a solve (pure numpy, SI units).

* :func:`pressure_grid`: the default pressure grid [Pa] on which the pressure PDF ``P`` is
  stored: from the lowest wall (0 Pa without adhesion) to the nominal load plus eight standard
  deviations of the diffused distribution, cut at an upper wall.
* :func:`persson_G`: Persson's ``G(zeta) = tau(zeta) / p0^2`` per (load, magnification).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

__all__ = ["pressure_grid", "persson_G", "wall_positions", "GridError"]


class GridError(ValueError):
    """The requested grid is empty (its upper end does not exceed its lower end)."""


def wall_positions(wall: Any, tau: np.ndarray) -> np.ndarray:
    """Positions [Pa] of a wall at the diffusion times ``tau`` [Pa^2] (one value for a wall
    at a constant position)."""
    pos = wall.position
    if callable(pos):
        return np.asarray(pos(tau.ravel()), float)
    return np.asarray([pos], float)


def pressure_grid(
    p0: np.ndarray,
    walls: Sequence[tuple[Any, Any]],
    tau_eff: np.ndarray,
    points: int,
    p_max: float | None = None,
) -> np.ndarray:
    """The default pressure grid [Pa] of a solve.

    Parameters
    ----------
    p0 : numpy.ndarray
        Nominal loads [Pa].
    walls : sequence of (lower, upper)
        The walls of every load (``upper`` may be None); a wall's ``position`` is a number
        [Pa] or a callable of the diffusion time [Pa^2].
    tau_eff : numpy.ndarray
        Effective diffusion time [Pa^2] per (load, magnification).
    points : int
        Number of grid points.
    p_max : float, optional
        Upper end [Pa] replacing the computed one.

    Returns
    -------
    numpy.ndarray
        ``points`` equally spaced pressures [Pa].

    Raises
    ------
    GridError
        The upper end does not exceed the lowest wall position.
    """
    tau_end = float(np.max(tau_eff[:, -1]))
    lo, hi = 0.0, float(np.max(p0)) + 8.0 * np.sqrt(2.0 * max(tau_end, 0.0))
    for lower, upper in walls:
        lo = min(lo, float(np.min(wall_positions(lower, tau_eff))))
        if upper is not None:
            hi = min(hi, float(np.max(wall_positions(upper, tau_eff))))
    if p_max is not None:
        hi = p_max
    if not hi > lo:
        raise GridError(f"must exceed the lower wall {lo:g} Pa")
    return np.linspace(lo, hi, points)


def persson_G(tau_c: np.ndarray, p0: np.ndarray) -> np.ndarray:
    """``G = tau / p0^2`` [1] per (p0, zeta) from ``tau`` [Pa^2] and ``p0`` [Pa]; ``inf`` at a
    zero load (adhesive boundaries)."""
    p2 = p0 * p0
    with np.errstate(divide="ignore", invalid="ignore"):
        G = tau_c[None, :] / p2[:, None]
    if p2.all():  # no 0/0 possible (every p0^2 nonzero; NaN counts as nonzero): G is final
        return G
    return np.where(np.isnan(G), np.inf, G)
