"""``checks.calling`` under a time limit leaves no timer behind (issue 36: the per-call timer is a
context manager class): after a return, a plugin's exception, a passed-through exception, a
nested call's failure and an interrupt, no interval timer is pending, nothing is recorded as
armed and a handler the user had installed for SIGALRM is theirs again."""

from __future__ import annotations

import signal

import pytest

from xpersson.checks import PluginFailure, calling
from xpersson.plugins import _limits, time_limit


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
                    assert _limits._MAIN_ARMED == [5.0]  # the outer timer only
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
