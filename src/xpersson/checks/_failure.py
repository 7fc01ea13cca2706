"""PluginFailure: a plugin's exception or bad output, attributed to the plugin."""

from __future__ import annotations

from typing import Any

from ..plugins import PluginTimeout, current_limit, limited

__all__ = ["PluginFailure", "calling", "make_failure"]


class PluginFailure(RuntimeError):
    """A plugin raised, or returned output that violates its declaration.

    When it wraps an exception raised inside a plugin, the instance is also an instance of
    that exception's class (``except ValueError`` still catches a plugin's ``ValueError``),
    with a message naming the plugin.

    Attributes
    ----------
    plugin : str
        Label of the plugin (group, registered name, distribution and version).
    variable : str or None
        The variable or call at fault.
    """

    def __init__(self, message: str, *, plugin: Any = "", variable: str | None = None) -> None:
        super().__init__(message)
        self.plugin = str(plugin)
        self.variable = variable

    def __reduce__(self) -> Any:  # picklable also in its per-cause subclasses (dask workers)
        cause = next((b for b in type(self).__bases__ if b is not PluginFailure), None)
        return (_rebuild, (cause, str(self), self.plugin, self.variable))


_FAILURES: dict[type, type] = {}


def _failure_class(cause: type | None) -> type:
    """``PluginFailure`` that is also a ``cause`` (cached; plain PluginFailure if impossible)."""
    if cause is None or cause is RuntimeError or issubclass(cause, PluginFailure):
        return PluginFailure
    if cause not in _FAILURES:
        try:
            _FAILURES[cause] = type(
                f"PluginFailure_{cause.__name__}", (PluginFailure, cause), {"__module__": __name__}
            )
        except TypeError:  # incompatible layout
            _FAILURES[cause] = PluginFailure
    return _FAILURES[cause]


def _rebuild(cause: type | None, message: str, plugin: str, variable: str | None) -> Any:
    return make_failure(cause, message, plugin, variable)


def make_failure(cause: type | None, message: str, plugin: Any, variable: str | None) -> Any:
    try:
        exc = _failure_class(cause)(message, plugin=plugin, variable=variable)
        if str(exc) == message:
            return exc
    except Exception:  # a cause class with an unusual constructor
        pass
    return PluginFailure(message, plugin=plugin, variable=variable)


class calling:  # noqa: N801 - used as a function: ``with calling(who, what):``
    """Re-raise any exception of a plugin call as :class:`PluginFailure` naming the plugin.

    Parameters
    ----------
    who : str
        :func:`plugin_label` of the plugin.
    what : str
        The call, e.g. ``"f(zeta)"``.
    passthrough : tuple of exception types
        Exceptions the caller handles itself (re-raised unchanged).

    Under a time limit (:func:`xpersson.plugins.time_limit`, ``[solver] plugin_time_limit``)
    a call running longer is interrupted and raised as a :class:`PluginFailure` (also a
    ``TimeoutError``) naming the plugin and the call. A context manager class (no generator
    per call: it wraps every plugin call of a solve); the limit's timer is disarmed on every
    exit, by a return, an exception or a nested call's failure.
    """

    __slots__ = ("_limit", "passthrough", "what", "who")

    def __init__(
        self, who: object, what: str, passthrough: tuple[type[BaseException], ...] = ()
    ) -> None:
        self.who, self.what, self.passthrough = who, what, passthrough

    def __enter__(self) -> None:
        limit = limited()
        limit.__enter__()
        self._limit = limit

    def __exit__(self, kind: Any, exc: Any, tb: Any) -> bool:
        try:
            self._limit.__exit__(kind, exc, tb)  # disarms first (it suppresses nothing)
        except PluginTimeout as late:  # a thread's timeout withdrawn at the exit: raised here
            kind, exc = PluginTimeout, late
        if kind is None:
            return False
        who, what = self.who, self.what
        if issubclass(kind, PluginTimeout):
            raise make_failure(
                TimeoutError,
                f"{who}: {what} exceeded the time limit of {current_limit():g} s "
                "([solver] plugin_time_limit)",
                who,
                what,
            ) from None
        passed = (PluginFailure, MemoryError, *self.passthrough)
        if issubclass(kind, passed) or not issubclass(kind, Exception):
            return False  # re-raised unchanged
        raise make_failure(kind, f"{who}: {what} raised {kind.__name__}: {exc}", who, what) from exc
