"""Library-wide options, set like :func:`xarray.set_options`.

Four options:

``cache`` : bool
    Whether the caches of :mod:`xpersson.cache` keep anything. ``False`` turns every cache of
    the core and of the first-party plugins off: every value is computed afresh, so a result
    cannot depend on what was solved before (it never should; CI runs the whole suite both
    ways). The default comes from the environment variable ``XPERSSON_CACHE`` (``on``/``off``,
    also ``1``/``0``, ``true``/``false``, ``yes``/``no``; unset means on), read when first
    needed in a process (so dask workers started with it follow it) and read again by
    ``set_options(cache=None)``.
``fast_paths`` : bool
    Whether the fast paths that plugins declare (:class:`xpersson.plugins.FastPaths`: batches
    of loads, stacked sweep blocks, walls and diffusion times asked once) may be taken.
    ``False`` sends every load and every sweep point down the plain path, the reference the
    fast paths are checked against (:func:`xpersson.sweep.plain_paths` is the same as a
    ``with`` block). The default comes from ``XPERSSON_FAST_PATHS`` (same values as
    ``XPERSSON_CACHE``).
``compiled`` : bool
    Whether the engine may run its compiled inner march (numba, an optional dependency; see
    :mod:`xpersson.engine._compiled`) where it pays. ``False`` keeps the pure-numpy path, the
    reference the compiled one is tested against. The default comes from
    ``XPERSSON_COMPILED`` (same values; on, and a no-op without numba).
``plugin_time_limit`` : float or False
    The wall-clock limit [s] of every plugin call (spectrum ``build()``, a plugin's import, a
    law, an analysis) that the scene's ``[solver] plugin_time_limit`` does not set; ``False``
    (or ``0``) turns the default limit off. The default comes from
    ``XPERSSON_PLUGIN_TIME_LIMIT`` (seconds, or ``off``); unset means
    :data:`DEFAULT_PLUGIN_TIME_LIMIT`.

Examples
--------
>>> import xpersson
>>> with xpersson.set_options(cache=False):  # doctest: +SKIP
...     ds = xpersson.solve("examples/elastic.toml")
>>> xpersson.set_options(cache=False)  # doctest: +SKIP  (for the rest of the process)
"""

from __future__ import annotations

import os
import threading
from types import TracebackType
from typing import Any

__all__ = [
    "CACHE_ENV",
    "FAST_PATHS_ENV",
    "get_options",
    "set_options",
    "cache_enabled",
    "fast_paths_enabled",
    "COMPILED_ENV",
    "compiled_enabled",
    "plugin_time_limit",
    "DEFAULT_PLUGIN_TIME_LIMIT",
    "TIME_LIMIT_ENV",
]

CACHE_ENV = "XPERSSON_CACHE"
"""The environment variable that sets the default of the ``cache`` option."""
FAST_PATHS_ENV = "XPERSSON_FAST_PATHS"
"""The environment variable that sets the default of the ``fast_paths`` option."""
COMPILED_ENV = "XPERSSON_COMPILED"
"""The environment variable that sets the default of the ``compiled`` option."""

TIME_LIMIT_ENV = "XPERSSON_PLUGIN_TIME_LIMIT"
"""The environment variable that sets the default of the ``plugin_time_limit`` option."""
DEFAULT_PLUGIN_TIME_LIMIT = 600.0
"""The default wall-clock limit of one plugin call [s] (a call never returning ends a run)."""
MAX_TIME_LIMIT = 1e7
"""Largest time limit accepted [s] (about 4 months)."""

_ON = frozenset({"", "1", "on", "true", "yes"})
_OFF = frozenset({"0", "off", "false", "no"})
_LOCK = threading.Lock()
#: options set by :func:`set_options`; a missing key means "the default" (for ``cache``: the
#: environment variable)
_SET: dict[str, Any] = {}
_VALID = {
    "cache": "a bool",
    "fast_paths": "a bool",
    "compiled": "a bool",
    "plugin_time_limit": f"a number of seconds in (0, {MAX_TIME_LIMIT:g}] or False (off)",
}
#: the environment variables' flags as read (cleared by ``set_options(option=None)``)
_FROM_ENV: dict[str, bool] = {}
_ENV = {
    "cache": CACHE_ENV,
    "fast_paths": FAST_PATHS_ENV,
    "compiled": COMPILED_ENV,
    "plugin_time_limit": TIME_LIMIT_ENV,
}


def _env_flag(name: str) -> bool:
    """The environment variable ``name`` as a flag, read once (again after
    ``set_options(option=None)``): a look-up is on every cache access."""
    value = _FROM_ENV.get(name)
    if value is None:
        value = _parse_env(name)
        _FROM_ENV[name] = value
    return value


def _parse_env(name: str) -> bool:
    raw = os.environ.get(name, "")
    text = raw.strip().lower()
    if text in _ON:
        return True
    if text in _OFF:
        return False
    raise ValueError(
        f"environment variable {name}={raw[:40]!r} is not one of on/off (also 1/0, "
        "true/false, yes/no); unset it for the default (on)"
    )


