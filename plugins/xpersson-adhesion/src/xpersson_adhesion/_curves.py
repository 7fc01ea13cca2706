"""The area curve a gap distribution is built from: its magnification grid.

``dmt`` (:mod:`.dmt`, :mod:`._dmt_batch`, :mod:`._dmt_reference`) and ``adhesive``
(:mod:`.adhesive`) sample the elastic area curve ``A(zeta)`` on :func:`curve_grid` and keep the
nodes where the diffusion time strictly increases (:func:`increasing`).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["curve_grid", "increasing"]


def curve_grid(zeta: np.ndarray, per_decade: int = 32) -> np.ndarray:
    """Magnifications of the area curve the gap distribution is built from [1].

    The output magnifications, ``1 + geomspace(1e-6, zeta_max - 1)`` (12 per decade: the fast
    change near zeta = 1 at small loads), ``per_decade`` log-spaced points and a tail
    ``zeta_max (1 - geomspace(1e-6, 0.3))`` (``3 per_decade / 4`` points) where the finer
    roughness ``h`` vanishes.

    Nodes closer than :data:`_MIN_LOG_STEP` in ``ln zeta`` are merged (the larger one is kept,
    so ``zeta_max`` stays the last node): the pieces above are built by different formulas, so
    the same magnification can come out a few ulps apart from two of them, and a pair like that
    has equal diffusion times and equal ``ln tau_c``, which the engine (strictly increasing
    ``tau_out``) and the gap distribution's splines (strictly increasing knots) refuse.
    """
    zmax = float(zeta[-1])
    if zmax <= 1.0:
        return np.array([1.0, 1.0 + 1e-9])
    dec = math.log10(zmax)
    z = np.concatenate(
        (
            [1.0],
            zeta,
            1.0 + np.geomspace(1e-6 * min(1.0, zmax - 1.0), zmax - 1.0, int(12 * (dec + 6)) + 2),
            np.geomspace(1.0, zmax, int(per_decade * dec) + 2),
            zmax * (1.0 - np.geomspace(1e-6, 0.3, max(4, 3 * per_decade // 4))),
        )
    )
    z = np.unique(z)
    return _separated(z[(z >= 1.0) & (z <= zmax)])


#: Smallest step in ``ln zeta`` between two nodes of the area curve [1].
_MIN_LOG_STEP = 1e-9


def _separated(z: np.ndarray) -> np.ndarray:
    """Sorted unique ``z`` (>= 1) thinned so that consecutive ``ln z`` differ by more than
    :data:`_MIN_LOG_STEP`; the first and the last node are kept."""
    if z.size < 3:
        return z
    s = np.log(z)
    keep = [z.size - 1]
    for i in range(z.size - 2, 0, -1):
        if s[keep[-1]] - s[i] > _MIN_LOG_STEP and s[i] - s[0] > _MIN_LOG_STEP:
            keep.append(i)
    keep.append(0)
    return z[keep[::-1]]


def increasing(z: np.ndarray, tau: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The (z, tau) pairs on which ``tau`` [Pa^2] strictly increases: a flat stretch (the
    spectrum numerically zero there, so the area does not change either) keeps its first node."""
    keep = np.concatenate(([True], np.diff(np.maximum.accumulate(tau)) > 0))
    return (z, tau) if keep.all() else (z[keep], tau[keep])
