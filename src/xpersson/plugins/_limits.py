"""Wall-clock limits on plugin calls and plugin imports.

A Python call cannot be killed from outside without killing its process, and a worker thread
joined with a timeout leaves the call running. The limit is therefore raised *inside* the call:

- in the main thread (the CLI, a serial solve or sweep, a forked worker): ``SIGALRM`` through
  :func:`signal.setitimer`; its handler raises :class:`PluginTimeout` in the plugin's frame.
  Pure-Python loops and sleeps are interrupted; a call blocked inside C code (one long numpy
  or LAPACK call) is interrupted when that C call returns.
- in any other thread (the ``"threads"`` scheduler, dask workers): a timer thread injects
  :class:`PluginTimeout` into the calling thread (``PyThreadState_SetAsyncExc``), delivered at
  its next Python bytecode: pure-Python loops are interrupted, a sleep or a C call only when it
  returns.

The limit in force is set with :func:`time_limit` (the pipeline sets ``[solver]
plugin_time_limit``) and applied to each call by :func:`limited`; without a limit nothing is
armed (no signal, no thread).
"""

from __future__ import annotations

import contextlib
import contextvars
import ctypes
import signal
import threading
from collections.abc import Iterator

__all__ = ["PluginTimeout", "time_limit", "limited", "current_limit"]

_LIMIT: contextvars.ContextVar[float | None] = contextvars.ContextVar(
    "xpersson_plugin_time_limit", default=None
)


class PluginTimeout(TimeoutError):
    """A plugin call or import exceeded its wall-clock limit."""


@contextlib.contextmanager
def time_limit(seconds: float | None) -> Iterator[None]:
    """Apply ``seconds`` [s] (``None``: no limit) to every :func:`limited` call inside."""
    if seconds is not None and not seconds > 0:
        raise ValueError(f"plugin time limit [s] must be > 0, got {seconds!r}")
    token = _LIMIT.set(seconds)
    try:
        yield
    finally:
        _LIMIT.reset(token)


def current_limit() -> float | None:
    """The limit [s] in force (``None``: none)."""
    return _LIMIT.get()


@contextlib.contextmanager
def limited(seconds: float | None = None) -> Iterator[None]:
    """Raise :class:`PluginTimeout` inside the block when it runs longer than ``seconds`` [s]
    (default: the :func:`time_limit` in force; nothing is armed when there is none)."""
    seconds = current_limit() if seconds is None else seconds
    if seconds is None:
        yield
    elif threading.current_thread() is threading.main_thread() and hasattr(signal, "setitimer"):
        with _alarm(seconds):
            yield
    else:
        with _async_timer(seconds):
            yield


def _message(seconds: float) -> str:
    return f"exceeded the time limit of {seconds:g} s"


@contextlib.contextmanager
def _alarm(seconds: float) -> Iterator[None]:
    if signal.getitimer(signal.ITIMER_REAL)[0] > 0:  # an outer limit is armed: it applies
        yield
        return

    def handler(signum: int, frame: object) -> None:
        raise PluginTimeout(_message(seconds))

    old = signal.signal(signal.SIGALRM, handler)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


@contextlib.contextmanager
def _async_timer(seconds: float) -> Iterator[None]:
    tid = threading.get_ident()
    lock = threading.Lock()
    state = {"done": False, "fired": False}

    def fire() -> None:
        with lock:
            if not state["done"]:
                state["fired"] = True
                ctypes.pythonapi.PyThreadState_SetAsyncExc(
                    ctypes.c_ulong(tid), ctypes.py_object(PluginTimeout)
                )

    timer = threading.Timer(seconds, fire)
    timer.daemon = True
    timer.start()
    try:
        yield
    finally:
        with lock:
            state["done"] = True
        timer.cancel()
        if state["fired"]:  # not delivered yet: withdraw it and raise here instead
            ctypes.pythonapi.PyThreadState_SetAsyncExc(ctypes.c_ulong(tid), None)
            raise PluginTimeout(_message(seconds))
