"""Boundary-element contact solves with tamaas, in SI units, with a checked convergence.

A rigid rough surface of heights ``h`` [m] (a periodic ``n x n`` map on a square cell of side
``L``; positive heights point towards the elastic body) is pressed on an elastic half-space of
contact modulus ``E*`` [Pa]. The map may already contain a macroscopic shape (a sphere, a
wavy profile): the solver only sees heights. Solvers (tamaas, Frérot, Anciaux and Molinari):

* elastic, frictionless, imposed mean pressure: ``PolonskyKeerRey`` (pressure primal);
* plastic at constant hardness ``H``: ``KatoSaturated`` (the contact pressure is capped at
  ``H``; the capped points carry the plastic area);
* adhesive (exponential law ``-w exp(-g / rho)`` per unit area), imposed mean gap:
  ``PolonskyKeerRey`` (gap primal) with ``ExponentialAdhesionFunctional``.

Inside, tamaas runs in reduced units (``L = 1``, ``E* = 1``); everything returned is SI.
Every solve returns the solver's final error; a solve whose error is not below the tolerance is
**not converged**: :func:`solve` raises :class:`BemConvergenceError` (or, with
``strict=False``, returns a :class:`BemState` whose reference values are NaN, flagged
``converged=False``). A non-converged solve is never a reference value.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

__all__ = [
    "BemConvergenceError",
    "BemState",
    "MissingTamaasError",
    "require_tamaas",
    "tamaas_version",
    "solve",
    "solve_gaps",
    "GapSolver",
]

#: Default relative tolerance of the pressure-controlled solves.
TOL = 1e-10
#: Default relative tolerance of the gap-controlled (adhesive) solves.
TOL_GAP = 1e-8
#: Default iteration limit of one solve attempt.
MAX_ITER = 1000
#: Restarts of a solve that did not reach its tolerance (each continues from the last
#: iterate with a fresh conjugate-gradient history: tamaas' iteration sometimes stalls on an
#: adhesive path and a restart converges); after them the solve is "not converged".
RETRIES = 4


class MissingTamaasError(ImportError):
    """tamaas, the boundary-element solver, is not installed."""


class BemConvergenceError(RuntimeError):
    """A boundary-element solve did not reach its tolerance."""


def require_tamaas() -> Any:
    """The ``tamaas`` module, or :class:`MissingTamaasError` with the install line."""
    try:
        import tamaas
    except ImportError as exc:
        raise MissingTamaasError(
            'the boundary-element cross-check needs tamaas: pip install "xpersson[bem]"'
        ) from exc
    return tamaas


def tamaas_version() -> str:
    """Version string of the installed tamaas (raises :class:`MissingTamaasError`)."""
    return str(require_tamaas().__version__)


@dataclass(frozen=True)
class BemState:
    """One converged (or flagged) contact state, SI.

    Attributes
    ----------
    p0 : float
        Mean (nominal) pressure [Pa]: the imposed one, or the one reached under gap control.
    area_fraction : float
        Fraction of the cell in contact (traction > 0; adhesive: gap <= 0) [1].
    mean_gap : float
        Mean gap between the surfaces [m] (zero on the contact points).
    gap_edges, gap_density : numpy.ndarray
        Histogram of the gap over the whole cell: bin edges [m] and density [1/m] (the
        contact points fall in the first bin; integral 1).
    pressure_mean, pressure_m2, pressure_contact_mean, pressure_max : float
        ``<p>`` [Pa] and ``<p^2>`` [Pa^2] over the cell, the mean over the contact [Pa] and the
        largest contact pressure [Pa].
    plastic_area_fraction : float
        Fraction of the cell at the hardness (plastic solves; 0 otherwise) [1].
    error, tolerance : float
        The solver's final error and its tolerance [1].
    converged : bool
        ``error < tolerance``; when False every reference value above is NaN.
    contact : numpy.ndarray or None
        The boolean contact map (``keep_fields=True`` only).
    gap : numpy.ndarray or None
        The gap map [m] (``keep_fields=True`` only).
    pressure : numpy.ndarray or None
        The traction map [Pa] (``keep_fields=True`` only; negative: adhesive tension).
    """

    p0: float
    area_fraction: float
    mean_gap: float
    gap_edges: np.ndarray
    gap_density: np.ndarray
    pressure_mean: float
    pressure_m2: float
    pressure_contact_mean: float
    pressure_max: float
    plastic_area_fraction: float
    error: float
    tolerance: float
    converged: bool
    contact: np.ndarray | None = field(default=None, repr=False)
    gap: np.ndarray | None = field(default=None, repr=False)
    pressure: np.ndarray | None = field(default=None, repr=False)


def _model(tm: Any, n: int) -> Any:
    tm.set_log_level(tm.LogLevel.error)
    model = tm.ModelFactory.createModel(tm.model_type.basic_2d, [1.0, 1.0], [n, n])
    model.E, model.nu = 1.0, 0.0  # E* = 1 in reduced units
    return model


def _check_map(heights: np.ndarray, L: float, E_star: float) -> np.ndarray:
    h = np.asarray(heights, dtype=float)
    if h.ndim != 2 or h.shape[0] != h.shape[1] or h.shape[0] < 4:
        raise ValueError(f"heights [m] must be a square n x n map with n >= 4; got {h.shape}")
    if not np.all(np.isfinite(h)):
        raise ValueError("heights [m] must be finite")
    for name, v in (("L [m]", L), ("E_star [Pa]", E_star)):
        if not (v > 0 and math.isfinite(v)):
            raise ValueError(f"{name} must be finite and > 0; got {v!r}")
    return np.ascontiguousarray(h / L)


def _state(
    model: Any,
    surf: np.ndarray,
    scale: tuple[float, float],
    err: float,
    tol: float,
    opts: dict[str, Any],
) -> BemState:
    """Read a solved model (reduced units) into an SI :class:`BemState`."""
    L, E_star = scale
    tr = np.asarray(model.traction).reshape(surf.shape)
    if opts["gap_control"]:
        gap = np.asarray(model["gap"]).reshape(surf.shape).copy()
        contact = gap <= 0.0
        gap = np.maximum(gap, 0.0)
    else:
        contact = tr > 0.0
        gap = np.asarray(model.displacement).reshape(surf.shape) - surf
        gap = np.maximum(gap - (gap[contact].mean() if contact.any() else gap.min()), 0.0)
    converged = bool(err < tol)
    gap_si = gap * L
    edges = np.asarray(opts["gap_edges"]) if opts["gap_edges"] is not None else None
    if edges is None:
        top = float(gap_si.max()) if gap_si.max() > 0 else L * 1e-12
        edges = np.linspace(0.0, top, opts["gap_bins"] + 1)
    dens, edges = np.histogram(gap_si, bins=edges, density=False)
    dens = dens / (gap_si.size * np.diff(edges))
    p = tr * E_star
    hard = opts["hardness"]
    vals = {
        "p0": float(p.mean()),
        "area_fraction": float(contact.mean()),
        "mean_gap": float(gap_si.mean()),
        "pressure_mean": float(p.mean()),
        "pressure_m2": float(np.mean(p**2)),
        "pressure_contact_mean": float(p[contact].mean()) if contact.any() else 0.0,
        "pressure_max": float(p.max()),
        "plastic_area_fraction": float(np.mean(tr >= hard * (1 - 1e-9))) if hard else 0.0,
    }
    if not converged:
        vals = {k: math.nan for k in vals}
        dens = np.full_like(dens, math.nan, dtype=float)
    keep = opts["keep_fields"] and converged
    return BemState(
        **vals,
        gap_edges=edges,
        gap_density=dens,
        error=float(err),
        tolerance=tol,
        converged=converged,
        contact=contact.copy() if keep else None,
        gap=gap_si if keep else None,
        pressure=p.copy() if keep else None,
    )


def _attempt(solver: Any, target: float, tol: float) -> float:
    """Solve, restarting up to :data:`RETRIES` times while the error is not below ``tol``."""
    err = float(solver.solve(target))
    for _ in range(RETRIES):
        if err < tol:
            break
        err = float(solver.solve(target))
    return err


def _finish(state: BemState, strict: bool, what: str) -> BemState:
    if strict and not state.converged:
        raise BemConvergenceError(
            f"tamaas did not converge at {what}: error {state.error:.3g} >= tolerance "
            f"{state.tolerance:.3g}; refine the grid, lower the load or raise max_iter"
        )
    return state


def solve(
    heights: np.ndarray,
    L: float,
    E_star: float,
    p0: Sequence[float] | np.ndarray,
    *,
    hardness: float | None = None,
    tol: float = TOL,
    max_iter: int = MAX_ITER,
    strict: bool = True,
    gap_bins: int = 64,
    gap_edges: np.ndarray | None = None,
    keep_fields: bool = False,
) -> list[BemState]:
    """Frictionless contact of a rigid rough map on an elastic half-space at mean pressures.

    Parameters
    ----------
    heights
        Periodic ``(n, n)`` height map [m] (may include a macroscopic shape); positive heights
        point towards the elastic body.
    L
        Side of the square cell [m].
    E_star
        Contact modulus ``E / (1 - nu^2)`` of the half-space [Pa] (rigid counter-surface; for
        two elastic bodies pass the combined modulus).
    p0
        Mean nominal pressures [Pa], each > 0; solved in the given order (each solve starts
        from the previous state).
    hardness
        Indentation hardness [Pa]: the contact pressure is capped there (``KatoSaturated``);
        ``None``: elastic (``PolonskyKeerRey``).
    tol, max_iter
        Solver tolerance [1] and iteration limit of one attempt (a solve above the tolerance
        is restarted from its last iterate up to :data:`RETRIES` times).
    strict
        Raise :class:`BemConvergenceError` on a non-converged solve (default); False: return
        it flagged, its values NaN.
    gap_bins, gap_edges
        Bins of the gap histogram: ``gap_bins`` equal bins from 0 to the largest gap, or the
        given edges [m] (the same edges for every load allow averaging).
    keep_fields
        Keep the contact map and gap map in each state.

    Returns
    -------
    list of BemState
        One per load, in the order of ``p0``.
    """
    tm = require_tamaas()
    surf = _check_map(heights, L, E_star)
    loads = np.atleast_1d(np.asarray(p0, dtype=float))
    if np.any(~np.isfinite(loads)) or np.any(loads <= 0):
        raise ValueError(f"p0 [Pa] must be finite and > 0; got {loads.tolist()}")
    if hardness is not None and not (hardness > 0 and math.isfinite(hardness)):
        raise ValueError(f"hardness [Pa] must be finite and > 0; got {hardness!r}")
    if hardness is not None and np.any(loads >= hardness):
        raise ValueError(f"p0 [Pa] must stay below the hardness {hardness:g} Pa")
    model = _model(tm, surf.shape[0])
    if hardness is None:
        solver = tm.PolonskyKeerRey(model, surf, tol)
    else:
        solver = tm.KatoSaturated(model, surf, tol, hardness / E_star)
    solver.max_iter = int(max_iter)
    opts = {
        "gap_control": False,
        "gap_bins": gap_bins,
        "gap_edges": gap_edges,
        "hardness": None if hardness is None else hardness / E_star,
        "keep_fields": keep_fields,
    }
    out = []
    for p in loads:
        err = _attempt(solver, float(p / E_star), tol)
        st = _state(model, surf, (L, E_star), err, tol, opts)
        out.append(_finish(st, strict, f"p0 = {p:.6g} Pa"))
    return out


class GapSolver:
    """A gap-controlled tamaas solver that keeps its state between solves (a loading path).

    Parameters are those of :func:`solve_gaps`; :meth:`at` solves at one mean gap [m].
    """

    def __init__(
        self,
        heights: np.ndarray,
        L: float,
        E_star: float,
        *,
        work: float = 0.0,
        rho: float | None = None,
        tol: float = TOL_GAP,
        max_iter: int = MAX_ITER,
        strict: bool = True,
        gap_bins: int = 64,
        gap_edges: np.ndarray | None = None,
        keep_fields: bool = False,
    ) -> None:
        tm = require_tamaas()
        self._surf = _check_map(heights, L, E_star)
        if work < 0 or (work > 0 and not (rho is not None and rho > 0)):
            raise ValueError(f"need work [J/m^2] >= 0 and rho [m] > 0; got {work!r}, {rho!r}")
        self._scale = (L, E_star)
        self._tol, self._strict = tol, strict
        self._model = _model(tm, self._surf.shape[0])
        kind = tm.PolonskyKeerRey.gap
        self._solver = tm.PolonskyKeerRey(self._model, self._surf, tol, kind, kind)
        self._solver.max_iter = int(max_iter)
        self._adh = None  # kept alive: the solver holds a raw pointer to it
        if work > 0:
            self._adh = tm.ExponentialAdhesionFunctional(self._surf)
            self._adh.parameters = {"rho": rho / L, "surface_energy": work / (E_star * L)}
            self._solver.addFunctionalTerm(self._adh)
        self._opts = {
            "gap_control": True,
            "gap_bins": gap_bins,
            "gap_edges": gap_edges,
            "hardness": None,
            "keep_fields": keep_fields,
        }

    def at(self, gap: float) -> BemState:
        """Solve at the mean gap ``gap`` [m], starting from the previous state."""
        err = _attempt(self._solver, float(gap / self._scale[0]), self._tol)
        st = _state(self._model, self._surf, self._scale, err, self._tol, self._opts)
        return _finish(st, self._strict, f"mean gap {gap:.6g} m")


def solve_gaps(
    heights: np.ndarray,
    L: float,
    E_star: float,
    gaps: Sequence[float] | np.ndarray,
    **kwargs: Any,
) -> list[BemState]:
    """Contact at imposed mean gaps, optionally adhesive (exponential law), in sequence.

    Displacement control follows the unstable parts of an adhesive loading curve (approach,
    retraction, pull-off) that load control cannot. The adhesive energy per unit area is
    ``-work exp(-g / rho)`` (maximum traction ``work / rho``).

    Parameters
    ----------
    heights, L, E_star
        As in :func:`solve` ([m], [m], [Pa]).
    gaps
        Mean gaps [m], solved in order (a path: each solve starts from the previous one).
    **kwargs
        ``work`` [J/m^2] (default 0: non-adhesive), ``rho`` [m] (the law's range, needed
        when ``work > 0``), and ``tol``, ``max_iter``, ``strict``, ``gap_bins``,
        ``gap_edges``, ``keep_fields`` as in :func:`solve` (see :class:`GapSolver`).

    Returns
    -------
    list of BemState
        One per gap; ``p0`` is the mean stress reached [Pa] (negative: tensile).
    """
    path = GapSolver(heights, L, E_star, **kwargs)
    return [path.at(g) for g in np.atleast_1d(np.asarray(gaps, dtype=float))]
