"""Wall-clock limits on plugin calls and plugin imports.

A Python call cannot be killed from outside without killing its process, and a worker thread
joined with a timeout leaves the call running. The limit is therefore raised *inside* the call:

- in the main thread (the CLI, a serial solve or sweep, a forked worker): ``SIGALRM`` through
  :func:`signal.setitimer`; its handler raises :class:`PluginTimeout` in the plugin's frame.
  Pure-Python loops and sleeps are interrupted; a call blocked inside C code (one long numpy
  or LAPACK call) is interrupted when that C call returns.
- in any other thread (the ``"threads"`` scheduler, dask workers): one watchdog thread injects
  :class:`PluginTimeout` into the calling thread (``PyThreadState_SetAsyncExc``), delivered at
  its next Python bytecode: pure-Python loops are interrupted, and so is :func:`time.sleep`
  (while a limit is armed in a thread, ``time.sleep`` sleeps in slices of
  :data:`SLEEP_SLICE`); another blocking C call is interrupted when it returns.

The limit in force is set with :func:`time_limit` (the pipeline sets ``[solver]
plugin_time_limit``) and applied to each call by :func:`limited`; where no scene sets one, the
default of :func:`xpersson.set_options` ``plugin_time_limit`` applies (environment
``XPERSSON_PLUGIN_TIME_LIMIT``, 600 s unless turned off): spectrum ``build()`` and a plugin's
import included (an import at most :data:`IMPORT_TIME_LIMIT`).
"""

from __future__ import annotations

import _signal
import contextlib
import contextvars
import ctypes
import heapq
import itertools
import os
import signal
import threading
import time
from collections.abc import Iterator

from ..options import plugin_time_limit

__all__ = ["PluginTimeout", "time_limit", "limited", "current_limit", "IMPORT_TIME_LIMIT"]

IMPORT_TIME_LIMIT = 60.0
"""Longest a plugin's import may take [s] (less when a smaller limit is in force)."""
SLEEP_SLICE = 0.05
"""Longest single sleep [s] of a thread under a limit (a pending timeout is delivered after)."""

_LIMIT: contextvars.ContextVar[float | None] = contextvars.ContextVar(
    "xpersson_plugin_time_limit", default=None
)


class PluginTimeout(TimeoutError):
    """A plugin call or import exceeded its wall-clock limit."""


@contextlib.contextmanager
def time_limit(seconds: float | None) -> Iterator[None]:
    """Apply ``seconds`` [s] (``None``: the default of ``set_options(plugin_time_limit=...)``)
    to every :func:`limited` call inside."""
    if seconds is not None and not seconds > 0:
        raise ValueError(f"plugin time limit [s] must be > 0, got {seconds!r}")
    main = threading.current_thread() is threading.main_thread()
    token = _LIMIT.set(seconds)
    _SCOPES[0] += main
    try:
        yield
    finally:
        _LIMIT.reset(token)
        if main:
            _SCOPES[0] -= 1
            if not _SCOPES[0]:
                _disarm_main()  # the scope leaves no timer behind


def current_limit() -> float | None:
    """The limit [s] in force: the innermost :func:`time_limit`, else the default option
    (``None``: none)."""
    limit = _LIMIT.get()
    return plugin_time_limit() if limit is None else limit


def limited(seconds: float | None = None) -> contextlib.AbstractContextManager[None]:
    """Raise :class:`PluginTimeout` inside the block when it runs longer than ``seconds`` [s]
    (default: the :func:`time_limit` in force; nothing is armed when there is none)."""
    seconds = current_limit() if seconds is None else seconds
    if seconds is None:
        return contextlib.nullcontext()
    if threading.current_thread() is threading.main_thread() and hasattr(signal, "setitimer"):
        return _alarm(seconds)
    return _async_timer(seconds)


def _message(seconds: float) -> str:
    return f"exceeded the time limit of {seconds:g} s"


_MAIN_ARMED: list[tuple[float, float]] = []
"""The limits armed in the main thread (innermost last): seconds [s] and deadline
(:func:`time.monotonic` [s])."""
_SCOPES = [0]
"""How many :func:`time_limit` scopes are open in the main thread."""
_PENDING: list[float] = []
"""When the interval timer this module set fires (monotonic [s]); empty: none of ours pending.

Inside a :func:`time_limit` scope of the main thread (a solve) a call's timer is not cancelled
when the call ends: the next call of the scope reuses it (no system call) when it fires no later
than that call's deadline, else sets it anew; when it fires early, the handler sets it again for
what is left of the deadline in force, and ignores it when no call is armed. The outermost scope
cancels it on exit, so no timer outlives a solve; a call outside any scope cancels its own."""


if hasattr(os, "register_at_fork"):  # a forked child has no interval timer of its parent
    os.register_at_fork(after_in_child=_PENDING.clear)


def _main_handler(signum: int, frame: object) -> None:
    if not _MAIN_ARMED:  # a timer left by an ended call of the scope (or a stray one): ignored
        _PENDING.clear()
        return
    seconds, deadline = _MAIN_ARMED[-1]
    left = deadline - time.monotonic()
    if left > 0:  # set by an earlier call of the scope: set again for the rest of this limit
        _PENDING[:] = [deadline]
        signal.setitimer(signal.ITIMER_REAL, left)
        return
    _PENDING.clear()
    raise PluginTimeout(_message(seconds))


