"""Plugin time limits (issue 24): a plugin call running longer than ``[solver]
plugin_time_limit`` fails naming the plugin (a sweep marks the point failed and completes the
rest), in the main thread (SIGALRM) and in worker threads (an exception injected into the
thread); a plugin import running longer than the limit of ``plugins list --check`` is reported
as broken."""

from __future__ import annotations

import json
import sys
import threading
import time
import types
from pathlib import Path

import numpy as np
import pytest

import xpersson
from xpersson.plugins import Analysis, PluginTimeout, Registry, VarSpec, limited, time_limit
from xpersson.testing import registry_with

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "sweep"))
from xpersson_sweep_testlib import scene  # noqa: E402

PZ = ("p0", "zeta")


def _hang(self, ctx, ds):
    if float(ctx.E) > 15e6:  # hangs only at the stiffest material of a sweep
        while True:
            pass
    return {"extra": (PZ, ds["area_fraction"].transpose(*PZ).values.copy())}


def _sleepy(self, ctx, ds):
    time.sleep(3600)


Hanging = type(
    "Hanging",
    (Analysis,),
    {
        "summary": "an analysis that never returns for E > 15 MPa",
        "requires": ("area_fraction",),
        "provides": ("extra",),
        "outputs": {"extra": VarSpec(PZ, "1", "copy of the area fraction")},
        "compute": _hang,
    },
)
Sleepy = type("Sleepy", (Hanging,), {"compute": _sleepy})


def _scene(limit: str | None, e: object = "20 MPa", name: str = "hanging") -> dict:
    sc = scene(material={"E": e}, output={"zeta_per_decade": 2}, analyses={name: {}})
    if limit is not None:
        sc["solver"] = {"plugin_time_limit": limit}
    return sc


@pytest.mark.parametrize("name", ["hanging", "sleepy"])
def test_a_hanging_plugin_call_fails_naming_the_plugin(name):
    with registry_with(analyses={"hanging": Hanging, "sleepy": Sleepy}):
        t0 = time.perf_counter()
        with pytest.raises(xpersson.PluginFailure, match="exceeded the time limit") as info:
            xpersson.solve(_scene("0.3 s", name=name))
        assert time.perf_counter() - t0 < 10
    assert f"analysis plugin {name!r}" in str(info.value) and "compute()" in str(info.value)
    assert isinstance(info.value, TimeoutError)
    assert threading.active_count() < 20


@pytest.mark.parametrize("scheduler", [None, "threads"])
def test_a_sweep_marks_the_hanging_point_failed_and_completes_the_rest(scheduler):
    with registry_with(analyses={"hanging": Hanging}):
        ds = xpersson.solve(
            _scene("0.5 s", e=["5 MPa", "10 MPa", "20 MPa"]), scheduler=scheduler, workers=2
        )
        one = xpersson.solve(_scene(None, e="10 MPa"))
    assert ds["point_status"].values.tolist() == [0, 0, 2]
    msgs = json.loads(ds.attrs["xpersson_point_messages"])
    assert "analysis plugin 'hanging'" in msgs[0]["message"]
    assert "exceeded the time limit of 0.5 s" in msgs[0]["message"]
    np.testing.assert_array_equal(ds["extra"].sel(E=10e6).values, one["extra"].values)


def test_the_limit_must_be_a_positive_time():
    with registry_with(analyses={"hanging": Hanging}):
        for bad in ("-1 s", "0 s", "1 m"):
            with pytest.raises(xpersson.SceneError, match="solver.plugin_time_limit"):
                xpersson.solve(_scene(bad))


def test_no_limit_arms_nothing_and_a_fast_call_is_untouched():
    with time_limit(None), limited():
        assert threading.active_count() >= 1
    with time_limit(5.0), limited():
        x = sum(range(1000))
    assert x == 499500
    time.sleep(0.05)  # nothing fires later


