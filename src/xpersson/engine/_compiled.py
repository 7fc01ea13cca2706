"""Optional compiled inner march of the ``cn`` method (numba), the numpy path's arithmetic.

The steps of :func:`._moving._steps` between two outputs are about ten numpy calls and one
LAPACK ``dgtsv`` call each; on the levels of steep or wide spectra (thousands of steps of a
few hundred nodes) their per-call overhead and the passes over memory are most of a solve
(measured in ``benchmarks/kernels_speed.py``: the engine at 3-14x the C march of the same
levels). :func:`march_steps` does the same steps in one compiled loop: the explicit half in
flux form, the yield closure's rows, and the tridiagonal solve as LAPACK's ``dgtsv`` does it
(Gaussian elimination with partial pivoting, the same operations in the same order), so the
results equal the numpy path's bit for bit (a result does not depend on whether the process has
built the compiled march yet; ``tests/engine/test_compiled_generated.py``). Built with it: the
whole level in a few calls (:func:`fused`: :mod:`._moving_fused`, which also builds each step's
diagonals and sums the wall fluxes in the loop), the window's edges and the level's times
(:func:`edges`, :func:`times`: :mod:`._cn_edges`); once few node-steps are left per level
(accurate error control), the numpy calls around the steps were most of a level's time. Levels
that want densities or report progress take :func:`march_steps` per block.

numba is an optional accelerator (``pip install numba``): without it, or with
``xpersson.set_options(compiled=False)`` (environment ``XPERSSON_COMPILED=off``), the numpy
path runs. Until a level of :data:`MIN_WORK` node-steps asks for it, or the levels the numpy
path has marched in the process add up to about the import's cost (:data:`BUILD_AFTER`, estimated
from their steps and node-steps: a rent-or-buy rule, so that many small solves in one process,
a sweep or a benchmark, pay at most twice the best of either path), the numpy path runs too, so
that a few small solves never import numba (its import and loading cost about 0.4 s per
process, the first compilation a few seconds; the compiled code is kept on disk by numba's
cache, keyed on the kernels' sources by :func:`xpersson.numba_cache.njit`); from then on every
level of the process takes the compiled path.

When to start was measured again with the fused level (``python -c``, CPU time, 2026-11-29):
with the build on disk, numba's import costs 0.15 s and the kernels' first calls 0.2-0.4 s
(LLVM's start-up, then ~10 ms per kernel); a first build costs 3.4 s. :data:`BUILD_AFTER`
stays at the cost of loading a build kept on disk: starting sooner would make a short session
pay more than it saves (rent or buy), and a build not yet on disk is paid once per installation
(later processes load it). The choice changes no result: both paths give the same numbers.
"""

from __future__ import annotations

import types
from collections.abc import Callable
from typing import Any

import numpy as np

from .. import numba_cache
from ..options import compiled_enabled
from ._cnstep import _factor, _gtsv, _solve_factor  # noqa: F401 - (_gtsv: for the tests)

__all__ = [
    "BUILD_AFTER",
    "MIN_WORK",
    "KERNELS",
    "build",
    "built",
    "kernel",
    "march_steps",
]

MIN_WORK = 500_000
"""Node-steps of a level below which the numpy path runs (no numba import for small solves)."""

BUILD_AFTER = 0.4
"""Estimated CPU seconds [s] of numpy marching in one process after which the compiled march is
built (about numba's import and load; see :data:`NUMPY_STEP`, :data:`NUMPY_NODE_STEP`)."""

NUMPY_STEP, NUMPY_NODE_STEP = 8e-6, 5e-9
"""The numpy march's cost [s] per time step (its ~10 calls) and per node-step (measured on the
marching ``jkr`` scenes of ``benchmarks/summary.py``: 7.6 us and ~5 ns)."""

_STATE: dict[str, Any] = {}  # the compiled function once built (or None: numba missing)


def kernel(work: float, steps: int = 0, nodes: int = 0) -> Callable[..., int] | None:
    """The compiled :func:`march_steps`, or None: the option is off, numba is missing, or the
    level's ``work`` [node-steps] is below :data:`MIN_WORK`, the numpy marching of the
    process so far (this block's ``steps`` of ``nodes`` unknowns included) is below
    :data:`BUILD_AFTER` and the kernel is not built yet (once built, every level takes it:
    the import is paid, and the results are the same to 1e-12)."""
    if not compiled_enabled():
        return None
    if work < MIN_WORK and "fn" not in _STATE:
        spent = _STATE.get("numpy", 0.0) + steps * (NUMPY_STEP + NUMPY_NODE_STEP * nodes)
        _STATE["numpy"] = spent
        if spent < BUILD_AFTER:
            return None
    if "fn" not in _STATE:
        _STATE["fn"] = _build()
    return _STATE["fn"]  # type: ignore[no-any-return]


