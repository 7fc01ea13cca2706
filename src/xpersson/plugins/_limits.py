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


class _async_timer:  # noqa: N801 - a context manager class (no generator per plugin call)
    """The watchdog's limit of ``seconds`` [s] on a block of a non-main thread.

    The interrupt can land at any bytecode once it is fired, also in this guard's own code; so
    the guard holds :data:`_LOCK` only around C operations (no Python frame between acquire and
    release for an interrupt to land in), disarms by truncating the thread's stack of armed
    limits (the watchdog fires only entries still on it), and never withdraws a fired interrupt
    (``PyThreadState_SetAsyncExc(tid, NULL)`` leaves CPython 3.11's eval breaker set for good,
    and under a line tracer such as ``coverage`` the next function entry then spins forever).
    An interrupt fired before the disarm lands, at the latest, where the lock is released in
    :meth:`__exit__`: never after the block. No thread enters a Python function while it holds
    the lock: under a line tracer, CPython 3.11 spins at every function entry of the other
    threads until the interrupted thread takes its interrupt, which it cannot while it waits for
    the lock."""

    __slots__ = ("entry",)

    def __init__(self, seconds: float) -> None:
        # tid, stack, level, state, seconds, the interrupt to raise
        self.entry = [0, None, 0, _ARMED_STATE, seconds, _interrupt(seconds)]

    def __enter__(self) -> None:
        entry = self.entry
        stack = _ARMED.__dict__.setdefault("stack", [])
        deadline = time.monotonic() + entry[4]
        with _LOCK:
            while stack and stack[-1][3] is not _ARMED_STATE:  # fired ones left by an
                del stack[-1]  # interrupt that landed in their exit: inert
            entry[:3] = threading.get_ident(), stack, len(stack)
            stack.append(entry)
            heapq.heappush(_WATCHDOG.heap, (deadline, next(_WATCHDOG.count), entry))
        _WATCHDOG.wake()

    def __exit__(self, *exc: object) -> bool:
        entry = self.entry
        stack, level = entry[1], entry[2]
        try:
            with _LOCK:  # C operations only inside: the watchdog fires nothing after this
                del stack[level:]  # this limit and any nested one an interrupt left armed
        except PluginTimeout:  # one fired earlier, landing as the lock is released: ours is
            pass  # raised below with its message; an outer one's by its own exit
        if entry[3] is _ARMED_STATE:
            return False
        raise PluginTimeout(_message(entry[4]))


class _Interrupt(PluginTimeout):
    """What the watchdog raises in a thread: one subclass per limit (:func:`_interrupt`), so
    that it needs no Python ``__init__`` (it may be created while the thread holds
    :data:`_LOCK`) and still names its limit (what the caller sees if it lands in
    :meth:`_async_timer.__exit__` before the guard's own :class:`PluginTimeout`)."""

    __slots__ = ()
    seconds = 0.0

    def __str__(self) -> str:
        return super().__str__() or _message(self.seconds)

    def __reduce__(self) -> tuple:  # pickled (to another process) as a PluginTimeout
        return PluginTimeout, (str(self),)


_INTERRUPTS: dict[float, ctypes.py_object] = {}


def _interrupt(seconds: float) -> ctypes.py_object:
    """The :class:`_Interrupt` of a ``seconds`` [s] limit, for ``PyThreadState_SetAsyncExc``."""
    cls = _INTERRUPTS.get(seconds)
    if cls is None:
        attrs = {"__slots__": (), "__module__": __name__, "seconds": seconds}
        cls = _INTERRUPTS[seconds] = ctypes.py_object(type("PluginTimeout", (_Interrupt,), attrs))
    return cls


_ARMED_STATE, _FIRED_STATE = "armed", "fired"
_LOCK = threading.Lock()
"""Guards the watchdog's heap and every thread's stack of armed limits (a C lock: its
``with`` has no Python frame an interrupt could land in while it is held)."""


class _Watchdog:
    """One daemon thread that raises :class:`PluginTimeout` in threads past their deadline."""

    def __init__(self) -> None:
        self.heap: list[tuple[float, int, list]] = []
        self.count = itertools.count()
        self._wake = threading.Lock()  # released to wake the watchdog (a binary semaphore)
        self._wake.acquire()
        self._thread: threading.Thread | None = None
        self._start = threading.Lock()

    def wake(self) -> None:
        """Start the watchdog thread if needed and make it look at the heap again.

        Called by a thread that may take an interrupt at any bytecode (a limit of its that
        fired), so nothing here may leave shared state broken when one lands: the watchdog's
        liveness is not asked of ``Thread.is_alive`` (whose ``_wait_for_tstate_lock``, an
        interrupt landing just after its ``acquire(False)`` failed, releases the *running*
        watchdog's thread-state lock: the watchdog then counts as stopped, a second one is
        started, and a concurrent ``is_alive`` in another thread fails with ``RuntimeError:
        release unlocked lock``). Its loop never returns; a forked child starts its own
        (:func:`_after_fork_in_child`)."""
        if self._thread is None:  # (no limit has fired yet: no interrupt can land in here)
            with self._start:  # one watchdog, whichever threads arm their first limits at once
                if self._thread is None:
                    thread = threading.Thread(
                        target=self._run, name="xpersson-time-limits", daemon=True
                    )
                    thread.start()
                    self._thread = thread
        try:
            self._wake.release()
        except RuntimeError:  # already woken
            pass

    def _run(self) -> None:
        heap, fire = self.heap, ctypes.pythonapi.PyThreadState_SetAsyncExc
        while True:
            with _LOCK:  # no Python function entered while held: see _async_timer
                while heap:  # drop entries no longer armed and on their thread's stack
                    entry = heap[0][2]
                    stack, level = entry[1], entry[2]
                    if entry[3] is _ARMED_STATE and len(stack) > level and stack[level] is entry:
                        break
                    heapq.heappop(heap)
                wait = heap[0][0] - time.monotonic() if heap else -1.0
                if heap and wait <= 0:
                    entry = heapq.heappop(heap)[2]
                    entry[3] = _FIRED_STATE
                    fire(ctypes.c_ulong(entry[0]), entry[5])
                    continue
            self._wake.acquire(timeout=min(wait, _LONGEST_WAIT))  # (a huge limit: no overflow)


_LONGEST_WAIT = 3600.0
"""Longest single wait [s] of the watchdog (``threading.TIMEOUT_MAX`` bounds a lock's timeout:
a limit of years must not end the watchdog's loop, which nothing restarts)."""
_WATCHDOG = _Watchdog()
_ARMED = threading.local()
_REAL_SLEEP = time.sleep


def _after_fork_in_child() -> None:
    """A forked child has no watchdog, and only its forking thread: a lock another thread held
    at the fork would never be released."""
    global _LOCK
    _LOCK = threading.Lock()
    _WATCHDOG.__init__()


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_after_fork_in_child)


def _sleep(seconds: float) -> None:
    """:func:`time.sleep`, in slices of :data:`SLEEP_SLICE` while a limit is armed in this
    (non-main) thread, so that a timeout is delivered."""
    stack = getattr(_ARMED, "stack", None)
    if not stack or stack[-1][3] is not _ARMED_STATE or not seconds > SLEEP_SLICE:
        _REAL_SLEEP(seconds)
        return
    end = time.monotonic() + seconds
    while (left := end - time.monotonic()) > 0:
        _REAL_SLEEP(min(left, SLEEP_SLICE))


time.sleep = _sleep
