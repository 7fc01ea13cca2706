"""A sweep leaves Python's warning filters as the user set them (issue 33: no process-wide side
effect). ``warnings.catch_warnings`` swaps the process-wide filter list and is not thread-safe
in Python 3.11, so no sweep code enters it on a worker thread; the calling thread silences the
points' warnings once (:func:`xpersson.sweep._quiet.silenced`), and concurrent or nested uses of
that share one ``catch_warnings`` that the last to leave restores."""

from __future__ import annotations

import sys
import threading
import warnings

import pytest
from xpersson_sweep_testlib import scene

import xpersson
from xpersson.sweep import _quiet

SWEEP = scene(spectrum={"H": [0.6, 0.75, 0.9], "h_rms": ["0.5 um", "2 um"]})
MATERIAL = scene(material={"E": ["2 MPa", "5 MPa"]}, load={"p0": "3e4 Pa"})


@pytest.mark.parametrize("data", [SWEEP, MATERIAL], ids=["stacked", "batched"])
@pytest.mark.parametrize("chunk", [1, 3])
def test_no_worker_thread_enters_catch_warnings(monkeypatch, data, chunk):
    entered: list[tuple[int, str]] = []  # (thread, module) of each xpersson caller
    original = warnings.catch_warnings

    class Recording(original):  # type: ignore[misc, valid-type]
        def __enter__(self):  # noqa: ANN204
            caller = sys._getframe(1)
            while caller.f_globals.get("__name__") == "contextlib":  # silenced() is one
                caller = caller.f_back
            module = caller.f_globals.get("__name__", "")
            if module.startswith("xpersson"):  # not NumPy's, SciPy's or the stdlib's own
                entered.append((threading.get_ident(), module))
            return super().__enter__()

    monkeypatch.setattr(warnings, "catch_warnings", Recording)
    xpersson.solve(data, scheduler="threads", workers=2, chunk=chunk)
    assert entered  # the calling thread silenced the run
    # and no worker thread touched the filters
    assert {t for t, _ in entered} == {threading.get_ident()}, entered


@pytest.mark.parametrize("scheduler", [None, "threads"])
def test_the_users_filters_hold_after_a_sweep(scheduler):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        before = list(warnings.filters)
        ds = xpersson.solve(SWEEP, scheduler=scheduler, workers=2, chunk=2)
        assert ds.point_status.values.tolist() == [[0, 0], [0, 0], [0, 0]]
        assert warnings.filters == before
        with pytest.raises(UserWarning, match="still an error"):
            warnings.warn("still an error", UserWarning, stacklevel=1)


def test_interleaved_silenced_blocks_restore_the_filters():
    """Two threads enter and leave in the order that leaks a filter with plain
    ``catch_warnings`` (A in, B in, A out, B out); the shared one restores them."""
    before = list(warnings.filters)
    a_in, b_in, a_out = threading.Event(), threading.Event(), threading.Event()
    seen: dict[str, bool] = {}

    def a() -> None:
        with _quiet.silenced():
            a_in.set()
            b_in.wait(5)
        a_out.set()

    def b() -> None:
        a_in.wait(5)
        with _quiet.silenced():
            b_in.set()
            a_out.wait(5)
            seen["silenced after A left"] = warnings.filters[0][0] == "ignore"

    threads = [threading.Thread(target=a), threading.Thread(target=b)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(10)
    assert seen == {"silenced after A left": True}
    assert warnings.filters == before
