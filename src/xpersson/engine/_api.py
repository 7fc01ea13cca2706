"""``solve`` / ``solve_batch``: validate, pick a method, run it, add the balances."""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ._clear import drop_clear_upper
from ._exactpath import ExactMethod
from ._methods import METHODS, EngineMethod, MethodError, get_method
from ._problem import Problem, make_problem
from ._result import EngineBatch, EngineResult, LazyField, Raw, finish, finish_batch
from ._walls import Wall

__all__ = ["solve", "solve_batch"]

_DEFAULT_LOWER = Wall.absorbing(0.0)


def _pick(
    problem: Problem, method: str | type[EngineMethod]
) -> tuple[type[EngineMethod], Problem, float]:
    """Method class, the problem it runs on (a clear moving wall dropped), the added error."""
    if isinstance(method, str) and method == "auto":
        if ExactMethod.admits(problem):
            return ExactMethod, problem, 0.0
        cleared = drop_clear_upper(problem)
        if cleared is not None and ExactMethod.admits(cleared[0]):
            return ExactMethod, cleared[0], cleared[1]
        from ._cn import CNMethod  # lazily: scipy.optimize/interpolate/linalg, ~0.5 s

        return CNMethod, problem, 0.0
    cls = get_method(method)
    if not cls.admits(problem):
        can = [name for name in METHODS if METHODS[name].admits(problem)]
        raise MethodError(
            f"method={getattr(cls, 'name', cls)!r} cannot treat these walls; methods that can: "
            f"'auto' (picks one), {', '.join(repr(n) for n in can)}"
        )
    return cls, problem, 0.0


def _run(cls: type[EngineMethod], problem: Problem, bound: float) -> Raw:
    raw = cls(problem).run()
    if bound > 0:
        raw.error_estimate = raw.error_estimate + np.where(problem.tau > 0, bound, 0.0)
        if raw.error_form is not None:
            raw.error_form = (raw.error_form[0], raw.error_form[1] + bound)
        note = f"moving upper wall never reached (hit probability <= {bound:.1e}); "
        if isinstance(raw.message, str):
            raw.message = note + raw.message
    return raw


def solve(
    tau_out: ArrayLike,
    p0: float,
    lower: Wall = _DEFAULT_LOWER,
    upper: Wall | None = None,
    *,
    rtol: float = 1e-6,
    atol: float | None = None,
    method: str | type[EngineMethod] = "auto",
    p_out: ArrayLike | None = None,
    max_steps: int = 200_000,
    options: dict[str, Any] | None = None,
) -> EngineResult:
    """Solve ``dP/dtau = d2P/dp2``, ``P(p, 0) = delta(p - p0)`` between two walls.

    Parameters
    ----------
    tau_out : array_like
        Output diffusion times [Pa^2], 1-D, strictly increasing, >= 0 (``tau = 0`` is the
        initial state, area 1).  Callers convert magnification to diffusion time with
        ``tau(zeta) = int_1^zeta f dzeta``.
    p0 : float
        Position of the initial delta [Pa], strictly between the walls at ``tau = 0``.
    lower : Wall, optional
        Lower wall (default ``Wall.absorbing(0.0)``).
    upper : Wall or None, optional
        Upper wall, or None for a domain open to ``+inf``.
    rtol : float, optional
        Requested relative error of the area fraction, in (0, 0.1).
    atol : float, optional
        Absolute error floor of the area fraction (default ``1e-7 * rtol``).
    method : str or EngineMethod subclass, optional
        ``"auto"`` (closed form when the walls admit one, also when a moving upper wall
        provably stays clear of the mass; else ``"cn"``), ``"exact"``, ``"sine"`` (fixed walls),
        ``"cn"`` (any walls), a registered name, or a class.
    p_out : array_like, optional
        Pressures [Pa] where the density is wanted; the field is computed only when given.
    max_steps : int, optional
        Budget of time steps summed over all refinement levels (numerical methods).
    options : dict, optional
        Method options (``"cn"``: ``nodes`` (pilot grid, 24), ``steps_per_decade`` (pilot,
        6), ``levels`` (grids, 10), ``max_work`` (node-steps per load, 1e8), ``stretch``,
        ``aim`` (error estimate the next grid is aimed at, as a fraction of the tolerance,
        0.5: the actual error lands near 0.15-0.4 rtol); ``"sine"``: ``window_k``).

    Returns
    -------
    EngineResult
        Areas, absorbed probabilities, load, balances, error estimate and status.

    Raises
    ------
    ValueError
        Bad input, naming the parameter, its unit and the allowed range (before any work).
    """
    t0 = time.perf_counter()
    problem = make_problem(tau_out, p0, lower, upper, rtol, atol, p_out, max_steps, options)
    cls, run_on, bound = _pick(problem, method)
    res = finish(run_on, _run(cls, run_on, bound), getattr(cls, "name", cls.__name__), t0)
    if run_on is not problem:  # report the real walls
        lo, up = problem.wall_positions(problem.tau)
        res = dataclasses.replace(
            res, wall_lower=lo, wall_upper=up, wall_time=time.perf_counter() - t0
        )
    return res


