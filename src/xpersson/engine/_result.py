"""The engine's result object and the shared bookkeeping (balances, status)."""

from __future__ import annotations

import math
import sys
import time
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from ._problem import Problem
from ._views import NO_WALL, LazyField, broadcast_view, no_wall, per_load

__all__ = [
    "Outcome",
    "EngineResult",
    "EngineBatch",
    "Raw",
    "finish",
    "finish_batch",
    "balance_status",
    "balance_tolerance",
]

Array = NDArray[np.float64]


@dataclass(frozen=True, kw_only=True)
class Outcome:
    """What every engine result reports about its run (shared by :class:`EngineResult` and
    :class:`~xpersson.engine.SourcedResult`; keyword-only fields)."""

    status: str
    message: str
    success: bool
    method: str
    nsteps: int
    n_nodes: int
    wall_time: float


@dataclass(frozen=True)
class EngineResult(Outcome):
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
        Residual of the load identity, scaled by ``max(|p0|, |lower wall|)``:
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
    nfev: int

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
    #: the probability and load identities hold by construction of the method (a closed form
    #: whose load and absorbed fraction are defined from one another): a batch reports them as
    #: exact zeros instead of evaluating them (single solves still evaluate them)
    exact_balances: bool = False
    #: ``(c, d)`` such that ``error_estimate <= c |area| + d`` everywhere (None: unknown); lets
    #: a batch decide "tolerance met" without a pass over the arrays when ``c <= rtol``,
    #: ``d <= atol``
    error_form: tuple[float, float] | None = None
    #: the lower wall's positions [Pa] at the output times (a row shared by the loads) where
    #: the method evaluated them already (no upper wall; None: evaluated here when needed)
    lower_at: Array | None = None


def balance_tolerance(rtol: float, atol: float) -> float:
    """Acceptance bound of the balances, ``10 (rtol + atol)`` (plus round-off)."""
    return 10.0 * (rtol + atol) + 1e-12


def balance_status(
    finite: bool, balances: dict[str, Array], tol: float, status: str = "success"
) -> tuple[str, str]:
    """Shared acceptance test: non-finite values or a balance above ``tol`` fail the result.

    Parameters
    ----------
    finite : bool
        Whether every output value is finite.
    balances : dict
        Name -> residual array (dimensionless, relative).
    tol : float
        Bound (see :func:`balance_tolerance`).
    status : str
        Status handed in by the method; only "success" is re-examined.

    Returns
    -------
    (status, message)
        ``message`` is empty when the balances pass.
    """
    if status != "success":
        return status, ""
    if not finite:
        return "balance_violated", "non-finite values in the solution"
    worst = {k: float(np.max(np.abs(v))) if np.size(v) else 0.0 for k, v in balances.items()}
    if any(w > tol for w in worst.values()):
        text = ", ".join(f"{k} {w:.2e}" for k, w in worst.items())
        return "balance_violated", f"{text} exceed 10*(rtol+atol) = {tol:.2e}"
    return "success", ""


def _row_status(problem: Problem, raw: Raw, prob: Array, loadb: Array, row) -> tuple[str, str]:
    """Status and message of one load (``row`` indexes the batch axis, or ``...``)."""
    status = raw.status if isinstance(raw.status, str) else raw.status[row]
    message = raw.message if isinstance(raw.message, str) else raw.message[row]
    fields = ("area", "non_area", "absorbed_lower", "absorbed_upper", "load")
    finite = all(np.all(np.isfinite(getattr(raw, f)[row])) for f in fields)
    if raw.P is not None:
        finite = finite and bool(np.all(np.isfinite(raw.P[row])))
    bal_tol = balance_tolerance(problem.rtol, problem.atol)
    new, msg = balance_status(
        finite, {"probability balance": prob[row], "load balance": loadb[row]}, bal_tol, status
    )
    if new != status or msg:
        return new, msg
    if status == "success":
        area, err = raw.area[row], raw.error_estimate[row]
        tol = problem.tolerance(area)
        if np.any(err > tol):
            i = int(np.argmax(err / tol))
            tau = problem.tau[row]
            return "tolerance_not_met", (
                f"error estimate {err[i]:.2e} > tolerance {tol[i]:.2e} at tau = {tau[i]:.6g} Pa^2"
            )
        if not message:
            message = "requested tolerance met"
    return status, message


def _screened_balances(problem: Problem, raw: Raw) -> tuple:
    """:func:`_balances` (exact zeros for identities) and the screen's reductions where one
    compiled call gives both (:func:`._cn_outputs.batch_balances`, no upper wall; else None)."""
    if raw.exact_balances:  # identities by construction: exact zeros (read-only, no memory)
        zero = broadcast_view(np.zeros(()), problem.tau.shape)
        return (*problem.output_positions(), zero, zero, None)
    compiled = sys.modules.get(f"{__package__}._compiled")  # (loaded with the march only)
    fast = None if compiled is None else compiled.built("balances")  # (then _cn_outputs is loaded)
    if fast is not None and problem.upper is None:
        lo, up = raw.lower_at, NO_WALL  # (the method's, where it has them)
        if lo is None:
            lo, up = problem.output_positions()
        outputs = sys.modules[f"{__package__}._cn_outputs"]
        return (lo, up, *outputs.batch_balances_of(fast, problem, raw, lo))
    return (*_balances(problem, raw), None)


