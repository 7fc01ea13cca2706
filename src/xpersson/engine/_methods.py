"""Method base class and registry (``solve(method=...)`` takes a name or a class)."""

from __future__ import annotations

from ._problem import Problem
from ._result import Raw

__all__ = ["EngineMethod", "register_method", "get_method", "METHODS"]


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


METHODS: dict[str, type[EngineMethod]] = {}


def register_method(name: str, cls: type[EngineMethod]) -> type[EngineMethod]:
    """Register ``cls`` (an :class:`EngineMethod` subclass) under ``name``; returns ``cls``."""
    if not isinstance(name, str) or not name or name == "auto":
        raise ValueError(f"method name must be a non-empty string other than 'auto'; got {name!r}")
    if not (isinstance(cls, type) and issubclass(cls, EngineMethod)):
        raise ValueError(f"method class must subclass xpersson.engine.EngineMethod; got {cls!r}")
    METHODS[name] = cls
    return cls


def get_method(method: str | type[EngineMethod]) -> type[EngineMethod]:
    """Resolve a registered name or a class."""
    if isinstance(method, type) and issubclass(method, EngineMethod):
        return method
    if isinstance(method, str) and method in METHODS:
        return METHODS[method]
    raise ValueError(
        f"method must be 'auto', one of {sorted(METHODS)} or an EngineMethod subclass; "
        f"got {method!r}"
    )
