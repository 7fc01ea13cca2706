"""Gap distribution as a diffusion equation in magnification (physics.md §5.5b).

For ``g > 0`` write ``P(g, zeta) = (A(zeta)/A0) delta(g) + rho(g, zeta)``; then

.. math::

    \\partial_\\zeta \\rho = b(\\zeta)\\, \\partial_g^2 \\rho
        + [-A'(\\zeta)/A_0]\\, \\delta(g - u_1(\\zeta)), \\qquad b = \\pi q_L q C(q),

with ``rho(g, 1) = 0``, a *reflecting* wall ``d rho/dg = 0`` at ``g = 0`` (no re-contact) and
``rho -> 0`` far away. In the diffusion time ``s = int_1^zeta b dzeta = (h_rms^2 - h^2(zeta))/2``
[m^2] the equation is the plain heat equation ``d rho/ds = d^2 rho/dg^2`` plus injections, which
:func:`xpersson.engine.solve_sourced` solves (finite volumes, Crank-Nicolson with Rannacher
start-up, exact image-pair Gaussian injections).  This module is only the adapter from
magnification bins to engine sources: each bin's mass is a source at the bin's mid diffusion
time, and the bin edges are the engine's grid times (so each injection is the exact Gaussian of
half a step).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from xpersson.engine import Wall, solve_sourced

__all__ = ["diffuse_with_injection", "DiffusionResult", "gap_pdf_by_diffusion"]


class DiffusionResult:
    """Solution of :func:`diffuse_with_injection`.

    Attributes
    ----------
    g : ndarray, (n_g,)
        Grid [m] (last node is the truncation of the domain, ``rho = 0``).
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
    status, message : str
        Engine outcome (:class:`xpersson.engine.SourcedResult`).
    """

    def __init__(self, g, rho, mass, injected, skipped, steps, status="success", message=""):  # noqa: ANN001
        self.g, self.rho, self.mass = g, rho, mass
        self.injected, self.skipped, self.steps = injected, skipped, steps
        self.status, self.message = status, message


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
    """Solve ``rho_s = rho_gg`` on ``[0, g_max]`` with one injection per bin (engine adapter).

    Parameters
    ----------
    g_max : float
        Truncation of the domain [m] (``rho = 0``); choose it many widths beyond the mass.
    n_g : int
        Number of grid intervals (uniform spacing ``g_max / n_g``).
    s_edges : array_like, (n_bin + 1,)
        Non-decreasing diffusion times [m^2] bounding the injection bins.
    inj_pos : array_like, (n_rhs, n_bin)
        Injection positions [m] (>= 0) per right-hand side and bin.
    inj_mass : array_like, (n_rhs, n_bin)
        Injected masses [1] (>= 0); bins at or beyond ``g_max`` are skipped (counted).
    rannacher : int
        Number of start-up steps done as two implicit-Euler half steps.
    max_step : float, optional
        Largest diffusion-time step [m^2]; longer bins are split (default: no limit).

    Returns
    -------
    DiffusionResult
    """
    s = np.maximum(np.asarray(s_edges, dtype=float), 0.0)  # s(1) = 0 up to rounding
    pos = np.atleast_2d(np.asarray(inj_pos, dtype=float))
    mass = np.atleast_2d(np.asarray(inj_mass, dtype=float))
    inside = (mass > 0) & (pos < g_max)
    skipped = np.where((mass > 0) & ~inside, mass, 0.0).sum(axis=1)
    g = np.linspace(0.0, g_max, n_g + 1)
    res = solve_sourced(
        [s[-1]],
        0.5 * (s[:-1] + s[1:]),
        np.where(inside, pos, 0.0),
        np.where(inside, mass, 0.0),
        lower=Wall.reflecting(0.0),
        p_out=g,
        options={
            "nodes": n_g,
            "p_max": g_max,
            "tau_grid": s,
            "max_step": max_step,
            "rannacher": rannacher,
        },
    )
    return DiffusionResult(
        g,
        res.P[:, -1],
        res.mass[:, -1],
        res.injected[:, -1],
        skipped,
        res.nsteps,
        res.status,
        res.message,
    )


def gap_pdf_by_diffusion(
    psd: Any, det: Any, u: np.ndarray, n_grid: int
) -> tuple[np.ndarray, np.ndarray]:
    """``gap_pdf`` and ``gap_mean`` of the detachment bins ``det`` by §5.5b, sampled on ``u``.

    Each load gets its own domain ``[0, g_max]``: many widths beyond the bins that carry its
    detached area (weight above 1e-14 of it), at least ``u(p0) + 10 h`` of those bins, and no
    larger than the output grid needs -- so at high load, where every gap is far below
    ``h_rms``, the ``n_grid`` intervals resolve them (one shared 10 ``h_rms`` domain put them
    all in the first cell).
    """
    q_L = float(psd.q_L)
    q_hi = float(det.zeta[-1]) * q_L
    m1 = psd.running_moment(1.0, np.minimum(det.zeta * q_L, q_hi))
    h2 = 2.0 * math.pi * (float(psd.running_moment(1.0, q_hi)) - np.asarray(m1, dtype=float))
    s = 0.5 * (det.h_rms**2 - h2)
    rho = np.zeros((det.weight.shape[0], u.size))
    mean = np.zeros(det.weight.shape[0])
    for i in range(det.weight.shape[0]):
        w, u1 = det.weight[i], det.u1[i]
        big = w > 1e-14 * max(float(w.sum()), 1e-300)
        reach = float(np.max(u1[big] + 10.0 * det.h[big])) if big.any() else float(u[-1])
        g_max = max(min(reach, max(float(u[-1]), float(det.mean_gap[i]) + 10 * det.h_rms)),
                    1e-300)  # fmt: skip
        res = diffuse_with_injection(g_max, n_grid, s, u1[None, :], w[None, :])
        rho[i] = np.interp(u, res.g, res.rho[0], right=0.0)
        vol = np.full(res.g.size, res.g[1] - res.g[0])
        vol[0] *= 0.5
        # bins beyond the far wall (vanishing area at large u1) keep their first moment
        far = float(np.sum(np.where(u1 >= g_max, w * u1, 0.0)))
        mean[i] = float(res.rho[0] @ (vol * res.g)) + far
    return rho, mean
