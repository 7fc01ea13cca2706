"""Base class of the engine methods (``solve(method=...)`` takes a name or a subclass).

Each built-in method lives in a module named after it (``_exactpath``: ``exact``, ``_sine``,
``_cn`` (with ``_cn_plan`` and the march ``_moving``), ``_markov``, ``_markov_ck``);
:mod:`._methods` holds the literal name -> class table.
"""

from __future__ import annotations

from ._problem import Problem
from ._result import Raw

__all__ = ["EngineMethod"]


class EngineMethod:
    """Base class of engine methods.

    Subclasses set ``name``, implement :meth:`admits` (can the method treat these walls?) and
    :meth:`run`, which returns a :class:`~xpersson.engine._result.Raw`; the engine adds the
    balances and the final status.  Register with :func:`register_method` or pass the class to
    ``solve(method=cls)``.
    """

    name: str = "base"
    #: True when :meth:`run` accepts a batch Problem (``tau`` ``(n_load, n_tau)``, ``p0`` a
    #: ``(n_load, 1)`` column) and returns a Raw with a leading load axis.  Methods without it
    #: are run once per load by :func:`~xpersson.engine.solve_batch`.
    batched: bool = False

    def __init__(self, problem: Problem) -> None:
        self.problem = problem

    @classmethod
    def admits(cls, problem: Problem) -> bool:  # pragma: no cover - overridden
        """True when the method can solve ``problem``."""
        return True

    def run(self) -> Raw:  # pragma: no cover - overridden
        raise NotImplementedError
