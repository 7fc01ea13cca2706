"""Input validation: a :class:`Problem` holds checked SI floats and numpy arrays only."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.special import erfcinv

from ..cache import Cache
from ._views import broadcast_view
from ._wall_table import kernels as table_kernels
from ._walls import Wall

__all__ = ["Problem", "make_problem", "window_k", "load_window_k", "sample_times"]

Array = NDArray[np.float64]


@dataclass(frozen=True)
class Problem:
    """A validated engine request (see :func:`xpersson.engine.solve` for the meaning)."""

    tau: Array  # output diffusion times [Pa^2], increasing, >= 0; (n_load, n_tau) in a batch
    p0: float | Array  # delta position [Pa]; a (n_load, 1) column in a batch
    lower: Wall
    upper: Wall | None
    rtol: float
    atol: float
    p_out: Array | None  # pressures [Pa] where P is wanted
    max_steps: int
    options: dict[str, Any] = field(default_factory=dict)

    @property
    def tau_max(self) -> float:
        t = self.tau
        return float(t[-1]) if t.ndim == 1 else float(t[:, -1].max())

    @property
    def is_batch(self) -> bool:
        """True for a batch of loads (``tau`` 2-D, ``p0`` a column)."""
        return self.tau.ndim == 2

    def load(self, i: int) -> Problem:
        """The single-load Problem of load ``i`` of a batch."""
        if not self.is_batch:
            return self
        # (the fields as they are but two: dataclasses.replace's checks cost ~3 us a load)
        return _problem(
            np.ascontiguousarray(self.tau[i]),
            float(self.p0[i, 0]),
            self.lower,
            self.upper,
            self.rtol,
            self.atol,
            self.p_out,
            self.max_steps,
            self.options,
        )

    def tolerance(self, area: ArrayLike) -> Array:
        """Allowed absolute error of the area, ``rtol |area| + atol``."""
        return self.rtol * np.abs(np.asarray(area, dtype=float)) + self.atol

    def output_positions(self) -> tuple[Array, Array]:
        """(lower, upper) wall positions [Pa] at the output times: 0-d arrays for fixed walls
        and a missing upper one (+inf), which broadcast; else per tau (a row shared by the
        loads evaluated once)."""
        lower, upper, t = self.lower, self.upper, self.tau
        if upper is None and not lower.is_fixed:  # (no full array of inf, nor copies per load)
            shared = t.ndim == 2 and t.shape[0] > 1 and t.strides[0] == 0
            return lower.at(t[0] if shared else t), np.asarray(np.inf)
        if lower.is_fixed and (upper is None or upper.is_fixed):
            up = float(upper.position) if upper is not None else np.inf
            return np.asarray(float(lower.position)), np.asarray(up)
        return self.wall_positions(t)

    def wall_positions(self, tau: ArrayLike) -> tuple[Array, Array]:
        """(lower, upper) positions [Pa] at ``tau``; upper is +inf without an upper wall."""
        t = np.asarray(tau, dtype=float)
        if t.ndim == 2 and t.shape[0] > 1 and t.strides[0] == 0:  # one row shared by the loads
            lo, up = self.wall_positions(t[0])
            return (np.broadcast_to(lo, t.shape).copy(), np.broadcast_to(up, t.shape).copy())
        lo = self.lower.at(tau)
        up = self.upper.at(tau) if self.upper is not None else np.full(lo.shape, np.inf)
        return lo, up


def window_k(atol: float) -> float:
    """Half-width of the truncation window in units of ``sqrt(2 tau)``.

    Chosen so that the probability that a free path leaves the window, ``erfc(k/sqrt 2)``, is
    below ``atol / 100``.
    """
    k = math.sqrt(2.0) * float(erfcinv(max(1e-300, 0.01 * atol)))
    return min(max(k, 5.0), 40.0)  # (numpy's clip of a scalar, without its dispatch)


def _load_lost(k: float, sigma: Array, d_lo: Array, d_hi: Array, scale: Array) -> float:
    """Bound [1] of the load lost through an artificial upper edge at ``p0 + k sigma`` (``sigma
    = sqrt(2 tau)`` [Pa] per output) relative to the load scale ``scale`` [Pa] per (load,
    output), the lower wall ``d_lo .. d_hi`` [Pa] below ``p0`` so far: the largest
    ``2 k^3 phi(k) d ln(k sigma / d) / scale`` over that range (see :func:`load_window_k`); 0
    where the wall has not entered the window."""
    reach = k * sigma
    d = np.clip(reach / math.e, d_lo, d_hi)
    g = d * np.log(np.maximum(reach / d, 1.0))
    phi = math.exp(-0.5 * k * k) / math.sqrt(2.0 * math.pi)
    return float(np.max(2.0 * k**3 * phi * g / scale, initial=0.0))


def _quick_bound(k: float, p: Array, lo: Array, t: Array) -> float:
    """An upper bound [1] of :func:`_load_lost` at ``k`` that needs no distances so far:
    ``d ln(k sigma / d) <= k sigma / e`` for every ``d > 0``, so the loss is at most
    ``2 k^4 phi(k) sigma / (e scale)`` at each output (``p`` (loads, 1) [Pa], ``lo`` (loads or
    1, outputs) [Pa], ``t`` (outputs,) [Pa^2]). Where it meets the tolerance so does the bound
    itself, and :func:`load_window_k` returns ``k`` unchanged after a few operations instead
    of some thirty (a tenth of a small ``cn`` solve's time)."""
    scale = np.maximum(np.abs(p), np.abs(lo))
    pos = scale > 0.0  # (scale 0: no load scale, left out as the bound leaves it: ratio 0)
    ratio = np.divide(np.sqrt(2.0 * np.maximum(t, 0.0)), scale, out=np.zeros(pos.shape), where=pos)
    phi = math.exp(-0.5 * k * k) / math.sqrt(2.0 * math.pi)
    return 2.0 * k**4 * phi / math.e * (float(ratio.max()) if ratio.size else 0.0)


def load_window_k(
    k: float, p0: ArrayLike, lower: ArrayLike, tau: ArrayLike, rtol: float, atol: float
) -> float:
    """The window half-width ``k`` [1] (from :func:`window_k`), widened until the *load* the
    window loses is below ``(rtol + atol) / 100`` of the load scale as well (a thousandth of
    the load balance's tolerance ``10 (rtol + atol)``, as ``window_k`` bounds the probability
    by ``atol / 100``: the error control judges the load identity's difference between grid
    levels, and a loss near the tolerance there costs refinements, found at ``/ 10``: fuzz
    seed 191 scene 4891 ended ``max_steps`` at ``k = 6.57`` and succeeds at 6.94).

    ``p0`` [Pa], one per load; ``tau`` [Pa^2], the output times; ``lower`` [Pa], the lower
    wall there, one row per load (or one row for all).  An artificial upper edge above a real
    lower wall absorbs paths that survived the wall: their first moment, about
    ``c d k^3 phi(k) ln(tau / tau_in)`` (``d = p0 - lower``, ``phi`` the standard normal
    density, ``tau_in = (d / k)^2 / 2`` where the wall entered the window: the loss per e-fold
    of ``tau`` is constant while the wall is inside; ``c`` measured 0.52-0.54 at ``k = 5.5 ..
    6.5``, ``sqrt(2 tau) / d = 1e3``, and 0.70 at 1e6; taken as 1 here, with ``d`` the least
    favourable distance so far), is what the load balance misses, relative to
    ``max(|p0|, |lower|)``.  ``window_k`` bounds only the probability lost: at ``atol =
    6e-7`` (k = 5.8) and ``sqrt(2 tau) / |lower| = 1.4e6`` the load balance was off by 8.7e-5
    against ``10 (rtol + atol) = 3e-5`` (``benchmarks/fuzz.py --seed 191 --methods 1``, scene
    328, ``tests/engine/test_window_load.py``).  Returns ``k`` itself (the same float) where
    it already meets the bound, as it does at the engine's default ``atol = 1e-7 rtol`` for a
    wall that stays within a few ``max(|p0|, |lower|)`` of ``p0`` (and at the pipeline's
    ``atol = 1e-12`` unless ``rtol`` is below ~3e-8 and the load light); otherwise the
    smallest ``k`` meeting it, at most 40.
    """
    t = np.asarray(tau, dtype=float).ravel()
    p = np.asarray(p0, dtype=float).reshape(-1, 1)
    lo = np.asarray(lower, dtype=float).reshape(-1, t.size)
    tol = 0.01 * (rtol + atol)
    if _quick_bound(k, p, lo, t) <= tol:  # (the common case, in a few operations)
        return k
    d = p - lo  # (loads, outputs): the wall's distance below p0 [Pa]
    ok = np.isfinite(d) & (d > 0.0)
    if not np.any(ok):
        return k
    d = np.where(ok, d, np.inf)
    d_lo = np.minimum.accumulate(d, axis=1)
    d_hi = np.maximum.accumulate(np.where(ok, d, 0.0), axis=1)
    scale = np.maximum(np.abs(p), np.abs(np.where(ok, lo, 0.0)))
    keep = ok & (scale > 0.0)
    sigma = np.broadcast_to(np.sqrt(2.0 * np.maximum(t, 0.0)), d.shape)
    args = (sigma[keep], d_lo[keep], d_hi[keep], scale[keep])
    if _load_lost(k, *args) <= tol:
        return k
    a, b = k, 40.0
    if _load_lost(b, *args) > tol:
        return b
    for _ in range(60):  # bisection: the bound decreases in k (k > sqrt 3)
        mid = 0.5 * (a + b)
        a, b = (mid, b) if _load_lost(mid, *args) > tol else (a, mid)
    return b


def _fail(name: str, unit: str, allowed: str, got: object) -> ValueError:
    return ValueError(f"{name} [{unit}] must be {allowed}; got {got!r}")


def _check_wall(name: str, wall: object) -> None:
    if not isinstance(wall, Wall):
        raise ValueError(
            f"{name} must be a Wall (Wall.absorbing(p [Pa]), Wall.yield_closure(Y [Pa], dY/dtau "
            f"[1/Pa]))" + (" or None" if name == "upper" else "") + f"; got {wall!r}"
        )
    if wall.kind == "reflecting":
        raise ValueError(
            f"{name}: solve() takes absorbing and yield walls; a reflecting wall (zero flux) is "
            "served by xpersson.engine.solve_sourced"
        )


def make_problem(
    tau_out: ArrayLike,
    p0: float | ArrayLike,
    lower: Wall,
    upper: Wall | None,
    rtol: float,
    atol: float | None,
    p_out: ArrayLike | None,
    max_steps: int,
    options: dict[str, Any] | None,
    *,
    batch: bool = False,
) -> Problem:
    """Check every input before any work; raise ValueError naming parameter, unit and range.

    With ``batch=True`` ``p0`` is a 1-D array of loads and ``tau_out`` is ``(n_tau,)`` (shared)
    or ``(n_load, n_tau)``; the Problem then holds ``tau`` as ``(n_load, n_tau)`` and ``p0`` as
    a ``(n_load, 1)`` column, so that closed forms broadcast over loads.
    """
    tau, p0v = _checked_times_and_loads(tau_out, p0, batch)
    rtol, atol = _checked_tolerances(rtol, atol)
    if int(max_steps) < 1:
        raise _fail("max_steps", "1", ">= 1", max_steps)
    _check_wall("lower", lower)
    if upper is not None:
        _check_wall("upper", upper)
    if lower.kind == "yield_closure" and not lower.is_fixed:
        raise ValueError("lower: a moving yield_closure wall is only supported as the upper wall")
    _check_positions(tau, p0v, lower, upper)
    if batch and tau.ndim == 1:
        tau = broadcast_view(tau, (p0v.size, tau.size))
    p_arr = None
    if p_out is not None:
        p_arr = np.atleast_1d(np.asarray(p_out, dtype=float))
        if p_arr.ndim != 1 or not np.all(np.isfinite(p_arr)):
            raise _fail("p_out", "Pa", "a 1-D array of finite pressures", p_out)
    p0_out: float | Array = p0v[:, None] if batch else float(p0v[0])
    return _problem(
        tau, p0_out, lower, upper, rtol, atol, p_arr, int(max_steps), dict(options or {})
    )


def _problem(
    tau: Array,
    p0: float | Array,
    lower: Wall,
    upper: Wall | None,
    rtol: float,
    atol: float,
    p_out: Array | None,
    max_steps: int,
    options: dict[str, Any],
) -> Problem:
    """``Problem(...)`` of checked fields, without the frozen dataclass's ``__init__`` (one
    ``object.__setattr__`` per field: ~2 us, ~1 us this way; two per solve)."""
    pb = object.__new__(Problem)
    pb.__dict__.update(
        tau=tau, p0=p0, lower=lower, upper=upper, rtol=rtol, atol=atol, p_out=p_out,
        max_steps=max_steps, options=options,
    )  # fmt: skip
    return pb


def _checked_times_and_loads(
    tau_out: ArrayLike, p0: float | ArrayLike, batch: bool
) -> tuple[Array, Array]:
    """``tau_out`` [Pa^2] and the loads ``p0`` [Pa] (always 1-D) checked; see make_problem."""
    try:
        tau = np.asarray(tau_out, dtype=float)
    except (TypeError, ValueError):
        raise _fail("tau_out", "Pa^2", "a 1-D array of finite floats", tau_out) from None
    if batch:
        try:
            p0v = np.atleast_1d(np.asarray(p0, dtype=float))
        except (TypeError, ValueError):
            raise _fail("p0", "Pa", "a 1-D array of finite floats", p0) from None
        if p0v.ndim != 1 or p0v.size == 0:
            raise _fail("p0", "Pa", "a non-empty 1-D array of loads", p0)
        shared = tau.ndim == 1  # validated once, then broadcast (no copy)
        if not shared and (tau.ndim != 2 or tau.shape[0] != p0v.size or tau.shape[1] == 0):
            raise _fail("tau_out", "Pa^2", f"shaped (n_tau,) or ({p0v.size}, n_tau)", tau.shape)
        if shared and tau.size == 0:
            raise _fail("tau_out", "Pa^2", "a non-empty 1-D array", tau_out)
    else:
        tau = np.atleast_1d(tau)
        if tau.ndim != 1 or tau.size == 0:
            raise _fail("tau_out", "Pa^2", "a non-empty 1-D array", tau_out)
        try:
            p0v = np.array([float(p0)])
        except (TypeError, ValueError):
            raise _fail("p0", "Pa", "a finite float", p0) from None
    if _valid_times(tau) and math.isfinite(float(p0v[0] if p0v.size == 1 else p0v.sum())):
        return tau, p0v  # (the checks below, in one pass: each failure's message is theirs)
    if not np.all(np.isfinite(tau)):
        raise _fail("tau_out", "Pa^2", "finite (no NaN/inf)", tau_out)
    if np.any(tau < 0):
        raise _fail("tau_out", "Pa^2", ">= 0", float(tau.min()))
    if np.any(np.diff(tau, axis=-1) <= 0):
        raise _fail("tau_out", "Pa^2", "strictly increasing", tau_out)
    if not np.all(np.isfinite(p0v)):
        raise _fail("p0", "Pa", "finite", p0)
    return tau, p0v


def _valid_times(tau: Array) -> bool:
    """Every row of ``tau`` [Pa^2] finite, >= 0 and strictly increasing, in two reductions: each
    time of a row is above the one before (false where either is NaN, and for inf after inf:
    with subnormals ``b > a`` is ``b - a > 0``), its first time is >= 0 and its last finite;
    then every time lies in [first, last]."""
    if tau.shape[-1] >= 2:  # (count_nonzero: ~1 us less than .all())
        rising = tau[..., 1:] > tau[..., :-1]
        if np.count_nonzero(rising) < rising.size:
            return False
    if tau.ndim == 1:  # (on floats: the same comparisons)
        return float(tau[0]) >= 0.0 and abs(float(tau[-1])) < math.inf
    return bool(((tau[..., 0] >= 0) & (np.abs(tau[..., -1]) < math.inf)).all())


def _checked_tolerances(rtol: float, atol: float | None) -> tuple[float, float]:
    """``rtol`` in (0, 0.1) and ``atol`` (default ``1e-7 rtol``) in (0, 0.1), as floats."""
    try:
        rtol = float(rtol)
    except (TypeError, ValueError):
        raise _fail("rtol", "1", "a float in (0, 0.1)", rtol) from None
    if not (0.0 < rtol < 0.1):
        raise _fail("rtol", "1 (relative error of A/A0)", "in the open interval (0, 0.1)", rtol)
    if atol is None:
        atol = 1e-7 * rtol
    else:
        atol = float(atol)
        if not (math.isfinite(atol) and 0.0 < atol < 0.1):
            raise _fail("atol", "1 (absolute error of A/A0)", "in the open interval (0, 0.1)", atol)
    return rtol, atol


def sample_times(tau: Array) -> Array:
    """Where moving walls are checked [Pa^2]: 0, the output times, 65 equal steps and 96
    log-spaced times over 16 decades up to the last output time (sorted, unique).

    One set for the input checks and the clearance bound of :mod:`._clear`, so that a wall
    whose position is costly (an inverted clock) is evaluated at these times once.
    """
    t = np.asarray(tau, dtype=float)
    if t.ndim == 2 and t.shape[0] > 1 and t.strides[0] == 0:  # one row shared by the loads
        t = t[0]

    def compute() -> Array:
        t_end = float(np.max(t))
        return np.unique(
            np.concatenate([[0.0], t.ravel(), np.linspace(0.0, t_end, 65), t_end * _LOG16])
        )

    return _SAMPLES.get(t, compute).copy()  # a copy: callers' walls may write into it


_LOG16 = np.logspace(-16, 0, 96)
_SAMPLES = Cache(
    "engine.sample_times",
    scope="process",
    maxsize=4,
    doc="times where moving walls are checked, per output-time array (checks, then the bound)",
)


def _checked_table(tau: Array, p0: Array, lower: Wall) -> bool:
    """Whether the compiled table of a moving ``lower`` wall passes the checks of
    :func:`_check_positions` at the times of :func:`sample_times` (False also where the
    compiled code does not run: the checks then run on numpy, with their messages)."""
    fns = table_kernels()
    if fns is None or not callable(lower.position):
        return False
    # (the sample times made in the compiled check: the same set, without its cache look-up)
    t = tau if tau.ndim == 1 else (tau[0] if tau.shape[0] > 1 and tau.strides[0] == 0 else tau)
    return bool(fns[3](*lower.table.args(), t.ravel(), _LOG16, p0))


def _check_positions(tau: Array, p0: Array, lower: Wall, upper: Wall | None) -> None:
    """Wall positions finite and ordered, every ``p0`` strictly inside at ``tau = 0``."""
    if lower.is_fixed and (upper is None or upper.is_fixed):
        lo0 = float(lower.position)
        hi0 = math.inf if upper is None else float(upper.position)
        if math.isfinite(lo0) and (upper is None or lo0 < hi0 < math.inf):
            if bool(((p0 > lo0) & (p0 < hi0)).all()):
                return  # (the checks below on these numbers: each failure's message is theirs)
        t_check = np.zeros(1)
    elif upper is None and lower.table is not None and _checked_table(tau, p0, lower):
        return  # (the checks below in one compiled call: the same positions and comparisons)
    else:
        t_check = sample_times(tau)
    lo = lower.at(t_check)
    if np.count_nonzero(np.isfinite(lo)) < lo.size:  # (count_nonzero: ~0.2 us, .all() ~1)
        raise _fail("lower", "Pa", "finite at every tau in [0, tau_out[-1]]", "non-finite position")
    below = p0 <= lo[0]
    if np.count_nonzero(below):
        raise _fail(
            "p0",
            "Pa",
            f"strictly above the lower wall (> {lo[0]:.6g} Pa)",
            float(p0[below][0]) if p0.size > 1 else float(p0[0]),
        )
    if upper is None:
        return
    up = upper.at(t_check)
    if not np.all(np.isfinite(up)):
        raise _fail("upper", "Pa", "finite at every tau in [0, tau_out[-1]]", "non-finite")
    above = p0 >= up[0]
    if np.any(above):
        raise _fail(
            "p0",
            "Pa",
            f"strictly below the upper wall (< {up[0]:.6g} Pa)",
            float(p0[above][0]) if p0.size > 1 else float(p0[0]),
        )
    if np.any(up <= lo):
        raise _fail("upper", "Pa", "above the lower wall at every tau", "walls cross")
    if upper.kind == "yield_closure" and not upper.is_fixed:
        sp = upper.speed(t_check)
        if not np.all(np.isfinite(sp)) or np.any(sp < 0):
            raise _fail("dposition", "1/Pa", "finite and >= 0 (a rising yield wall)", "dY<0")