def build() -> bool:
    """Build the compiled march now, whatever the work so far (for benchmarks that measure the
    engine with it in force); whether it is in force (False: the option is off or numba is
    missing)."""
    if not compiled_enabled():
        return False
    if "fn" not in _STATE:
        _STATE["fn"] = _build()
    return _STATE["fn"] is not None


KERNELS: dict[str, str] = {
    "edges": "_cn_edges.window_edges (numpy: the window's edges)",
    "times": "_cn_edges.level_times (numpy: the level's times)",
    "tracks": "(_cn_edges.wall_query, _cn_edges.wall_track) (numpy: the walls' tracks)",
    "lean": "(_cn_lean.level_setup, start_scale, lean_march, lean_load) (numpy: the level's "
    "set-up by the numpy path's pieces)",
    "start": "_cn_lean.start_scan (numpy: _cn_plan._start_time's scan)",
    "plan": "_cn_lean.plan_base (numpy: _cn_plan._joint_plan's calls)",
    "judge": "_cn_outputs.judge_ratio (numpy: _cn_control._Judge.ratio)",
    "fourth": "_cn_outputs.fourth_ratio (numpy: _cn_control._fourth's combine and ratio calls)",
    "balances": "_cn_outputs.batch_balances (numpy: _result._balances)",
    "fields": "(_cn_outputs.combine_fields, weighted_fields) (numpy: _level.combine, weighted)",
    "fitted": "_cn_outputs.fitted_error (numpy: _cn_control._control's calls)",
    "scale": "_cn_outputs.scale_kernel (numpy: _cn_outputs.load_scale's calls)",
    "assembled": "_cn_outputs.assembled (numpy: _cn_assemble._assemble's calls)",
    "fused": "(the level march, the face products) (numpy: _moving's level by blocks)",
}
"""The kernels built with the compiled march, by name: what each compiles and the numpy path
that gives the same numbers where it is not in force."""


def built(name: str) -> Any:
    """The compiled kernel(s) ``name`` (a key of :data:`KERNELS`) once the compiled march is
    built and the option is on, else None: the caller then takes the numpy path (the same
    numbers)."""
    if not compiled_enabled():
        return None
    return _STATE.get(name)


def _build() -> Callable[..., int] | None:
    from . import _cn_edges, _cn_lean, _cn_outputs, _wall_table
    from . import _moving_fused as fused_src

    # numba's disk cache keyed on the sources of these modules and everything they import
    mods = (_cn_edges, fused_src, _cn_lean, _cn_outputs, _wall_table)
    jit = numba_cache.njit(__name__, *mods, nogil=True, error_model="numpy")
    if jit is None:  # numba is not installed
        return None
    # the step loops and their helpers make no arrays: compiled without numba's reference
    # counts (the counts of a step's views were a third of a small level's march)
    bare = numba_cache.njit(__name__, *mods, nogil=True, error_model="numpy", _nrt=False)
    # the kernels call the compiled helpers: the same code, its globals bound to the dispatchers
    solve = {"_factor": bare(_factor), "_solve_factor": bare(_solve_factor)}
    scope = {**globals(), **solve}
    names = ("_system", "_explicit", "_wall_fluxes", "_record", "_yield_rows", "_yield_gain")
    helpers = {name: bare(getattr(fused_src, name)) for name in names}
    fused_scope = {**vars(fused_src), **solve, **helpers}
    steps = bare(types.FunctionType(fused_src._level_steps.__code__, fused_scope, "_level_steps"))
    fused_scope["_level_steps"] = steps
    _STATE["edges"] = jit(_cn_edges.window_edges)
    _STATE["times"] = jit(_cn_edges.level_times)
    _STATE["tracks"] = (jit(_cn_edges.wall_query), jit(_cn_edges.wall_track))
    faces = jit(fused_src.face_coefficients)
    code = fused_src.level_march.__code__
    level = jit(types.FunctionType(code, fused_scope, "level_march"))
    _STATE["fused"] = (level, faces)
    _STATE["lean"] = _lean(jit, faces, _wall_table.kernels())
    return jit(types.FunctionType(march_steps.__code__, scope, "march_steps"))


def _lean(jit: Callable, faces: Callable, table: tuple | None) -> tuple | None:
    """The compiled :mod:`._cn_lean` kernels, their callees bound to compiled ones (None
    without the wall table's kernels)."""
    from . import _cn_lean

    if table is None:
        return None
    scope = {
        **vars(_cn_lean),
        "level_times": _STATE["times"],
        "window_edges": _STATE["edges"],
        "table_values": table[0],
        "face_coefficients": faces,
        "level_march": _STATE["fused"][0],
    }
    setup = jit(types.FunctionType(_cn_lean.level_setup.__code__, scope, "level_setup"))
    _STATE["start"] = jit(types.FunctionType(_cn_lean.start_scan.__code__, scope, "start_scan"))
    _outputs(jit)
    scope["_sorted_unique"] = jit(_cn_lean._sorted_unique)
    _STATE["plan"] = jit(types.FunctionType(_cn_lean.plan_base.__code__, scope, "plan_base"))
    march = jit(types.FunctionType(_cn_lean.lean_march.__code__, scope, "lean_march"))
    return setup, jit(_cn_lean.start_scale), march, jit(_cn_lean.lean_load)


