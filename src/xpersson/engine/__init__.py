"""Numerical diffusion engine: ``dP/dtau = d2P/dp2`` between walls (numpy in, numpy out).

Public API
----------
solve(tau_out, p0, lower=Wall.absorbing(0.0), upper=None, *, rtol, atol, method, p_out, ...)
solve_batch(tau_out, p0[:], walls=(lower, upper) or [(lower, upper), ...], ...) -> EngineBatch
solve_sourced(tau_out, sources_tau, sources_position, sources_weight, *, lower, p_out, ...)
Wall.absorbing(position), Wall.linear(p_start, velocity), Wall.yield_closure(position, dposition),
Wall.reflecting(position)
WallTable(c, x, t_lo, t_hi, ...): a moving wall's position as a clipped piecewise polynomial,
evaluated in compiled code (``Wall.absorbing(position, table=...)``)
progress_reporting(callback): work done (node-steps) by long solves, reported to ``callback``
SourcedResult
EngineResult, EngineMethod, register_method, exact (closed forms)
MarkovMethod ("markov": walkers), ChapmanKolmogorovMethod ("markov_ck"), sample_paths,
transition_kernel

Units: pressures in Pa, diffusion time tau in Pa^2, densities in 1/Pa.

The methods other than ``exact`` and ``solve_sourced`` are imported on first access: the
modules of ``cn`` and ``solve_sourced`` import ``scipy.optimize``, ``scipy.interpolate`` and
``scipy.linalg`` (~0.5 s), which the closed-form path never needs.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from . import exact as exact  # noqa: PLC0414 (the public closed-forms module)
from ._api import solve, solve_batch
from ._base import EngineMethod
from ._exactpath import ExactMethod
from ._methods import METHODS, MethodError, register_method
from ._progress import reporting as progress_reporting
from ._result import EngineBatch, EngineResult
from ._wall_table import WallTable
from ._walls import Wall

if TYPE_CHECKING:
    from ._cn import CNMethod
    from ._markov import MarkovMethod, sample_paths
    from ._markov_ck import ChapmanKolmogorovMethod, transition_kernel
    from ._sine import SineMethod
    from ._sourced import SourcedResult, solve_sourced

__all__ = [
    "solve",
    "solve_batch",
    "solve_sourced",
    "SourcedResult",
    "Wall",
    "WallTable",
    "EngineResult",
    "EngineBatch",
    "EngineMethod",
    "register_method",
    "METHODS",
    "MethodError",
    "exact",
    "ExactMethod",
    "SineMethod",
    "CNMethod",
    "MarkovMethod",
    "ChapmanKolmogorovMethod",
    "sample_paths",
    "transition_kernel",
    "progress_reporting",
]


def __getattr__(name: str) -> Any:
    # lazily: see the module docstring (function-level imports, so that import-linter sees them)
    if name == "CNMethod":
        from ._cn import CNMethod

        return CNMethod
    if name == "SineMethod":
        from ._sine import SineMethod

        return SineMethod
    if name in ("MarkovMethod", "sample_paths"):
        from . import _markov

        return getattr(_markov, name)
    if name in ("ChapmanKolmogorovMethod", "transition_kernel"):
        from . import _markov_ck

        return getattr(_markov_ck, name)
    if name in ("SourcedResult", "solve_sourced"):
        from . import _sourced

        return getattr(_sourced, name)
    raise AttributeError(f"module 'xpersson.engine' has no attribute {name!r}")
