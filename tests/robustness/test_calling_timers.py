"""``checks.calling`` under a time limit leaves no timer behind (issue 36: the per-call timer is a
context manager class): after a return, a plugin's exception, a passed-through exception, a
nested call's failure and an interrupt, no interval timer is pending, nothing is recorded as
armed and a handler the user had installed for SIGALRM is theirs again."""

from __future__ import annotations

import signal

import pytest

from xpersson.checks import PluginFailure, calling
from xpersson.plugins import PluginTimeout, _limits, time_limit


def _clean(handler: object = None) -> None:
    assert signal.getitimer(signal.ITIMER_REAL) == (0.0, 0.0)
    assert _limits._MAIN_ARMED == []
    if handler is not None:
        assert signal.getsignal(signal.SIGALRM) is handler


class _Stop(BaseException):
    """Stands for KeyboardInterrupt (not an Exception: never wrapped)."""


def _raise(exc: BaseException) -> None:
    raise exc


CASES = {
    "returns": (lambda: None, None),
    "raises": (lambda: _raise(ValueError("bad")), PluginFailure),
    "passes through": (lambda: _raise(KeyError("k")), KeyError),
    "interrupted": (lambda: _raise(_Stop()), _Stop),
}


@pytest.mark.parametrize("case", sorted(CASES))
@pytest.mark.parametrize("nested", [False, True])
def test_no_timer_survives_a_call(case, nested):
    body, expected = CASES[case]

    def call() -> None:
        with calling("outer", "o", passthrough=(KeyError,)):
            if nested:
                with calling("inner", "i", passthrough=(KeyError,)):
                    assert [s for s, _ in _limits._MAIN_ARMED] == [5.0]  # the outer timer only
                    body()
            else:
                assert signal.getitimer(signal.ITIMER_REAL)[0] > 0.0  # armed inside
                body()

    with time_limit(5.0):
        if expected is None:
            call()
        else:
            with pytest.raises(expected) as err:
                call()
            if expected is PluginFailure:  # named by the innermost call, cause kept
                label = "inner: i" if nested else "outer: o"
                assert str(err.value) == f"{label} raised ValueError: bad"
                assert isinstance(err.value, ValueError)
                assert isinstance(err.value.__cause__, ValueError)
    _clean()


def test_a_users_handler_is_restored_after_every_exit():
    def mine(signum, frame):  # pragma: no cover - never called
        raise AssertionError("a stray alarm reached the user's handler")

    before = signal.signal(signal.SIGALRM, mine)
    try:
        with time_limit(5.0):
            with calling("p", "call"):
                pass
            _clean(mine)
            with pytest.raises(PluginFailure):
                with calling("p", "call"):
                    raise RuntimeError("x")
            _clean(mine)
    finally:
        signal.signal(signal.SIGALRM, before)


def test_a_timer_of_the_user_is_left_to_them():
    """A pending itimer of the caller: no limit of ours is armed over it, and it is kept."""
    signal.setitimer(signal.ITIMER_REAL, 100.0)
    try:
        with time_limit(5.0), calling("p", "call"):
            assert _limits._MAIN_ARMED == []
        assert signal.getitimer(signal.ITIMER_REAL)[0] > 90.0
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
    _clean()


def test_a_scope_reuses_one_timer_and_leaves_none(monkeypatch):
    """Inside one ``time_limit`` scope (a solve) the calls share one interval timer: it is set
    once, not cancelled between calls, and cancelled when the scope ends."""
    real, sets = signal.setitimer, []

    def counting(which, seconds, interval=0.0):
        sets.append(seconds)
        return real(which, seconds, interval)

    monkeypatch.setattr(signal, "setitimer", counting)
    with time_limit(5.0):
        for _ in range(4):
            with calling("p", "call"):
                assert signal.getitimer(signal.ITIMER_REAL)[0] > 4.0
        assert signal.getitimer(signal.ITIMER_REAL)[0] > 4.0  # kept for the next call
        assert sets == [5.0]
    assert sets == [5.0, 0]
    _clean()


def test_a_reused_timer_still_gives_each_call_its_whole_limit():
    """A call reusing a timer set by an earlier call is interrupted at its own deadline, not at
    the earlier call's: the handler sets the timer again for the rest of the limit."""
    import time

    with time_limit(0.4):
        with calling("p", "first"):
            pass
        time.sleep(0.25)  # the timer now fires ~0.15 s into the next call
        t0 = time.monotonic()
        with pytest.raises(PluginFailure, match="second exceeded the time limit"):
            with calling("p", "second"):
                while True:
                    pass
        assert 0.39 <= time.monotonic() - t0 < 5.0
    _clean()


def test_a_timer_firing_between_calls_is_ignored_and_a_shorter_limit_is_set_anew():
    import time

    from xpersson.plugins import limited

    with time_limit(0.1):
        with calling("p", "first"):
            pass
        time.sleep(0.2)  # fires with no call armed: nothing raised
        with calling("p", "second"):
            assert signal.getitimer(signal.ITIMER_REAL)[0] > 0.0  # armed again
    _clean()
    with time_limit(60.0):
        with calling("p", "long"):
            pass
        t0 = time.monotonic()
        with pytest.raises(PluginTimeout), limited(0.1):
            while True:
                pass
        assert time.monotonic() - t0 < 5.0
    _clean()


@pytest.mark.skipif(not hasattr(__import__("os"), "fork"), reason="needs fork")
def test_a_forked_child_arms_its_own_timer():
    """A child forked inside a scope inherits no interval timer: it does not reuse the parent's
    (it would run its calls without a limit), it sets its own."""
    import os

    with time_limit(5.0):
        with calling("p", "parent"):
            pass
        assert _limits._PENDING  # the parent's timer, kept for its next call
        pid = os.fork()
        if pid == 0:  # pragma: no cover - the child reports by its exit status
            ok = not _limits._PENDING
            with calling("p", "child"):
                ok = ok and signal.getitimer(signal.ITIMER_REAL)[0] > 4.0
            os._exit(0 if ok else 1)
        _, status = os.waitpid(pid, 0)
    assert os.waitstatus_to_exitcode(status) == 0
    _clean()