def _outputs(jit: Callable) -> None:
    """The compiled :mod:`._cn_outputs` kernels, their callees bound to compiled ones."""
    from . import _cn_outputs as src

    scope = dict(vars(src))
    for name in ("_nan_max", "_same_shape", "_combined", "_summed", "_plain"):
        scope[name] = jit(getattr(src, name))

    def bound(name: str) -> Callable:
        return jit(types.FunctionType(getattr(src, name).__code__, scope, name))

    _STATE["judge"] = jit(src.judge_ratio)
    _STATE["balances"] = bound("batch_balances")
    _STATE["fields"] = (bound("combine_fields"), bound("weighted_fields"))
    scope["combine_fields"], scope["judge_ratio"] = _STATE["fields"][0], _STATE["judge"]
    _STATE["fourth"] = bound("fourth_ratio")
    _STATE["fitted"] = jit(src.fitted_error)
    _STATE["assembled"] = bound("assembled")
    _STATE["scale"] = jit(src.scale_kernel)


def march_steps(  # noqa: PLR0913 - the arrays of one block, as the numpy path holds them
    i0: int,
    i1: int,
    states: Any,
    flux_lo: Any,
    flux_hi: Any,
    lower: Any,
    diag: Any,
    upper: Any,
    volumes: Any,
    walls: Any,
    last: Any,
    yields: Any,
    yield_rhs: Any,
    yield_gain: Any,
    z: Any,
) -> int:  # pragma: no cover - compiled (the numpy path is the reference)
    """The steps ``i0 .. i1 - 1`` of a block (see :func:`._moving._steps`): the state after
    step ``i`` into ``states[i + 1]``, the yield rows into ``z`` (5, loads); returns LAPACK's
    ``info`` of the first failed solve (0: all succeeded; the march stops there).

    ``flux_*``, ``lower``, ``diag``, ``upper``: (steps, rows) as in ``Block`` (``lower`` and
    ``upper`` overwritten, as ``dgtsv`` does); ``yields[i]`` whether a real yield wall closes
    step ``i``, then ``yield_rhs[i]`` (3, loads) and ``yield_gain[i]`` (5, loads) apply.
    """
    m = states.shape[1]
    nb = last.shape[0]
    if i1 <= i0:
        return 0
    # each step's system is eliminated during the step before (_solve_factor): two of each
    fact, swap = np.empty((2, m)), np.empty((2, m), np.bool_)
    info = _factor(lower[i0, : m - 1], diag[i0], upper[i0, : m - 1], fact[0], swap[0])
    for i in range(i0, i1):
        if info != 0:
            return info
        cur, nxt = (i - i0) % 2, (i - i0 + 1) % 2
        r = states[i]
        b = states[i + 1]
        fl, fh = flux_lo[i], flux_hi[i]
        for k in range(m):
            b[k] = volumes[k] * r[k]
        f_prev = fl[0] * r[0] + fh[0] * r[1]
        for k in range(1, m - 1):
            f = fl[k] * r[k] + fh[k] * r[k + 1]
            b[k] += f - f_prev
            f_prev = f
        if nb > 1:
            for k in range(walls.shape[0]):
                b[walls[k]] = 0.0
        if yields[i]:
            for j in range(nb):
                z[0, j] = r[last[j] - 1]
                z[1, j] = r[last[j]]
                yr = yield_rhs[i]
                b[last[j]] = yr[0, j] * z[0, j] + yr[1, j] * z[1, j] + yr[2, j] * z[2, j]
        more = i + 1 < i1  # (never beyond the call's steps: a later call eliminates those)
        j2 = i + 1 if more else i
        info = _solve_factor(lower[i, : m - 1], diag[i], upper[i, : m - 1], fact[cur],
                             swap[cur], b, lower[j2, : m - 1], diag[j2], upper[j2, : m - 1],
                             fact[nxt], swap[nxt], more)  # fmt: skip
        if yields[i]:
            yg = yield_gain[i]
            for j in range(nb):
                z[3, j] = b[last[j] - 1]
                z[4, j] = b[last[j]]
                gain = yg[0, j] * z[0, j]
                for k in range(1, 5):
                    gain += yg[k, j] * z[k, j]
                z[2, j] += gain
    return info
