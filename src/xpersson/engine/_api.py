"""``solve``: validate, pick a method, run it, add the balances."""

from __future__ import annotations

import time
from typing import Any

from numpy.typing import ArrayLike

from ._exactpath import ExactMethod
from ._methods import EngineMethod, get_method
from ._moving import CNMethod
from ._problem import make_problem
from ._result import EngineResult, finish
from ._walls import Wall

__all__ = ["solve"]

_DEFAULT_LOWER = Wall.absorbing(0.0)


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
        ``"auto"`` (closed form when the walls admit one, else ``"cn"``), ``"exact"``,
        ``"sine"`` (fixed walls), ``"cn"`` (any walls), a registered name, or a class.
    p_out : array_like, optional
        Pressures [Pa] where the density is wanted; the field is computed only when given.
    max_steps : int, optional
        Budget of time steps summed over all refinement levels (numerical methods).
    options : dict, optional
        Method options (``"cn"``: ``nodes``, ``steps_per_decade``, ``levels``, ``stretch``;
        ``"sine"``: ``window_k``).

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
    if isinstance(method, str) and method == "auto":
        cls: type[EngineMethod] = ExactMethod if ExactMethod.admits(problem) else CNMethod
    else:
        cls = get_method(method)
        if not cls.admits(problem):
            raise ValueError(f"method={getattr(cls, 'name', cls)!r} cannot treat these walls")
    raw = cls(problem).run()
    return finish(problem, raw, getattr(cls, "name", cls.__name__), t0)