def _disarm_main() -> None:
    """Cancel this module's pending timer (main thread, no call armed)."""
    if _PENDING and not _MAIN_ARMED:
        _PENDING.clear()
        if _signal.getsignal(signal.SIGALRM) is _main_handler:
            signal.setitimer(signal.ITIMER_REAL, 0)


class _alarm:  # noqa: N801 - a context manager class (no generator per plugin call)
    """SIGALRM after ``seconds`` [s] in the main thread, unless an outer limit is armed (or
    another itimer is pending); disarmed on exit (inside a :func:`time_limit` scope: left for
    the scope's next call, see :data:`_PENDING`), an other handler restored on every exit."""

    __slots__ = ("armed", "old", "seconds")

    def __init__(self, seconds: float) -> None:
        self.seconds, self.armed = seconds, False

    def __enter__(self) -> None:
        if _MAIN_ARMED:  # an outer limit applies
            return
        old = _signal.getsignal(signal.SIGALRM)  # (signal.getsignal's enum look-up costs ~4 us)
        if old is not _main_handler or not _PENDING:  # is a timer of someone else's pending?
            _PENDING.clear()
            if signal.getitimer(signal.ITIMER_REAL)[0] > 0:  # an outer limit applies
                return
            if old is not _main_handler:  # installed once while SIGALRM has its default action
                signal.signal(signal.SIGALRM, _main_handler)
        seconds = self.seconds
        deadline = time.monotonic() + seconds
        self.old, self.armed = old, True
        _MAIN_ARMED.append((seconds, deadline))  # armed before the pending timer is read
        if not _PENDING or _PENDING[0] > deadline:
            _PENDING[:] = [deadline]
            signal.setitimer(signal.ITIMER_REAL, seconds)

    def __exit__(self, *exc: object) -> bool:
        if not self.armed:
            return False
        self.armed = False
        _MAIN_ARMED.pop()
        old = self.old
        if old is not _main_handler and old not in (signal.SIG_DFL, None):  # restored
            _PENDING.clear()
            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.signal(signal.SIGALRM, old)
        elif not _SCOPES[0]:  # outside a scope: no timer left behind
            _PENDING.clear()
            signal.setitimer(signal.ITIMER_REAL, 0)
        return False


@contextlib.contextmanager
def _async_timer(seconds: float) -> Iterator[None]:
    tid = threading.get_ident()
    entry = _WATCHDOG.arm(tid, seconds)
    _ARMED.depth = getattr(_ARMED, "depth", 0) + 1
    try:
        yield
    finally:
        _ARMED.depth -= 1
        if _WATCHDOG.disarm(entry):  # fired, not delivered yet: withdraw it, raise here
            ctypes.pythonapi.PyThreadState_SetAsyncExc(ctypes.c_ulong(tid), None)
            raise PluginTimeout(_message(seconds))


class _Watchdog:
    """One daemon thread that raises :class:`PluginTimeout` in threads past their deadline."""

    def __init__(self) -> None:
        self._cond = threading.Condition()
        self._heap: list[tuple[float, int, list]] = []
        self._count = itertools.count()
        self._thread: threading.Thread | None = None

    def arm(self, tid: int, seconds: float) -> list:
        entry = [tid, "armed"]  # state: armed -> fired | done
        with self._cond:
            heapq.heappush(self._heap, (time.monotonic() + seconds, next(self._count), entry))
            if self._thread is None or not self._thread.is_alive():
                self._thread = threading.Thread(
                    target=self._run, name="xpersson-time-limits", daemon=True
                )
                self._thread.start()
            self._cond.notify()
        return entry

    def disarm(self, entry: list) -> bool:
        """Withdraw ``entry``; whether it had fired."""
        with self._cond:
            fired = entry[1] == "fired"
            entry[1] = "done"
        return fired

    def _run(self) -> None:
        with self._cond:
            while True:
                while self._heap and self._heap[0][2][1] == "done":
                    heapq.heappop(self._heap)
                if not self._heap:
                    self._cond.wait()
                    continue
                wait = self._heap[0][0] - time.monotonic()
                if wait > 0:
                    self._cond.wait(wait)
                    continue
                _, _, entry = heapq.heappop(self._heap)
                if entry[1] == "armed":
                    entry[1] = "fired"
                    ctypes.pythonapi.PyThreadState_SetAsyncExc(
                        ctypes.c_ulong(entry[0]), ctypes.py_object(PluginTimeout)
                    )


_WATCHDOG = _Watchdog()
_ARMED = threading.local()
_REAL_SLEEP = time.sleep


def _sleep(seconds: float) -> None:
    """:func:`time.sleep`, in slices of :data:`SLEEP_SLICE` while a limit is armed in this
    (non-main) thread, so that a timeout is delivered."""
    if not getattr(_ARMED, "depth", 0) or not seconds > SLEEP_SLICE:
        _REAL_SLEEP(seconds)
        return
    end = time.monotonic() + seconds
    while (left := end - time.monotonic()) > 0:
        _REAL_SLEEP(min(left, SLEEP_SLICE))


time.sleep = _sleep