def _balances(problem: Problem, raw: Raw) -> tuple[Array, Array, Array, Array]:
    lo, up = problem.output_positions()
    # in place: one new array each (fresh large temporaries cost page faults)
    prob = np.add(raw.area, raw.absorbed_lower)
    prob += raw.absorbed_upper
    prob -= 1.0
    scale = np.maximum(np.abs(problem.p0), np.abs(lo))
    scale = np.where(scale > 0, scale, 1.0)
    loadb = np.add(raw.load, raw.wall_term)
    loadb -= problem.p0
    loadb /= scale
    return lo, up, prob, loadb


def finish(problem: Problem, raw: Raw, method: str, t_start: float) -> EngineResult:
    """Balances, final status and the frozen result."""
    lo, up, prob, loadb = _balances(problem, raw)
    shape = problem.tau.shape
    lo, up = np.broadcast_to(lo, shape).copy(), np.broadcast_to(up, shape).copy()
    status, message = _row_status(problem, raw, prob, loadb, ...)
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


_BATCH_FIELDS = (
    "tau",
    "area",
    "non_area",
    "absorbed_lower",
    "absorbed_upper",
    "load",
    "wall_lower",
    "wall_upper",
    "P",
    "error_estimate",
    "probability_balance",
    "load_balance",
)


class EngineBatch(Sequence):
    """Results of a batch of loads (:func:`xpersson.engine.solve_batch`).

    A sequence of :class:`EngineResult` (one per load, built on access) that also exposes the
    stacked arrays: every per-tau field of :class:`EngineResult` with a leading load axis,
    ``(n_load, n_tau)`` (``P``: ``(n_load, n_tau, n_p)``), plus ``p0`` [Pa] ``(n_load,)``,
    ``status``/``message``/``method`` (lists), ``success``, ``nsteps``, ``n_nodes``, ``nfev``
    (arrays per load) and ``wall_time`` [s] of the whole batch. ``exact_balances`` (bool per
    load) marks loads whose method makes both balances identities by construction (the
    one-wall closed form): their ``probability_balance`` and ``load_balance`` are exact zeros,
    not evaluated (read-only arrays).
    """

    def __init__(
        self,
        p0: Array,
        fields: dict,
        status: list[str],
        message: list[str],
        method: list[str],
        nsteps: Array,
        n_nodes: Array,
        nfev: Array,
        p: Array | None,
        wall_time: float,
        exact_balances: Array | None = None,
        success: Array | None = None,
    ) -> None:
        self.p0 = p0
        self._pending: dict[str, LazyField] = {}
        own = self.__dict__  # (written directly: setattr per field costs ~0.2 us each)
        for name in _BATCH_FIELDS:
            value = fields.get(name)
            if type(value) is LazyField:  # computed on first access (see __getattr__)
                self._pending[name] = value
            else:
                own[name] = value
        self.p = p
        self.status = status
        self.message = message
        self.method = method
        self.success = (
            np.array([s == "success" for s in status], dtype=bool)
            if success is None
            else np.asarray(success, dtype=bool)
        )
        self.nsteps, self.n_nodes, self.nfev = nsteps, n_nodes, nfev
        self.wall_time = wall_time
        self.exact_balances = (
            np.zeros(len(p0), dtype=bool)
            if exact_balances is None
            else np.asarray(exact_balances, dtype=bool)
        )
        self._loads: dict[int, EngineResult] = {}  # built on first access, by index

    def __getattr__(self, name: str):
        lazy = self.__dict__.get("_pending", {})
        if name in lazy:
            value = lazy.pop(name)()
            setattr(self, name, value)
            return value
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    def __getstate__(self) -> dict:  # pickled with every field computed
        for name in list(self._pending):
            getattr(self, name)
        return dict(self.__dict__)

    def __len__(self) -> int:
        return int(self.p0.size)

    def __getitem__(self, i):  # type: ignore[override]
        if isinstance(i, slice):
            return [self[j] for j in range(*i.indices(len(self)))]
        i = int(i)
        if i < 0:
            i += len(self)
        if not 0 <= i < len(self):
            raise IndexError(i)
        if i not in self._loads:
            row = {
                name: getattr(self, name)[i] if getattr(self, name) is not None else None
                for name in _BATCH_FIELDS
            }
            self._loads[i] = EngineResult(
                **row,
                p=self.p,
                status=self.status[i],
                message=self.message[i],
                success=bool(self.success[i]),
                method=self.method[i],
                nsteps=int(self.nsteps[i]),
                n_nodes=int(self.n_nodes[i]),
                nfev=int(self.nfev[i]),
                wall_time=self.wall_time / max(len(self), 1),
            )
        return self._loads[i]

    def __repr__(self) -> str:
        n_bad = int(np.sum(~self.success))
        return (
            f"EngineBatch(n_load={len(self)}, methods={sorted(set(self.method))}, "
            f"failed={n_bad}, wall_time={self.wall_time:.3g} s)"
        )