def _pairs(walls: Any, n: int) -> list[tuple[Wall, Wall | None]]:
    if isinstance(walls, tuple) and len(walls) == 2 and isinstance(walls[0], Wall):
        return [walls] * n
    if not isinstance(walls, Sequence) or len(walls) != n:
        raise ValueError(
            f"walls must be a (lower, upper) pair or a sequence of {n} such pairs (one per "
            f"load); got {type(walls).__name__}"
        )
    return [tuple(w) for w in walls]  # type: ignore[misc]


def _stack_raws(raws: list[Raw]) -> Raw:
    def st(name: str) -> np.ndarray:
        return np.stack([np.asarray(getattr(r, name), dtype=float) for r in raws])

    P = None if any(r.P is None for r in raws) else np.stack([r.P for r in raws])
    return Raw(
        area=st("area"),
        non_area=st("non_area"),
        absorbed_lower=st("absorbed_lower"),
        absorbed_upper=st("absorbed_upper"),
        load=st("load"),
        wall_term=st("wall_term"),
        error_estimate=st("error_estimate"),
        P=P,
        status=np.array([r.status for r in raws], dtype=object),  # type: ignore[arg-type]
        message=[r.message for r in raws],  # type: ignore[arg-type]
        nsteps=np.array([r.nsteps for r in raws]),  # type: ignore[arg-type]
        n_nodes=np.array([r.n_nodes for r in raws]),  # type: ignore[arg-type]
        nfev=np.array([r.nfev for r in raws]),  # type: ignore[arg-type]
    )


def _run_group(problem: Problem, picked: tuple[type[EngineMethod], Problem, float]) -> dict:
    """Solve one group of loads sharing their walls with its method ``picked``
    (:func:`_pick`); the pieces of an EngineBatch."""
    cls, run_on, bound = picked
    name = cls.name  # declared on EngineMethod (get_method admits only its subclasses)
    if cls.batched:
        raw = _run(cls, run_on, bound)
    else:
        raw = _stack_raws([_run(cls, run_on.load(i), bound) for i in range(problem.tau.shape[0])])
    out = finish_batch(run_on, raw, name)
    if run_on is not problem:  # report the real walls (positions computed when asked for)
        positions: list[tuple[np.ndarray, np.ndarray]] = []  # both fields: one evaluation

        def walls(side: int) -> np.ndarray:
            if not positions:
                positions.append(problem.wall_positions(problem.tau))
            return np.broadcast_to(positions[0][side], problem.tau.shape)

        out["fields"]["wall_lower"] = LazyField(lambda: walls(0))
        out["fields"]["wall_upper"] = LazyField(lambda: walls(1))
    return out


