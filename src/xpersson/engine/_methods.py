"""The method table: a literal ``METHODS`` mapping of the built-in methods, plus
:func:`register_method` for third-party methods and :func:`get_method` (name or class).

The built-ins are listed here, not registered as a side effect of importing the package.
"""

from __future__ import annotations

from ._base import EngineMethod
from ._cn import CNMethod
from ._exactpath import ExactMethod
from ._markov import MarkovMethod
from ._markov_ck import ChapmanKolmogorovMethod
from ._sine import SineMethod

__all__ = ["EngineMethod", "register_method", "get_method", "METHODS"]

METHODS: dict[str, type[EngineMethod]] = {
    "exact": ExactMethod,
    "sine": SineMethod,
    "cn": CNMethod,
    "markov": MarkovMethod,
    "markov_ck": ChapmanKolmogorovMethod,
}


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
