"""Front-fixed Crank-Nicolson solver for moving walls (absorbing or yield closure).

Scheme
------
* Window.  The free solution ``G = N(p; p0, 2 tau)`` bounds P from above for absorbing walls, and
  mass released by a yield wall starts above ``p0``; so the domain is truncated to
  ``[max(l, p0 - k s), min(u, p0 + k s)]`` with ``s = sqrt(2 tau)`` and artificial absorbing walls
  where the real ones are farther (error ``<= erfc(k/sqrt 2)`` each, ``k`` from ``atol``,
  widened where the load the upper edge absorbs above a real lower wall would miss the
  tolerance: :func:`._problem.load_window_k`).  The window follows the growing support
  ``~ sqrt(tau)``; a yield wall stays real once it entered (it carries the plastic area it
  releases), unless it leaves the window again with a negligible plastic area
  (``_cn_control._release``: then it is real only while inside).
* Front fixing.  Nodes ``p_j(tau) = l_eff(tau) + W(tau) x_j`` on a fixed map ``x_j`` of [0, 1]
  clustered at both walls.  The unknown ``R = W P`` (mass per unit x) obeys the conservation law
  ``R_tau = d/dx [R_x / W^2 + (v / W) R]`` with the mesh velocity ``v = l_eff' + x W'``.
* Finite volumes.  Control volumes between face midpoints (the trapezoid weights), face fluxes
  ``F = (R_{j+1} - R_j)/(W^2 dx) + v (R_j + R_{j+1})/(2W)``: the discrete mass changes exactly
  by the wall fluxes, which are what is counted as absorbed (non-contact / plastic area), so
  ``area + absorbed = initial mass`` holds to round-off at every step and every refinement level
  (and for their Richardson combination): the area never exceeds 1.
* Start.  Analytic: the free Gaussian at ``tau_s``, the largest time at which no real wall lies
  inside the window (its discrete mass set to the window mass ``erf(k/sqrt 2)``).
* Time.  Geometric steps merged with the output times and the kinks of the window edges;
  Crank-Nicolson with two implicit-Euler half steps first (Rannacher).  One tridiagonal solve
  per step for all loads of a batch (their systems concatenated); the operators are built
  vectorised for a block of steps at a time, so memory stays proportional to the grid and a
  step costs one flux-form product and one LAPACK ``dgtsv`` call.
* Yield closure.  ``P(Y) = A_pl Y'``: the last node is a half cell whose mass plus ``A_pl``
  changes by the flux through its inner face (``dA_pl/dtau = -Y' P(Y) - P_p(Y)`` at the wall),
  solved implicitly with the interior (one row of the tridiagonal system).
* Accuracy (aimed at the request, see :mod:`._cn_control`).  A pilot pair of grids
  ``(N0, 2 N0)`` measures the constant of the second-order error; the final grid ``N`` is chosen
  so that the error estimate of the result is about ``AIM = 0.5`` times ``rtol |A| + atol`` and
  the pair ``(N/2, N)`` is solved; the result is the finer solution, its error estimate
  ``2 |R_N - R_{N/2}| / 3`` (twice the asymptotic value).  For tight tolerances, where second
  order would need very fine grids, four nested levels ``N, 2N, 3N, 4N`` (twice the steps per
  node) are combined by Richardson extrapolation to sixth order, twice (levels 1-3 and 2-4):
  the result is the finer combination, its error estimate their difference.  If an estimate
  misses the tolerance the grid is refined again, up to ``max_steps`` / ``levels``; ``status``
  says when it could not.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from . import _compiled
from ._base import EngineMethod
from ._cn_assemble import _assemble
from ._cn_control import AIM, _control, _Fit
from ._cn_kinks import kinks_apart
from ._cn_plan import _exact_start, _joint_plan, _Plan, _start_time, _switch_times_batch
from ._level import Level, Outputs
from ._moving import LevelInputs, _march, level_inputs
from ._problem import Problem, load_window_k, window_k
from ._result import Raw
from ._stiff import stiff_refined, wall_kinks

__all__ = ["CNMethod", "grid_level"]

Array = NDArray[np.float64]


class CNMethod(EngineMethod):
    """Moving (or fixed) walls: front-fixed finite-volume Crank-Nicolson, error aimed at rtol."""

    name = "cn"
    batched = True

    @classmethod
    def admits(cls, problem: Problem) -> bool:
        return True

    def run(self) -> Raw:
        pb = self.problem
        if pb.is_batch:
            n = pb.tau.shape[0]
            shared = n == 1 or bool(np.all(pb.tau == pb.tau[:1]))
            if not shared:  # loads on different clocks: one at a time
                raws = [self._run([pb.load(i)]) for i in range(n)]
                return _stack(raws)
            return self._run([pb.load(i) for i in range(n)])
        raw = self._run([pb])
        return _unbatch(raw)

    # -- the solver --------------------------------------------------------------------------
    def _run(self, pbs: list[Problem]) -> Raw:
        pb = pbs[0]
        opts = _options(pbs)
        tau = pb.tau
        tau_s = _start_time(pbs, opts.window_k, scan=_compiled.built("start"))
        tau_s, image = _exact_start(pbs, opts.window_k, tau_s)
        analytic = tau <= tau_s
        num = ~analytic
        nb = len(pbs)
        marched = bool(np.count_nonzero(num))
        lv = _Grids(pbs, opts, tau_s, num, image, marched)
        lower_at = _tabled_positions(pb)
        if marched:
            at_num = None if lower_at is None else lower_at[num]
            fit = _control(lv, pb, opts.aim, tau[num], at_num)
            if fit.best is None:
                return self._failed(nb, fit.status, fit.message or "no level completed", lv.nsteps)
        else:
            fit = _Fit(np.full((nb, 0), np.inf))
        raw = _assemble(pbs, opts.window_k, analytic, fit, lv)
        raw.lower_at = lower_at
        return raw

    def _failed(self, nb: int, status: str, message: str, nsteps: int) -> Raw:
        n_t = self.problem.tau.shape[-1]
        nan = np.full((nb, n_t), np.nan)
        return Raw(nan, nan, nan, nan, nan, nan, nan, None, status, message, nsteps, 0, nsteps)


def _options(pbs: list[Problem]) -> CNOptions:
    """The options of the loads ``pbs`` (one batch, one clock); the window half-width, unless
    given, widened so that the load it loses meets the tolerance too (:func:`load_window_k`)."""
    pb = pbs[0]
    opts = CNOptions.read(pb.options, pb.atol)
    if "window_k" in pb.options or not pb.tau.size:
        return opts
    tau = pb.tau
    shared = all(p.lower is pb.lower for p in pbs[1:])
    lower = pb.lower.at(tau) if shared else np.stack([p.lower.at(tau) for p in pbs])
    p0 = [p.p0 for p in pbs]
    k = load_window_k(opts.window_k, p0, lower, tau, pb.rtol, pb.atol)
    if k != opts.window_k:
        opts.__dict__["window_k"] = k  # (frozen: a fresh instance from read, owned here)
    return opts


def _tabled_positions(pb: Problem) -> Array | None:
    """The lower wall's positions [Pa] at the output times where it carries a table evaluated
    by the compiled loop and there is no upper wall (point by point: the load scale and the
    batch's balances take them instead of asking the wall twice more), else None."""
    lo = pb.lower
    if pb.upper is not None or lo.table is None or not callable(lo.position):
        return None
    return lo.table.compiled(pb.tau)


def _unbatch(raw: Raw) -> Raw:
    for name in (
        "area",
        "non_area",
        "absorbed_lower",
        "absorbed_upper",
        "load",
        "wall_term",
        "error_estimate",
    ):
        setattr(raw, name, getattr(raw, name)[0])
    if raw.P is not None:
        raw.P = raw.P[0]
    return raw


def _stack(raws: list[Raw]) -> Raw:
    out = Raw(
        *(
            np.concatenate([getattr(r, f) for r in raws])
            for f in (
                "area",
                "non_area",
                "absorbed_lower",
                "absorbed_upper",
                "load",
                "wall_term",
                "error_estimate",
            )
        )
    )
    out.P = None if raws[0].P is None else np.concatenate([r.P for r in raws])
    out.status = np.array([r.status for r in raws], dtype=object)
    out.message = [r.message for r in raws]
    out.nsteps = np.array([r.nsteps for r in raws])
    out.n_nodes = np.array([r.n_nodes for r in raws])
    out.nfev = np.array([r.nfev for r in raws])
    return out


GRADED_STRETCH = 2.0  # node clustering of a march that crosses a declared breakpoint: after a
# square-root onset the error sits at the moving wall (measured on the jkr onset scene of
# benchmarks/summary.py: E at stretch 2 converges at order ~3 and reaches rtol 1e-6 with a
# grid 1.5x coarser than at the default 1; more time steps changed nothing there)


#: The defaults of :class:`CNOptions` but the two read from the tolerance and ``AIM``.
_DEFAULTS: dict[str, Any] = {
    "nodes": 24,
    "per_node": 0.25,
    "levels": 20,
    "max_work": 1e8,
    "stretch": 1.0,
    "rannacher": 2,
}


@dataclass(frozen=True)
class CNOptions:
    """Options of ``cn`` (``solve(options=...)``), typed and checked.

    Attributes
    ----------
    nodes : int
        Intervals of the pilot grid (24).
    per_node : float
        Time steps per decade per grid interval (``steps_per_decade / nodes``; 0.25).
    levels : int
        Most grids solved (20).
    max_work : float
        Node-steps per load over all grids (1e8).
    stretch : float
        Clustering of the nodes at the walls (1).
    rannacher : int
        Implicit-Euler half-step pairs at the start (2).
    window_k : float
        Half-width of the window in units of ``sqrt(2 tau)`` (from ``atol``; :func:`_options`
        widens it for the load identity, :func:`._problem.load_window_k`).
    aim : float
        Error estimate the next grid is aimed at, as a fraction of the tolerance, in (0, 1].
    """

    nodes: int
    per_node: float
    levels: int
    max_work: float
    stretch: float
    rannacher: int
    window_k: float
    aim: float

    @classmethod
    def read(cls, opt: dict[str, Any], atol: float) -> CNOptions:
        """The options of ``opt`` (defaults filled in); ValueError naming option and range."""
        d = _DEFAULTS
        if not opt:  # the defaults (the frozen dataclass's per-field __setattr__ skipped)
            out = object.__new__(cls)
            out.__dict__.update(d, window_k=float(window_k(atol)), aim=float(AIM))
            return out
        n0 = int(opt.get("nodes", d["nodes"]))
        per_node = (
            float(opt.get("steps_per_decade", 0.0)) / n0
            if "steps_per_decade" in opt
            else d["per_node"]
        )
        aim = float(opt.get("aim", AIM))
        if not 0.0 < aim <= 1.0:
            raise ValueError(
                f"options['aim'] [1] (error estimate aimed at, as a fraction of "
                f"the tolerance) must be in (0, 1]; got {aim!r}"
            )
        return cls(
            nodes=n0,
            per_node=per_node,
            levels=int(opt.get("levels", d["levels"])),
            max_work=float(opt.get("max_work", d["max_work"])),
            stretch=float(opt.get("stretch", d["stretch"])),
            rannacher=int(opt.get("rannacher", d["rannacher"])),
            window_k=float(opt.get("window_k", window_k(atol))),
            aim=aim,
        )


class _Grids:
    """The grid levels of one solve: each solved once, within the budgets.

    Levels are keyed ``(n_base, mult, dense)`` (see :mod:`._cn_control`).  ``solved`` holds
    the outputs of every level solved so far and ``plans`` the time plan of every
    ``(n_base, dense)``: these are the solve's own state, not caches (the levels of one
    plan must share it to be nested; the budgets count the levels solved, and a search
    ended by a budget falls back to the finest solved pair, see
    :func:`._cn_control._finest_pair`).  ``stop``: ``(status, message)`` once a budget (or a
    failed level) ended the search; then no level is returned any more.
    """

    def __init__(
        self,
        pbs: list[Problem],
        opts: CNOptions,
        tau_s: float,
        num: Array,
        image: float | None = None,
        marched: bool | None = None,
    ) -> None:
        self.pbs, self.opts, self.tau_s, self.image = pbs, opts, tau_s, image
        pb = pbs[0]
        lo, up = pb.lower, pb.upper
        bps = (*lo.breakpoints, *up.breakpoints) if up is not None else lo.breakpoints
        # the march crosses a declared breakpoint: its nodes clustered more at the walls
        # (GRADED_STRETCH) unless options['stretch'] is given
        self.graded = bool(bps) and any(t >= tau_s for t in bps)
        given = pb.options is not None and "stretch" in pb.options
        self.stretch = GRADED_STRETCH if self.graded and not given else opts.stretch
        self.solved: dict[tuple[int, int, int], Outputs] = {}
        self.plans: dict[tuple[int, int], _Plan] = {}
        self.stop: tuple[str, str] | None = None
        self.nsteps = 0
        self.work = 0.0
        self.kinks: list[float] = []
        self.release = False  # yield walls released once they leave the window (_Plan.release)
        if np.count_nonzero(num) if marched is None else marched:
            # the kinks of the window edges do not depend on the grid: found once (the
            # marched outputs are the last ones: the output times increase)
            t_end = float(pb.tau[-1])
            k = opts.window_k
            found = _switch_times_batch(pbs, k, tau_s, t_end) + wall_kinks(pb, tau_s, t_end)
            self.kinks = kinks_apart(found, pb.tau)  # (none a few ulps from another time)

    def levels(self, n_base: int, mults: tuple[int, ...], dense: int) -> list[Outputs] | None:
        """The levels ``(n_base, m, dense)`` for ``m`` in ``mults``, solved in this order
        (None as soon as one cannot be: ``stop`` says why)."""
        out = []
        for m in mults:
            level = self.level(n_base, m, dense)
            if level is None:
                return None
            out.append(level)
        return out

    def level(self, n_base: int, mult: int, dense: int = 1) -> Outputs | None:
        """Grid ``n_base * mult`` on the time plan of ``n_base`` (at ``dense`` times the steps
        per decade of ``options['per_node']``) subdivided ``mult`` times; None (and ``stop``
        set) when a budget ends the search or the level fails."""
        if self.stop is not None:
            return None
        key = (n_base, mult, dense)
        opts, pb = self.opts, self.pbs[0]
        if key not in self.solved:
            plan = self.plan(n_base, dense)
            cost = (plan.base.size - 1) * mult + 2 * opts.rannacher
            if self.nsteps + cost > pb.max_steps:
                msg = f"max_steps = {pb.max_steps} reached before the tolerance was met"
                return self._stop("max_steps", msg)
            if self.work + cost * n_base * mult > opts.max_work:
                return self._stop(
                    "max_steps",
                    f"the next grid (N = {n_base * mult}, {cost} steps) would exceed "
                    f"the work budget options['max_work'] = {opts.max_work:.3g} node-steps; "
                    "loosen rtol/atol or raise max_work",
                )
            self.work += cost * n_base * mult
            if len(self.solved) >= opts.levels:
                msg = f"after {len(self.solved)} grids (levels = {opts.levels})"
                return self._stop("tolerance_not_met", msg)
            level = _march(self.pbs, plan, n_base * mult, mult, self.stretch, opts.rannacher)
            if not level.ok:
                return self._stop("tolerance_not_met", f"numerical failure: {level.failure}")
            self.solved[key] = level.outputs
            self.nsteps += level.nsteps
        return self.solved[key]

    def plan(self, n_base: int, dense: int) -> _Plan:
        """The time plan of the levels ``(n_base, *, dense)`` (made on first use)."""
        if (n_base, dense) not in self.plans:
            per_decade = self.opts.per_node * n_base * dense
            k, fast = self.opts.window_k, _compiled.built("plan")
            plan = _joint_plan(self.pbs, k, per_decade, self.tau_s, self.kinks, fast)
            plan.image, plan.release = self.image, self.release
            # substeps where a yield wall makes the window stiff (:mod:`._stiff`)
            self.plans[n_base, dense] = stiff_refined(self.pbs, plan, per_decade)
        return self.plans[n_base, dense]

    def _stop(self, status: str, message: str) -> None:
        """End the search: ``status`` and ``message`` go to the result."""
        self.stop = (status, message)


def grid_level(
    pbs: list[Problem], n_base: int, mult: int = 1, dense: int = 1
) -> tuple[LevelInputs, Level]:
    """The inputs and the march of the grid level ``(n_base, mult, dense)`` (see
    :mod:`._cn_control`) of the loads ``pbs`` (one batch), as :class:`CNMethod` solves it:
    for tests (the reference solver of ``tests/engine``) and benchmarks."""
    opts = _options(pbs)
    tau_s = _start_time(pbs, opts.window_k)
    grids = _Grids(pbs, opts, tau_s, pbs[0].tau > tau_s)
    plan = grids.plan(n_base, dense)
    args = (pbs, plan, n_base * mult, mult, grids.stretch, opts.rannacher)
    return level_inputs(*args), _march(*args)