def _raw_ok(raw: Raw, n: int) -> np.ndarray:  # per load: did the method report success?
    if isinstance(raw.status, str):  # one status for the batch
        return np.full(n, raw.status == "success")
    return broadcast_view(np.asarray(raw.status) == "success", (n,)).copy()


def finish_batch(problem: Problem, raw: Raw, method: str) -> dict:
    """Balances and per-load status of a batched Raw: the pieces of an :class:`EngineBatch`.

    The whole batch is screened with reductions over all its values (a few passes, no
    per-load reductions); only when that screen fails are the loads examined one by one.
    """
    shape = problem.tau.shape
    n = shape[0]
    lo, up, prob, loadb, red = _screened_balances(problem, raw)  # (fresh arrays: methods)
    bal_tol = balance_tolerance(problem.rtol, problem.atol)
    # NaN/inf in any field reaches a balance or one of the sums (max/min/sum propagate NaN)
    if raw.exact_balances:
        finite_all = bool(np.isfinite(np.sum(raw.area) + np.sum(raw.non_area)))
        worst_all = 0.0
    else:
        worst = (prob.max(), -prob.min(), loadb.max(), -loadb.min()) if red is None else red[:4]
        worst_all = max(float(worst[0]), float(worst[1]), float(worst[2]), float(worst[3]))
        finite_all = math.isfinite(worst_all) and (
            (red is not None and red[5] == 1.0)  # (the sum is finite in any order)
            or math.isfinite(np.asarray(raw.non_area).sum())
        )
    if raw.P is not None:
        finite_all = finite_all and bool(np.isfinite(np.sum(raw.P)))
    form = raw.error_form
    if form is not None and form[0] <= problem.rtol and form[1] <= problem.atol:
        tol_all = True  # error_estimate <= c |area| + d <= rtol |area| + atol everywhere
    elif red is not None:
        tol_all = bool(red[4] <= problem.atol)  # False where it is NaN
    else:
        slack = np.abs(raw.area)
        slack *= -problem.rtol
        slack += raw.error_estimate
        tol_all = bool(slack.max() <= problem.atol)  # False where it holds NaN
    if finite_all and worst_all <= bal_tol and tol_all:
        # (one status for the batch: every load as the method says, no per-load array)
        clean = raw.status == "success" if isinstance(raw.status, str) else _raw_ok(raw, n)
    else:  # per-load screen: only loads that may fail get the detailed examination
        worst = np.maximum.reduce(
            [
                np.max(prob, axis=-1),
                -np.min(prob, axis=-1),
                np.max(loadb, axis=-1),
                -np.min(loadb, axis=-1),
            ]
        )
        finite = (
            np.isfinite(worst)
            & np.isfinite(np.sum(raw.non_area, axis=-1))
            & np.isfinite(np.sum(raw.area, axis=-1))
        )
        if raw.P is not None:
            finite &= np.all(np.isfinite(raw.P), axis=(-2, -1))
        slack = np.abs(raw.area)
        slack *= -problem.rtol
        slack += raw.error_estimate
        tol_ok = np.max(slack, axis=-1) <= problem.atol  # False where a row holds NaN
        clean = finite & (worst <= bal_tol) & tol_ok & _raw_ok(raw, n)
    default = (
        raw.message if isinstance(raw.message, str) and raw.message else ("requested tolerance met")
    )
    status = ["success"] * n
    message = (
        [default] * n
        if isinstance(raw.message, str)
        else [m or "requested tolerance met" for m in raw.message]
    )
    if clean is True or clean is False:  # (np.ones/np.zeros: np.full costs ~1.5 us more)
        success = np.ones(n, dtype=bool) if clean else np.zeros(n, dtype=bool)
    else:
        success = clean.astype(bool)
    if clean is not True and np.count_nonzero(success) < n:
        for i in np.flatnonzero(~success):
            status[i], message[i] = _row_status(problem, raw, prob, loadb, int(i))
            success[i] = status[i] == "success"
    fields = {
        "tau": problem.tau,
        "area": raw.area,
        "non_area": raw.non_area,
        "absorbed_lower": raw.absorbed_lower,
        "absorbed_upper": raw.absorbed_upper,
        "load": raw.load,
        "wall_lower": broadcast_view(lo, shape),
        "wall_upper": no_wall(shape) if up is NO_WALL else broadcast_view(up, shape),
        "P": raw.P,
        "error_estimate": raw.error_estimate,
        "probability_balance": prob,
        "load_balance": loadb,
    }
    return dict(
        fields=fields,
        status=status,
        message=message,
        method=[method] * n,
        nsteps=per_load(raw.nsteps, n),
        n_nodes=per_load(raw.n_nodes, n),
        nfev=per_load(raw.nfev, n),
        exact_balances=np.ones(n, dtype=bool) if raw.exact_balances else np.zeros(n, dtype=bool),
        success=success,
    )
