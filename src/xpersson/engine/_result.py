"""The engine's result object and the shared bookkeeping (balances, status)."""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from ._problem import Problem

__all__ = ["EngineResult", "Raw", "finish"]

Array = NDArray[np.float64]

STATUSES = ("success", "max_steps", "balance_violated", "tolerance_not_met", "invalid_input")


@dataclass(frozen=True)
class EngineResult:
    """Result of :func:`xpersson.engine.solve` (scipy-style; arrays are per output tau).

    Attributes
    ----------
    tau : ndarray
        Output diffusion times [Pa^2] (= ``tau_out``).
    area, non_area : ndarray
        Probability in the domain (contact-area fraction A/A0) and ``1 - area``, each computed
        without cancellation where it is small.
    absorbed_lower, absorbed_upper : ndarray
        Cumulative probability absorbed at each wall; for a yield-closure upper wall
        ``absorbed_upper`` is the plastic area ``A_pl/A0``.
    load : ndarray
        ``int p P dp`` over the domain [Pa].
    wall_lower, wall_upper : ndarray
        Wall positions [Pa] (``inf`` without an upper wall).
    P : ndarray or None
        Density [1/Pa] at ``(tau, p)``, shape ``(n_tau, n_p)``; only when ``p_out`` was given.
    p : ndarray or None
        ``p_out`` [Pa].
    error_estimate : ndarray
        Estimate of the absolute error of ``area``.
    probability_balance : ndarray
        ``area + absorbed_lower + absorbed_upper - 1``.
    load_balance : ndarray
        Residual of the load identity, scaled by ``max(|p0|, |walls|)``:
        ``(load + int p_l d(absorbed_lower) + U - p0) / scale`` with ``U = int p_u
        d(absorbed_upper)`` for an absorbing upper wall and ``U = Y(tau) A_pl(tau)`` for a yield
        closure wall.  Fixed walls make the integrals ``p_w * absorbed``; a fixed wall at 0 with
        no upper wall gives ``load/p0 - 1``.
    status, message, success, method : str, str, bool, str
        Outcome.  ``status`` is one of "success", "max_steps", "balance_violated",
        "tolerance_not_met", "invalid_input".
    nsteps, n_nodes, nfev : int
        Work counters: time steps (all refinement levels), grid nodes or modes of the finest
        level, and right-hand-side / matrix evaluations (or evaluated series terms).
    wall_time : float
        Seconds spent in :func:`solve`.
    """

    tau: Array
    area: Array
    non_area: Array
    absorbed_lower: Array
    absorbed_upper: Array
    load: Array
    wall_lower: Array
    wall_upper: Array
    P: Array | None
    p: Array | None
    error_estimate: Array
    probability_balance: Array
    load_balance: Array
    status: str
    message: str
    success: bool
    method: str
    nsteps: int
    n_nodes: int
    nfev: int
    wall_time: float

    def __repr__(self) -> str:  # compact, like scipy's OptimizeResult summary
        return (
            f"EngineResult(method={self.method!r}, status={self.status!r}, "
            f"n_tau={self.tau.size}, area[-1]={self.area[-1]:.6g}, "
            f"error_estimate.max()={np.max(self.error_estimate):.2e}, "
            f"wall_time={self.wall_time:.3g} s)"
        )


@dataclass
class Raw:
    """What a method hands back before the shared bookkeeping (all per output tau)."""

    area: Array
    non_area: Array
    absorbed_lower: Array
    absorbed_upper: Array
    load: Array
    wall_term: Array  # the wall terms of the load identity [Pa]
    error_estimate: Array
    P: Array | None = None
    status: str = "success"
    message: str = ""
    nsteps: int = 0
    n_nodes: int = 0
    nfev: int = 0
    extra: dict = field(default_factory=dict)


def finish(problem: Problem, raw: Raw, method: str, t_start: float) -> EngineResult:
    """Balances, final status and the frozen result."""
    lo, up = problem.wall_positions(problem.tau)
    prob = raw.area + raw.absorbed_lower + raw.absorbed_upper - 1.0
    scale = np.maximum(abs(problem.p0), np.abs(lo))
    scale = np.maximum(scale, np.where(np.isfinite(up), np.abs(up), 0.0))
    scale = np.where(scale > 0, scale, 1.0)
    loadb = (raw.load + raw.wall_term - problem.p0) / scale
    status, message = raw.status, raw.message
    fields = (raw.area, raw.non_area, raw.absorbed_lower, raw.absorbed_upper, raw.load)
    finite = all(np.all(np.isfinite(a)) for a in fields)
    if raw.P is not None:
        finite = finite and bool(np.all(np.isfinite(raw.P)))
    tol = problem.tolerance(raw.area)
    if not finite and status == "success":
        status, message = "balance_violated", "non-finite values in the solution"
    elif status == "success":
        bal_tol = 10.0 * (problem.rtol + problem.atol) + 1e-12
        bad_p = np.max(np.abs(prob)) > bal_tol
        bad_l = np.max(np.abs(loadb)) > bal_tol
        if bad_p or bad_l:
            status = "balance_violated"
            message = (
                f"probability balance {np.max(np.abs(prob)):.2e}, load balance "
                f"{np.max(np.abs(loadb)):.2e} exceed 10*(rtol+atol) = {bal_tol:.2e}"
            )
        elif np.any(raw.error_estimate > tol):
            i = int(np.argmax(raw.error_estimate / tol))
            status = "tolerance_not_met"
            message = (
                f"error estimate {raw.error_estimate[i]:.2e} > tolerance {tol[i]:.2e} at "
                f"tau = {problem.tau[i]:.6g} Pa^2"
            )
        elif not message:
            message = "requested tolerance met"
    return EngineResult(
        tau=problem.tau,
        area=raw.area,
        non_area=raw.non_area,
        absorbed_lower=raw.absorbed_lower,
        absorbed_upper=raw.absorbed_upper,
        load=raw.load,
        wall_lower=lo,
        wall_upper=up,
        P=raw.P,
        p=problem.p_out,
        error_estimate=raw.error_estimate,
        probability_balance=prob,
        load_balance=loadb,
        status=status,
        message=message,
        success=status == "success",
        method=method,
        nsteps=int(raw.nsteps),
        n_nodes=int(raw.n_nodes),
        nfev=int(raw.nfev),
        wall_time=time.perf_counter() - t_start,
    )