def test_a_hanging_import_is_reported_broken_within_the_limit(monkeypatch, tmp_path):
    module = tmp_path / "xpersson_hanging_import.py"
    module.write_text("while True:\n    pass\n", encoding="utf-8")
    monkeypatch.syspath_prepend(str(tmp_path))
    ep = types.SimpleNamespace(
        name="hang", value="xpersson_hanging_import:Cls", group="xpersson.analyses", dist=None
    )
    from xpersson.plugins import _discovery

    monkeypatch.setattr(
        _discovery,
        "_entry_points",
        lambda group, installed=None: [ep] if group == "xpersson.analyses" else [],
    )
    reg = Registry()
    t0 = time.perf_counter()
    infos = reg.check("analysis", time_limit=0.5)
    assert time.perf_counter() - t0 < 10
    (info,) = [i for i in infos if i.name == "hang"]
    # reported as what it is, not as a generic import failure
    assert info.error == "import exceeded the time limit of 0.5 s"
    assert info.status == "broken: import exceeded the time limit of 0.5 s"
    assert "xpersson_hanging_import" not in sys.modules


def test_limits_in_threads_interrupt_a_python_loop():
    out = {}

    def work():
        try:
            with limited(0.3):
                while True:
                    pass
        except PluginTimeout:
            out["ok"] = True

    t = threading.Thread(target=work)
    t.start()
    t.join(10)
    assert out == {"ok": True} and not t.is_alive()


def test_a_nested_limit_in_the_main_thread_is_the_outer_one_and_leaves_nothing_armed():
    """A limited call inside another (a plugin call inside a checked call) arms no timer of
    its own: the outer limit interrupts the inner loop, and no timer is left afterwards."""
    import signal

    from xpersson.checks import PluginFailure, calling

    t0 = time.monotonic()
    with pytest.raises(PluginFailure, match="inner call exceeded the time limit") as err:
        with time_limit(0.2), calling("outer", "outer call"), calling("inner", "inner call"):
            while True:
                pass
    assert isinstance(err.value, TimeoutError)
    assert time.monotonic() - t0 < 5.0
    assert signal.getitimer(signal.ITIMER_REAL)[0] == 0.0
    with time_limit(5.0), calling("outer", "o"), calling("inner", "i"):
        x = sum(range(10))
    assert x == 45
    assert signal.getitimer(signal.ITIMER_REAL)[0] == 0.0


def _straddling_calls(seed: int, out: list, trace: bool) -> None:
    """250 calls under a 2 ms limit, each busy for 1.6-2.4 ms: one ends as its limit fires."""
    import random

    rng = random.Random(seed)
    if trace:  # a line tracer (as coverage sets one): an interrupt withdrawn under it spun
        sys.settrace(lambda frame, event, arg: None)
    for _ in range(250):
        end = time.perf_counter() + 2e-3 * rng.uniform(0.8, 1.2)
        try:
            try:
                with limited(2e-3):
                    while time.perf_counter() < end:
                        pass
                outcome = "value"
            except PluginTimeout as exc:
                outcome = str(exc)
            sum(range(100))  # the caller's own code: no interrupt may land here
        except BaseException as exc:  # noqa: BLE001 - what escaped the guarded call
            outcome = f"escaped {exc!r}"
        out.append(outcome)
    stack = getattr(sys.modules["xpersson.plugins._limits"]._ARMED, "stack", [])
    out.append(sum(entry[3] == "armed" for entry in stack))


def test_calls_ending_as_their_limit_fires_return_or_time_out_and_nothing_else():
    # Race: the watchdog fires as the call ends, its interrupt landing in the guard's own exit
    # (once it leaked the guard's lock: every thread deadlocked) or after it (under a tracer,
    # withdrawing it left CPython 3.11 spinning at the next call). Each of 3 x 250 calls in 3
    # threads returns or raises one PluginTimeout naming the limit; no thread hangs.
    outs: list[list] = [[], [], []]
    threads = [
        threading.Thread(target=_straddling_calls, args=(i, outs[i], i == 2), daemon=True)
        for i in range(3)
    ]
    for t in threads:
        t.start()
    deadline = time.monotonic() + 60.0
    for t in threads:
        t.join(max(deadline - time.monotonic(), 0.0))
    assert not any(t.is_alive() for t in threads)
    for out in outs:
        assert out[-1] == 0  # no limit left armed in the thread (to fire later)
        assert len(out) == 251
        assert set(out[:-1]) <= {"value", "exceeded the time limit of 0.002 s"}


