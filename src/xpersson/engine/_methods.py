"""The method table: a literal ``METHODS`` mapping of the built-in methods, plus
:func:`register_method` for third-party methods and :func:`get_method` (name or class).

The built-ins are listed here, not registered as a side effect of importing the package.
Every built-in but ``exact`` is listed by a loader and imported on first look-up: ``cn``'s
modules import ``scipy.optimize``, ``scipy.interpolate`` and ``scipy.linalg`` (~0.5 s), which
the closed-form path never needs (nor the other methods' modules).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, MutableMapping

from ._base import EngineMethod
from ._exactpath import ExactMethod

__all__ = ["EngineMethod", "MethodError", "register_method", "get_method", "METHODS"]


class MethodError(ValueError):
    """A method asked for by name cannot treat a problem's walls (raised before any work)."""


def _cn() -> type[EngineMethod]:
    from ._cn import CNMethod  # lazily: see the module docstring

    return CNMethod


def _sine() -> type[EngineMethod]:
    from ._sine import SineMethod

    return SineMethod


def _markov() -> type[EngineMethod]:
    from ._markov import MarkovMethod

    return MarkovMethod


def _markov_ck() -> type[EngineMethod]:
    from ._markov_ck import ChapmanKolmogorovMethod

    return ChapmanKolmogorovMethod


class _MethodTable(MutableMapping[str, type[EngineMethod]]):
    """Name -> method class; an entry given as a loader (a function, not a class) is
    replaced by the class it returns on its first look-up."""

    def __init__(self, entries: dict[str, type[EngineMethod] | Callable[[], type[EngineMethod]]]):
        self._entries = dict(entries)

    def __getitem__(self, name: str) -> type[EngineMethod]:
        entry = self._entries[name]
        if not isinstance(entry, type):
            entry = self._entries[name] = entry()
        return entry

    def __setitem__(self, name: str, cls: type[EngineMethod]) -> None:
        self._entries[name] = cls

    def __delitem__(self, name: str) -> None:
        del self._entries[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._entries)

    def __len__(self) -> int:
        return len(self._entries)

    def __contains__(self, name: object) -> bool:
        return name in self._entries

    def __repr__(self) -> str:
        return f"METHODS({sorted(self._entries)})"


METHODS: MutableMapping[str, type[EngineMethod]] = _MethodTable(
    {
        "exact": ExactMethod,
        "sine": _sine,
        "cn": _cn,
        "markov": _markov,
        "markov_ck": _markov_ck,
    }
)


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