def solve_batch(
    tau_out: ArrayLike,
    p0: ArrayLike,
    walls: tuple[Wall, Wall | None] | Sequence[tuple[Wall, Wall | None]] = (_DEFAULT_LOWER, None),
    *,
    rtol: float = 1e-6,
    atol: float | None = None,
    method: str | type[EngineMethod] = "auto",
    p_out: ArrayLike | None = None,
    max_steps: int = 200_000,
    options: dict[str, Any] | None = None,
) -> EngineBatch:
    """Solve a batch of loads in one call (vectorised over ``p0`` where the method allows).

    Loads that share their walls are solved together: the closed forms and the ``sine`` series
    are evaluated for all of them at once; methods without batch support (``cn``, registered
    third-party methods) run once per load.  Each load gets the same result as
    :func:`solve` would give it.

    Parameters
    ----------
    tau_out : array_like
        Output diffusion times [Pa^2], ``(n_tau,)`` shared by every load or ``(n_load, n_tau)``
        (each row strictly increasing, >= 0).
    p0 : array_like
        Initial delta positions [Pa], ``(n_load,)``.
    walls : (Wall, Wall or None) or sequence of them
        ``(lower, upper)`` shared by every load, or one pair per load.
    rtol, atol, method, p_out, max_steps, options
        As in :func:`solve`.

    Returns
    -------
    EngineBatch
        A sequence of :class:`EngineResult` (one per load) with stacked ``(n_load, n_tau)``
        arrays.
    """
    t0 = time.perf_counter()
    p0v = np.atleast_1d(np.asarray(p0, dtype=float))
    n = p0v.size
    groups: dict[tuple, list[int]] = {}
    if isinstance(walls, tuple) and len(walls) == 2 and isinstance(walls[0], Wall):
        items = [(walls, [])]  # one shared pair, every load (not hashed: ~3 us a call)
    else:
        for i, pair in enumerate(_pairs(walls, n)):
            groups.setdefault(pair, []).append(i)
        items = list(groups.items())
    tau = np.asarray(tau_out, dtype=float)
    problems = []
    for (lower, upper), idx in items:  # validate every group before any work
        sel = np.asarray(idx) if len(items) > 1 else slice(None)
        tau_g = tau[sel] if tau.ndim == 2 else tau
        if tau.ndim == 2 and tau.shape[0] != n:
            raise ValueError(
                f"tau_out [Pa^2] must be shaped (n_tau,) or ({n}, n_tau); got {tau.shape}"
            )
        problems.append(
            (
                sel,
                make_problem(
                    tau_g, p0v[sel], lower, upper, rtol, atol, p_out, max_steps, options, batch=True
                ),
            )
        )
    picked = [_pick(pb, method) for _, pb in problems]  # every group's method before any work
    parts = [(sel, _run_group(pb, pick)) for (sel, pb), pick in zip(problems, picked, strict=True)]
    if len(parts) == 1:
        out = parts[0][1]
    else:
        out = _merge(parts, n)
    return EngineBatch(
        p0v,
        out["fields"],
        out["status"],
        out["message"],
        out["method"],
        out["nsteps"],
        out["n_nodes"],
        out["nfev"],
        problems[0][1].p_out,
        time.perf_counter() - t0,
        exact_balances=out.get("exact_balances"),
        success=out.get("success"),
    )


def _merge(parts: list[tuple[np.ndarray, dict]], n: int) -> dict:
    first = parts[0][1]
    fields: dict[str, Any] = {}
    for name, val in first["fields"].items():
        if isinstance(val, LazyField):
            val = val()
        if val is None:
            fields[name] = None
            continue
        full = np.empty((n, *np.shape(val)[1:]))
        for sel, part in parts:
            value = part["fields"][name]
            full[sel] = value() if isinstance(value, LazyField) else value
        fields[name] = full
    out: dict[str, Any] = {"fields": fields}
    for key in ("status", "message", "method"):
        lst: list[Any] = [None] * n
        for sel, part in parts:
            for j, i in enumerate(sel):
                lst[i] = part[key][j]
        out[key] = lst
    out["exact_balances"] = np.zeros(n, dtype=bool)
    out["success"] = np.zeros(n, dtype=bool)
    for sel, part in parts:
        out["exact_balances"][sel] = part.get("exact_balances", False)
        out["success"][sel] = (
            part["success"] if "success" in part else [s == "success" for s in part["status"]]
        )
    for key in ("nsteps", "n_nodes", "nfev"):
        arr = np.zeros(n, dtype=np.int64)
        for sel, part in parts:
            arr[sel] = part[key]
        out[key] = arr
    return out