def _landing_points(k: int, box: list) -> None:
    """``with limited(5 s): with limited(5 s): pass`` in this (non-main) thread, the outer
    limit firing at the ``k``-th place an interrupt can land from the inner guard's entry on
    (each function entry, and each return of a call, in any frame below the guards: where
    CPython delivers an injected exception); ``box``: [the outcome, the places counted, the
    lost limits]."""
    import dis

    lim = sys.modules["xpersson.plugins._limits"]
    call, here, last, seen = dis.opmap["CALL"], __file__, {}, [0]

    def fire(frame: types.FrameType) -> None:
        stack = getattr(lim._ARMED, "stack", [])
        armed = [e for e in stack if e[3] is lim._ARMED_STATE]
        if not armed or frame.f_code.co_filename == here:  # nothing left to fire
            return
        seen[0] += 1
        if seen[0] == k:  # as the watchdog did (its interrupt landing only now, maybe where
            armed[0][3] = lim._FIRED_STATE  # this thread holds the lock): the outer entry
            raise armed[0][5].value()  # marked fired, its interrupt raised

    def local(frame, event, arg):  # noqa: ANN001, ANN202
        if event == "opcode":
            prev, last[frame] = last.get(frame), frame.f_lasti
            if prev is not None and frame.f_code.co_code[prev] == call:
                fire(frame)
        return local

    def tracer(frame, event, arg):  # noqa: ANN001, ANN202
        frame.f_trace_opcodes = True
        fire(frame)  # a function's entry
        return local

    outer = limited(5.0)
    outer.__enter__()
    sys.settrace(tracer)
    try:
        try:
            with limited(5.0):
                pass
        except BaseException as exc:  # noqa: BLE001 - what the outer guard's exit sees
            pending = exc
        else:
            pending = None
        try:
            kept = outer.__exit__(type(pending) if pending else None, pending, None)
            outcome = "value" if pending is None or kept else pending
        except BaseException as exc:  # noqa: BLE001 - what the caller sees
            outcome = exc
    finally:
        sys.settrace(None)
    stack = getattr(lim._ARMED, "stack", [])
    box[:] = [outcome, seen[0], sum(e[3] is lim._ARMED_STATE for e in stack)]


def test_an_interrupt_landing_anywhere_in_the_guards_leaves_nothing_broken():
    # Deterministic form of the race above: an outer limit's interrupt delivered at every place
    # of the inner guard's entry and exit (and of the outer one's exit) where it can land. Once
    # it landed in Thread.is_alive (the guard's check of its watchdog) just after its
    # tstate-lock acquire failed: threading's clean-up then released the running watchdog's
    # lock, the watchdog counted as stopped, and another thread's is_alive raised
    # "RuntimeError: release unlocked lock" out of a guarded call (CI, 2026-11-30).
    lim = sys.modules["xpersson.plugins._limits"]

    def run(k: int) -> list:
        box: list = []
        t = threading.Thread(target=_landing_points, args=(k, box), daemon=True)
        t.start()
        t.join(10.0)
        assert not t.is_alive()
        return box

    count = run(0)[1]  # the places, counted without firing
    for k in range(1, count + 1):
        outcome, _, armed = run(k)
        # the outer limit's timeout, or nothing (where it landed as the inner exit ended)
        assert outcome == "value" or isinstance(outcome, PluginTimeout), (k, outcome)
        assert armed == 0, k  # no limit left armed to fire later
        assert lim._LOCK.acquire(timeout=1.0), k  # the guards' lock not leaked
        lim._LOCK.release()
        dog = lim._WATCHDOG._thread  # the watchdog still runs, its thread state intact
        assert dog is not None and dog.is_alive(), k  # (asked here, in no guarded call)
    assert count >= 10  # the places were reached (the guards' code ran under the tracer)


def test_a_limit_beyond_the_lock_timeouts_keeps_the_watchdog_for_the_next_limits():
    # a limit past threading.TIMEOUT_MAX once ended the watchdog's loop (OverflowError in its
    # wait); nothing restarts it since the guards no longer ask Thread.is_alive
    lim = sys.modules["xpersson.plugins._limits"]
    out: list = []

    def work() -> None:
        with limited(10 * threading.TIMEOUT_MAX):
            time.sleep(0.01)  # the watchdog waits for this deadline meanwhile
        end = time.monotonic() + 5.0  # (bounded: a dead watchdog must not leave a spinning thread)
        try:
            with limited(0.05):
                while time.monotonic() < end:
                    pass
            out.append("not interrupted")
        except PluginTimeout as exc:
            out.append(str(exc))

    t = threading.Thread(target=work, daemon=True)
    t.start()
    t.join(10.0)
    assert not t.is_alive()
    assert out == ["exceeded the time limit of 0.05 s"]
    assert lim._WATCHDOG._thread.is_alive()
