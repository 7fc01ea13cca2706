"""Numerical diffusion engine: ``dP/dtau = d2P/dp2`` between walls (numpy in, numpy out).

Public API
----------
solve(tau_out, p0, lower=Wall.absorbing(0.0), upper=None, *, rtol, atol, method, p_out, ...)
solve_batch(tau_out, p0[:], walls=(lower, upper) or [(lower, upper), ...], ...) -> EngineBatch
solve_sourced(tau_out, sources_tau, sources_position, sources_weight, *, lower, p_out, ...)
Wall.absorbing(position), Wall.linear(p_start, velocity), Wall.yield_closure(position, dposition),
Wall.reflecting(position)
progress_reporting(callback): work done (node-steps) by long solves, reported to ``callback``
SourcedResult
EngineResult, EngineMethod, register_method, exact (closed forms)
MarkovMethod ("markov": walkers), ChapmanKolmogorovMethod ("markov_ck"), sample_paths,
transition_kernel

Units: pressures in Pa, diffusion time tau in Pa^2, densities in 1/Pa.
"""

from __future__ import annotations

from . import exact as exact  # noqa: PLC0414 (the public closed-forms module)
from ._api import solve, solve_batch
from ._base import EngineMethod
from ._cn import CNMethod
from ._exactpath import ExactMethod
from ._markov import MarkovMethod, sample_paths
from ._markov_ck import ChapmanKolmogorovMethod, transition_kernel
from ._methods import METHODS, register_method
from ._progress import reporting as progress_reporting
from ._result import EngineBatch, EngineResult
from ._sine import SineMethod
from ._sourced import SourcedResult, solve_sourced
from ._walls import Wall

__all__ = [
    "solve",
    "solve_batch",
    "solve_sourced",
    "SourcedResult",
    "Wall",
    "EngineResult",
    "EngineBatch",
    "EngineMethod",
    "register_method",
    "METHODS",
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
