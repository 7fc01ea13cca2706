"""Gap distribution as a diffusion equation in magnification (physics.md §5.5b).

For ``g > 0`` write ``P(g, zeta) = (A(zeta)/A0) delta(g) + rho(g, zeta)``; then

.. math::

    \\partial_\\zeta \\rho = b(\\zeta)\\, \\partial_g^2 \\rho
        + [-A'(\\zeta)/A_0]\\, \\delta(g - u_1(\\zeta)), \\qquad b = \\pi q_L q C(q),

with ``rho(g, 1) = 0``, a *reflecting* wall ``d rho/dg = 0`` at ``g = 0`` (no re-contact) and
``rho -> 0`` far away. In the diffusion time ``s = int b dzeta = (h_rms^2 - h^2(zeta))/2`` [m^2]
the equation is the plain heat equation ``d rho/ds = d^2 rho/dg^2`` plus injections.

:func:`diffuse_with_injection` is a small, self-contained implicit solver written so that it can
move into :mod:`xpersson.engine` (which offers absorbing and yield walls only): it knows nothing
about contact mechanics, only a uniform grid, a reflecting lower wall, an absorbing far wall, a
schedule of diffusion times and point injections (mass, position) per right-hand side.

Scheme: finite volumes (exactly conservative; the reflecting wall is a zero-flux face),
Crank-Nicolson in ``s`` with Rannacher start-up (the first steps after the first injection are
replaced by two implicit-Euler half steps each), one banded solve per step for all loads at once.
Each bin's mass is injected at the bin's mid time, i.e. as the exact image-pair Gaussian of
variance ``s_{k+1} - s_k`` (half a step of diffusion), cell-averaged with ``erf`` so the
injected discrete mass is exact; CN therefore only ever acts on data resolved by the step.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.linalg import solve_banded
from scipy.special import erf

__all__ = ["diffuse_with_injection", "DiffusionResult"]


class DiffusionResult:
    """Solution of :func:`diffuse_with_injection`.

    Attributes
    ----------
    g : ndarray, (n_g,)
        Grid [m] (last node is the absorbing far wall, ``rho = 0``).
    rho : ndarray, (n_rhs, n_g)
        Density at the final time [1/m].
    mass : ndarray, (n_rhs,)
        Discrete mass ``sum V_i rho_i`` at the final time [1].
    injected : ndarray, (n_rhs,)
        Mass injected inside the domain [1].
    skipped : ndarray, (n_rhs,)
        Mass of injections beyond the far wall (not injected) [1].
    steps : int
        Number of linear solves.
    """

    def __init__(self, g, rho, mass, injected, skipped, steps):  # noqa: ANN001
        self.g, self.rho, self.mass = g, rho, mass
        self.injected, self.skipped, self.steps = injected, skipped, steps


def _cell_masses(
    edges: NDArray[np.float64], pos: NDArray[np.float64], sig: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Mass of the image pair N(pos, sig) + N(-pos, sig) in each cell, (n_rhs, n_cell)."""
    e = edges[None, :]
    p, s = pos[:, None], np.maximum(sig, 1e-300)[:, None]
    cdf = 0.5 * (erf((e - p) / (math.sqrt(2.0) * s)) + erf((e + p) / (math.sqrt(2.0) * s)))
    return np.diff(cdf, axis=1)


def diffuse_with_injection(
    g_max: float,
    n_g: int,
    s_edges: ArrayLike,
    inj_pos: ArrayLike,
    inj_mass: ArrayLike,
    *,
    rannacher: int = 2,
    max_step: float | None = None,
) -> DiffusionResult:
    """Solve ``rho_s = rho_gg`` on ``[0, g_max]`` with point injections.

    Parameters
    ----------
    g_max : float
        Far wall [m] (absorbing, ``rho = 0``); choose it many widths beyond the mass.
    n_g : int
        Number of grid intervals (uniform spacing ``g_max / n_g``).
    s_edges : array_like, (n_bin + 1,)
        Non-decreasing diffusion times [m^2] bounding the injection bins.
    inj_pos : array_like, (n_rhs, n_bin)
        Injection positions [m] (>= 0) per right-hand side and bin.
    inj_mass : array_like, (n_rhs, n_bin)
        Injected masses [1] (>= 0).
    rannacher : int
        Number of start-up steps done as two implicit-Euler half steps.
    max_step : float, optional
        Largest diffusion-time step [m^2]; longer bins are split (default: no limit).

    Returns
    -------
    DiffusionResult
    """
    s_edges = np.asarray(s_edges, dtype=float)
    pos = np.atleast_2d(np.asarray(inj_pos, dtype=float))
    mass = np.atleast_2d(np.asarray(inj_mass, dtype=float))
    n_rhs, n_bin = mass.shape
    dg = g_max / n_g
    g = np.linspace(0.0, g_max, n_g + 1)
    n = n_g  # unknowns at nodes 0..n_g-1; node n_g is the far wall
    vol = np.full(n, dg)
    vol[0] = 0.5 * dg
    edges = np.concatenate(([0.0], 0.5 * (g[:-2] + g[1:-1]), [g_max - 0.5 * dg]))
    # L (finite volume, flux (rho_{i+1} - rho_i)/dg, zero flux at g = 0)
    up = np.full(n, 1.0 / dg**2)
    up[0] = 2.0 / dg**2  # node 0: half cell
    lo = np.full(n, 1.0 / dg**2)
    diag = np.full(n, -2.0 / dg**2)

    def apply_L(r: NDArray[np.float64]) -> NDArray[np.float64]:
        out = diag[:, None] * r
        out[:-1] += up[:-1, None] * r[1:]
        out[1:] += lo[1:, None] * r[:-1]
        return out

    def implicit(r: NDArray[np.float64], theta_dt: float) -> NDArray[np.float64]:
        ab = np.zeros((3, n))
        ab[0, 1:] = -theta_dt * up[:-1]
        ab[1] = 1.0 - theta_dt * diag
        ab[2, :-1] = -theta_dt * lo[1:]
        return solve_banded((1, 1), ab, r, check_finite=False)

    rho = np.zeros((n, n_rhs))
    started, startup_left, steps = False, rannacher, 0
    injected = np.zeros(n_rhs)
    skipped = np.zeros(n_rhs)
    for k in range(n_bin):
        ds = float(s_edges[k + 1] - s_edges[k])
        m = max(1, math.ceil(ds / max_step)) if (max_step and ds > 0) else 1
        h = ds / m
        for _ in range(m):
            if started and h > 0:
                if startup_left > 0:
                    rho = implicit(implicit(rho, 0.5 * h), 0.5 * h)
                    startup_left -= 1
                    steps += 2
                else:
                    rho = implicit(rho + 0.5 * h * apply_L(rho), 0.5 * h)
                    steps += 1
        w = mass[:, k]
        inside = (w > 0) & (pos[:, k] < g_max)
        skipped += np.where((w > 0) & ~inside, w, 0.0)
        if np.any(inside):
            sig = np.full(n_rhs, math.sqrt(max(ds, 0.0)))  # variance 2 * (ds / 2)
            cm = _cell_masses(edges, np.where(inside, pos[:, k], 0.0), sig)
            add = np.where(inside[:, None], w[:, None] * cm, 0.0)
            rho += (add / vol[None, :]).T
            injected += np.where(inside, w * cm.sum(axis=1), 0.0)
            started = True
    rho_out = np.concatenate((rho.T, np.zeros((n_rhs, 1))), axis=1)
    return DiffusionResult(g, rho_out, vol @ rho, injected, skipped, steps)
