"""``solve_sourced``: heat equation with point injections above a reflecting wall.

.. math::

    \\partial_\\tau \\rho = \\partial_p^2 \\rho + \\sum_j w_j\\, \\delta(\\tau - \\tau_j)\\,
        \\delta(p - p_j), \\qquad \\rho(p, 0) = 0, \\qquad
    \\partial_p \\rho = 0 \\text{ at the wall},

with no upper wall (the domain is truncated at ``p_max``, where ``rho = 0``, far beyond the mass).
This is the gap-distribution problem of :doc:`/theory/04_gap_equation` in diffusion time (moved
here from
``xpersson_interface._gap_diffusion``); it knows nothing about contact mechanics.

Scheme (unchanged from the plugin solver): finite volumes on a uniform grid (exactly
conservative; the reflecting wall is a zero-flux face), Crank-Nicolson with Rannacher start-up
(the first steps after an injection that the step does not resolve are replaced by two
implicit-Euler half steps each), one tridiagonal solve per step for all right-hand sides at
once (the implicit half shared with the moving-wall integrator, :mod:`._cnstep`).
A source at ``tau_j`` is injected at the first grid time ``t_i > tau_j`` as the exact image-pair
Gaussian of variance ``2 (t_i - tau_j)``, cell-averaged with ``erf`` so the injected discrete mass
is exact; sources placed mid-way between grid times (``options["tau_grid"]``) are therefore
injected after half a step of exact diffusion and CN only acts on data resolved by the step.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.special import erf

from ._cnstep import implicit_operator, tridiagonal_solve
from ._problem import _fail, window_k
from ._result import Outcome, balance_status, balance_tolerance
from ._walls import Wall

__all__ = ["solve_sourced", "SourcedResult"]

Array = NDArray[np.float64]

_DEFAULT_LOWER = Wall.reflecting(0.0)
_OPTIONS = ("nodes", "p_max", "tau_grid", "max_step", "rannacher")


@dataclass(frozen=True)
class SourcedResult(Outcome):
    """Result of :func:`solve_sourced` (arrays per output tau; a leading batch axis when the
    sources were given per right-hand side).

    Attributes
    ----------
    tau : ndarray, (n_tau,)
        Output diffusion times [Pa^2] (= ``tau_out``).
    p : ndarray, (n_p,)
        ``p_out`` [Pa].
    P : ndarray, ([n_batch,] n_tau, n_p)
        Density [1/Pa] at ``(tau, p)`` (linear interpolation of the grid solution; 0 below the
        wall and beyond the truncation ``p_max``).
    injected : ndarray, ([n_batch,] n_tau)
        Source mass with ``tau_j < tau`` [1].
    mass : ndarray, ([n_batch,] n_tau)
        Discrete mass in the domain [1].
    mass_balance : ndarray, ([n_batch,] n_tau)
        ``injected - mass`` (what left through the far truncation, plus rounding).
    p_max : float
        Truncation of the domain [Pa] (``rho = 0`` there).
    status, message, success, method : str, str, bool, str
        Outcome; ``status`` is "success" or "balance_violated" (``|mass_balance|`` above
        ``10 * (rtol + atol)`` times the total source mass, or non-finite values).
    nsteps, n_nodes : int
        Linear solves and grid nodes.
    wall_time : float
        Seconds spent in :func:`solve_sourced`.
    """

    tau: Array
    p: Array
    P: Array
    injected: Array
    mass: Array
    mass_balance: Array
    p_max: float

    def __repr__(self) -> str:
        return (
            f"SourcedResult(status={self.status!r}, n_tau={self.tau.size}, "
            f"max|mass_balance|={np.max(np.abs(self.mass_balance)):.2e}, "
            f"n_nodes={self.n_nodes}, nsteps={self.nsteps}, wall_time={self.wall_time:.3g} s)"
        )


def _array(name: str, unit: str, value: ArrayLike) -> Array:
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise _fail(name, unit, "an array of finite floats", value) from None
    if not np.all(np.isfinite(arr)):
        raise _fail(name, unit, "finite (no NaN/inf)", value)
    return arr


def _cell_masses(edges: Array, pos: Array, sig: Array) -> Array:
    """Mass of the image pair N(pos, sig) + N(-pos, sig) in each cell, (n_rhs, n_cell)."""
    e = edges[None, :]
    p, s = pos[:, None], np.maximum(sig, 1e-300)[:, None]
    cdf = 0.5 * (erf((e - p) / (math.sqrt(2.0) * s)) + erf((e + p) / (math.sqrt(2.0) * s)))
    return np.diff(cdf, axis=1)


def solve_sourced(
    tau_out: ArrayLike,
    sources_tau: ArrayLike,
    sources_position: ArrayLike,
    sources_weight: ArrayLike,
    *,
    lower: Wall = _DEFAULT_LOWER,
    p_out: ArrayLike,
    rtol: float = 1e-4,
    atol: float | None = None,
    options: dict[str, Any] | None = None,
) -> SourcedResult:
    """Solve ``drho/dtau = d2rho/dp2`` from ``rho = 0`` with point injections, reflecting wall.

    Parameters
    ----------
    tau_out : array_like, (n_tau,)
        Output diffusion times [Pa^2], strictly increasing, > 0.
    sources_tau : array_like, (n_src,)
        Injection times [Pa^2], >= 0 (any order).  Sources with ``tau_j >= tau`` are not yet
        injected at output time ``tau``.
    sources_position : array_like, (n_src,) or (n_batch, n_src)
        Injection positions [Pa], finite and >= the wall.  A 2-D array solves ``n_batch``
        right-hand sides sharing the times (one banded solve per step for all).
    sources_weight : array_like, same shape as ``sources_position``
        Injected masses [1], finite and >= 0.
    lower : Wall, optional
        ``Wall.reflecting(position)`` (default at 0).
    p_out : array_like, (n_p,)
        Positions [Pa] where the density is returned.
    rtol : float, optional
        Relative accuracy aimed at by the default grid, in (0, 0.1).
    atol : float, optional
        Mass (relative to the total source mass) allowed to leave through the truncation
        (default ``1e-7 * rtol``); sets the default ``p_max``.
    options : dict, optional
        ``nodes`` (grid intervals), ``p_max`` [Pa] (truncation, > every source position),
        ``tau_grid`` [Pa^2] (extra grid times; put sources mid-way between them),
        ``max_step`` [Pa^2] (longest step, ``None`` for no limit), ``rannacher`` (start-up steps,
        default 2).  Defaults follow from ``rtol``/``atol``.

    Returns
    -------
    SourcedResult

    Raises
    ------
    ValueError
        Bad input, naming the parameter, its unit and the allowed range (before any work).
    """
    t_start = time.perf_counter()
    tau, src_t, pos, weight, wall, p_arr = _checked_inputs(
        tau_out, sources_tau, sources_position, sources_weight, lower, p_out
    )
    rtol, atol, opts = _checked_controls(rtol, atol, options)
    batched = pos.ndim == 2
    pos2 = np.atleast_2d(pos) - wall  # coordinate above the wall
    w2 = np.atleast_2d(weight)
    active = np.any(w2 > 0, axis=0)
    nodes_t, var_ref = _time_grid(tau, src_t, active, rtol, opts)
    g_max, n_g = _space_grid(tau, src_t, pos2, w2, active, wall, rtol, atol, var_ref, opts)
    P, injected, mass, steps = _march(
        tau, nodes_t, src_t, pos2, w2, active, g_max, n_g, p_arr - wall, opts
    )
    balance = injected - mass
    total = np.maximum(w2.sum(axis=1), 1e-300)
    finite = bool(np.all(np.isfinite(P)) and np.all(np.isfinite(mass)))
    status, message = balance_status(
        finite,
        {"relative mass balance": balance / total[:, None]},
        balance_tolerance(rtol, atol),
    )
    message = message or "mass balance within 10*(rtol+atol)"
    if not batched:
        P, injected, mass, balance = P[0], injected[0], mass[0], balance[0]
    return SourcedResult(
        tau=tau,
        p=p_arr,
        P=P,
        injected=injected,
        mass=mass,
        mass_balance=balance,
        p_max=wall + g_max,
        status=status,
        message=message,
        success=status == "success",
        method="cn",
        nsteps=steps,
        n_nodes=n_g + 1,
        wall_time=time.perf_counter() - t_start,
    )


def _checked_inputs(
    tau_out: ArrayLike,
    sources_tau: ArrayLike,
    sources_position: ArrayLike,
    sources_weight: ArrayLike,
    lower: Wall,
    p_out: ArrayLike,
) -> tuple[Array, Array, Array, Array, float, Array]:
    """The arrays of :func:`solve_sourced` checked (units there); the wall position [Pa]."""
    tau = np.atleast_1d(_array("tau_out", "Pa^2", tau_out))
    if tau.ndim != 1 or tau.size == 0:
        raise _fail("tau_out", "Pa^2", "a non-empty 1-D array", tau_out)
    if np.any(tau <= 0):
        raise _fail("tau_out", "Pa^2", "> 0", float(tau.min()))
    if np.any(np.diff(tau) <= 0):
        raise _fail("tau_out", "Pa^2", "strictly increasing", tau_out)
    src_t = np.atleast_1d(_array("sources_tau", "Pa^2", sources_tau))
    if src_t.ndim != 1 or src_t.size == 0:
        raise _fail("sources_tau", "Pa^2", "a non-empty 1-D array", sources_tau)
    if np.any(src_t < 0):
        raise _fail("sources_tau", "Pa^2", ">= 0", float(src_t.min()))
    pos = _array("sources_position", "Pa", sources_position)
    weight = _array("sources_weight", "1", sources_weight)
    if pos.ndim not in (1, 2) or pos.shape[-1] != src_t.size:
        raise _fail(
            "sources_position",
            "Pa",
            f"shaped (n_src,) or (n_batch, n_src), n_src = {src_t.size}",
            pos.shape,
        )
    if weight.shape != pos.shape:
        raise _fail(
            "sources_weight", "1", f"shaped like sources_position {pos.shape}", weight.shape
        )
    if np.any(weight < 0):
        raise _fail("sources_weight", "1", ">= 0", float(weight.min()))
    if not isinstance(lower, Wall) or lower.kind != "reflecting":
        raise ValueError(f"lower must be Wall.reflecting(position [Pa]); got {lower!r}")
    wall = float(lower.position)  # type: ignore[arg-type]
    if np.any(pos < wall):
        raise _fail("sources_position", "Pa", f">= the wall at {wall:.6g} Pa", float(pos.min()))
    p_arr = np.atleast_1d(_array("p_out", "Pa", p_out))
    if p_arr.ndim != 1:
        raise _fail("p_out", "Pa", "a 1-D array of finite positions", p_out)
    return tau, src_t, pos, weight, wall, p_arr


def _checked_controls(
    rtol: float, atol: float | None, options: dict[str, Any] | None
) -> tuple[float, float, dict[str, Any]]:
    """``rtol``, ``atol`` (default ``1e-7 rtol``) and the option keys checked."""
    try:
        rtol = float(rtol)
    except (TypeError, ValueError):
        raise _fail("rtol", "1", "a float in (0, 0.1)", rtol) from None
    if not (0.0 < rtol < 0.1):
        raise _fail("rtol", "1", "in the open interval (0, 0.1)", rtol)
    atol = 1e-7 * rtol if atol is None else float(atol)
    if not (math.isfinite(atol) and 0.0 < atol < 0.1):
        raise _fail("atol", "1 (mass relative to the sources)", "in (0, 0.1)", atol)
    opts = dict(options or {})
    unknown = sorted(set(opts) - set(_OPTIONS))
    if unknown:
        raise ValueError(f"options: unknown keys {unknown}; allowed {list(_OPTIONS)}")
    return rtol, atol, opts


def _time_grid(
    tau: Array, src_t: Array, active: Array, rtol: float, opts: dict[str, Any]
) -> tuple[Array, float]:
    """Grid times [Pa^2] (outputs, ``tau_grid`` or mid-points between sources, ``max_step``
    refinement) and the reference variance [Pa^2] of the youngest injection at an output."""
    t_end = float(tau[-1])
    grid = [tau]
    if "tau_grid" in opts:
        tg = np.atleast_1d(_array('options["tau_grid"]', "Pa^2", opts["tau_grid"]))
        if tg.ndim != 1 or np.any(tg < 0):
            raise _fail('options["tau_grid"]', "Pa^2", "a 1-D array of times >= 0", tg)
        grid.append(tg[tg < t_end])
    else:  # sources mid-way between grid times: edges at the midpoints between source times
        c = np.unique(src_t[active & (src_t < t_end)])
        if c.size > 1:
            grid.append(0.5 * (c[1:] + c[:-1]))
    nodes_t = np.unique(np.concatenate([[0.0], *grid]))
    # reference width: the youngest injection seen at an output time
    idx = np.searchsorted(np.sort(src_t[active]), tau, side="left")
    last = np.where(idx > 0, np.sort(src_t[active])[np.maximum(idx - 1, 0)], 0.0)
    var_ref = float(np.min(2.0 * (tau - last))) if np.any(active) else 2.0 * t_end
    if "max_step" in opts:
        max_step = opts["max_step"]
        if max_step is not None and not (math.isfinite(float(max_step)) and max_step > 0):
            raise _fail('options["max_step"]', "Pa^2", "> 0 or None", max_step)
    else:
        max_step = 0.25 * math.sqrt(rtol) * var_ref
    if max_step is not None:
        fine = [nodes_t[:1]]
        for a, b in zip(nodes_t[:-1], nodes_t[1:], strict=True):
            m = max(1, math.ceil((b - a) / float(max_step)))
            fine.append(np.linspace(a, b, m + 1)[1:])
        nodes_t = np.concatenate(fine)
    return nodes_t, var_ref


def _space_grid(
    tau: Array,
    src_t: Array,
    pos2: Array,
    w2: Array,
    active: Array,
    wall: float,
    rtol: float,
    atol: float,
    var_ref: float,
    opts: dict[str, Any],
) -> tuple[float, int]:
    """Truncation ``g_max`` [Pa above the wall] and the number of grid intervals."""
    t_end = float(tau[-1])
    x_src = float(np.max(np.where(w2 > 0, pos2, 0.0)))
    if "p_max" in opts:
        g_max = float(opts["p_max"]) - wall
        if not (math.isfinite(g_max) and g_max > 0):
            raise _fail(
                'options["p_max"]', "Pa", f"finite and > the wall at {wall:.6g}", opts["p_max"]
            )
        if np.any((w2 > 0) & (pos2 >= g_max)):
            raise _fail(
                'options["p_max"]', "Pa", "above every source with weight > 0", opts["p_max"]
            )
    else:
        t_first = float(np.min(src_t[active])) if np.any(active) else 0.0
        g_max = x_src + window_k(atol) * math.sqrt(2.0 * max(t_end - t_first, 0.0))
        g_max = max(g_max, 1e-300)
    if "nodes" in opts:
        n_g = int(opts["nodes"])
        if n_g < 4:
            raise _fail('options["nodes"]', "1", ">= 4", opts["nodes"])
    else:
        dx = math.sqrt(3.0 * rtol * var_ref)
        n_g = int(np.clip(math.ceil(g_max / dx), 200, 200_000))
    return g_max, n_g


def _march(
    tau: Array,
    nodes_t: Array,
    src_t: Array,
    pos2: Array,
    w2: Array,
    active: Array,
    g_max: float,
    n_g: int,
    xq: Array,
    opts: dict[str, Any],
) -> tuple[Array, Array, Array, int]:
    """Finite volumes on ``[0, g_max]``: (P, injected, mass) per output and the solve count."""
    rannacher = int(opts.get("rannacher", 2))
    n_rhs = w2.shape[0]
    dg = g_max / n_g
    g = np.linspace(0.0, g_max, n_g + 1)
    n = n_g  # unknowns at nodes 0..n_g-1; node n_g is the truncation, rho = 0
    vol = np.full(n, dg)
    vol[0] = 0.5 * dg
    edges = np.concatenate(([0.0], 0.5 * (g[:-2] + g[1:-1]), [g_max - 0.5 * dg]))
    up = np.full(n, 1.0 / dg**2)
    up[0] = 2.0 / dg**2  # node 0: half cell, zero flux through the wall
    lo = np.full(n, 1.0 / dg**2)
    diag = np.full(n, -2.0 / dg**2)

    def apply_L(r: Array) -> Array:
        out = diag[:, None] * r
        out[:-1] += up[:-1, None] * r[1:]
        out[1:] += lo[1:, None] * r[:-1]
        return out

    def implicit(r: Array, theta_dt: float) -> Array:
        info = tridiagonal_solve(*implicit_operator(theta_dt, lo, diag, up), r)
        if info != 0:  # I - theta dt L is diagonally dominant: this is a bug, not a status
            raise FloatingPointError(f"tridiagonal solve failed (info={info})")
        return r

    # source j is injected at the first grid time > tau_j
    where = np.searchsorted(nodes_t, src_t, side="right")
    out_at = {int(i): k for k, i in enumerate(np.searchsorted(nodes_t, tau))}
    n_tau = tau.size
    rho = np.zeros((n, n_rhs))
    P = np.zeros((n_rhs, n_tau, xq.size))
    mass = np.zeros((n_rhs, n_tau))
    injected = np.zeros((n_rhs, n_tau))
    started, startup_left, steps = False, 0, 0
    for i in range(1, nodes_t.size):
        h = float(nodes_t[i] - nodes_t[i - 1])
        if started and h > 0:
            if startup_left > 0:
                rho = implicit(implicit(rho.copy(), 0.5 * h), 0.5 * h)
                startup_left -= 1
                steps += 2
            else:
                rho = implicit(rho + 0.5 * h * apply_L(rho), 0.5 * h)
                steps += 1
        h_next = float(nodes_t[i + 1] - nodes_t[i]) if i + 1 < nodes_t.size else 0.0
        for j in np.flatnonzero((where == i) & active):
            w = w2[:, j]
            var = 2.0 * float(nodes_t[i] - src_t[j])
            cm = _cell_masses(edges, pos2[:, j], np.full(n_rhs, math.sqrt(var)))
            rho += ((w[:, None] * cm) / vol[None, :]).T
            if not started or var < 0.25 * h_next:  # first or unresolved injection
                startup_left = rannacher
            started = True
        k = out_at.get(i)
        if k is not None:
            full = np.concatenate((rho.T, np.zeros((n_rhs, 1))), axis=1)
            for r in range(n_rhs):
                P[r, k] = np.interp(xq, g, full[r], left=0.0, right=0.0)
            mass[:, k] = vol @ rho
            injected[:, k] = (w2 * (src_t[None, :] < tau[k])).sum(axis=1)
    return P, injected, mass, steps