def _flag(option: str) -> bool:
    """``option`` of :func:`set_options`, else its environment variable's flag (read at every
    cache access and compiled-kernel look-up, a few dozen times a solve: the parsed flag
    taken directly once read)."""
    value = _SET.get(option)
    if value is None:
        name = _ENV[option]
        value = _FROM_ENV.get(name)
        return _env_flag(name) if value is None else value
    return bool(value)


def cache_enabled() -> bool:
    """Whether caches keep values now: :func:`set_options` ``cache``, else ``XPERSSON_CACHE``."""
    return _flag("cache")


def fast_paths_enabled() -> bool:
    """Whether declared fast paths may be taken: :func:`set_options` ``fast_paths``, else
    ``XPERSSON_FAST_PATHS``."""
    return _flag("fast_paths")


def compiled_enabled() -> bool:
    """Whether compiled accelerators (numba, when installed) may run: :func:`set_options`
    ``compiled``, else ``XPERSSON_COMPILED``."""
    return _flag("compiled")


def plugin_time_limit() -> float | None:
    """The default limit of a plugin call [s] (``None``: off): :func:`set_options`
    ``plugin_time_limit``, else ``XPERSSON_PLUGIN_TIME_LIMIT``, else
    :data:`DEFAULT_PLUGIN_TIME_LIMIT`."""
    value = _SET.get("plugin_time_limit")
    if value is None:
        value = _FROM_ENV.get(TIME_LIMIT_ENV)
        if value is None:
            value = _FROM_ENV[TIME_LIMIT_ENV] = _parse_limit(os.environ.get(TIME_LIMIT_ENV, ""))
    return None if value is False else float(value)


def _parse_limit(raw: str) -> float | bool:
    text = raw.strip().lower()
    if not text:
        return DEFAULT_PLUGIN_TIME_LIMIT
    if text in _OFF:
        return False
    try:
        value = float(text.removesuffix("s").strip())
    except ValueError:
        value = float("nan")
    if not 0 < value <= MAX_TIME_LIMIT:
        raise ValueError(
            f"environment variable {TIME_LIMIT_ENV}={raw[:40]!r} must be a number of seconds in "
            f"(0, {MAX_TIME_LIMIT:g}] or off; unset it for the default "
            f"({DEFAULT_PLUGIN_TIME_LIMIT:g} s)"
        )
    return value


def get_options() -> dict[str, Any]:
    """The options in force (a copy): ``{"cache": bool, "fast_paths": bool, "compiled": bool,
    "plugin_time_limit": float or None}``."""
    out: dict[str, Any] = {name: _flag(name) for name in ("cache", "fast_paths", "compiled")}
    out["plugin_time_limit"] = plugin_time_limit()
    return out


def _valid(name: str, value: Any) -> bool:
    if value is None:
        return True
    if name != "plugin_time_limit":
        return isinstance(value, bool)
    if value is False or (type(value) in (int, float) and value == 0):
        return True
    return type(value) in (int, float) and 0 < value <= MAX_TIME_LIMIT


class set_options:  # noqa: N801 - named as xarray.set_options, used as a function
    """Set options for the rest of the process, or inside a ``with`` block.

    Parameters
    ----------
    cache : bool or None
        ``False`` turns every cache off, ``True`` on; ``None`` returns to the default (the
        environment variable ``XPERSSON_CACHE``).
    fast_paths : bool or None
        ``False`` sends everything down the plain path, ``True`` lets declared fast paths
        run; ``None`` returns to the default (``XPERSSON_FAST_PATHS``).
    compiled : bool or None
        ``False`` keeps the engine on its pure-numpy path; ``None`` returns to the default
        (``XPERSSON_COMPILED``).
    plugin_time_limit : float, False or None
        The default limit of a plugin call [s]; ``False`` or ``0``: no default limit;
        ``None``: back to ``XPERSSON_PLUGIN_TIME_LIMIT`` (or 600 s).

    Raises
    ------
    ValueError
        For an unknown option or a value of the wrong type (naming the option).
    """

    def __init__(self, **options: Any) -> None:
        unknown = sorted(set(options) - set(_VALID))
        if unknown:
            raise ValueError(
                f"unknown option(s) {unknown}; allowed: "
                + ", ".join(f"{k} ({v})" for k, v in _VALID.items())
            )
        for name, value in options.items():
            if not _valid(name, value):
                raise ValueError(f"option {name!r} must be {_VALID[name]} or None, got {value!r}")
        options = {
            k: (False if k == "plugin_time_limit" and v is not None and not v else v)
            for k, v in options.items()
        }
        with _LOCK:
            self._old = {k: _SET.get(k) for k in options}
            for name, value in options.items():
                if value is None:  # back to the default: the environment, read again
                    _SET.pop(name, None)
                    _FROM_ENV.pop(_ENV[name], None)
                else:
                    _SET[name] = value

    def __enter__(self) -> set_options:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        with _LOCK:
            for name, value in self._old.items():
                if value is None:
                    _SET.pop(name, None)
                    _FROM_ENV.pop(_ENV[name], None)
                else:
                    _SET[name] = value
