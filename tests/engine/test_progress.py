"""Progress of long solves: the moving-wall path reports its work; nothing else changes."""

from __future__ import annotations

import threading

import numpy as np
import pytest

import xpersson
from xpersson.engine import Wall, _compiled, progress_reporting, solve

P0, S0, C = 0.5, 0.2, 1.0
TAU = np.logspace(-3, 0, 13)


def _cn():
    return solve(TAU, P0, Wall.linear(-S0, -C), None, rtol=1e-6, method="cn")


@pytest.mark.parametrize("compiled", [False, True])
def test_cn_reports_its_work_and_results_do_not_change(compiled, request):
    """Reporting changes no number, on the numpy path and with the compiled march (a level
    that reports is marched in compiled blocks, one that does not in one fused call: the
    same numbers)."""
    if compiled:
        request.getfixturevalue("compiled_on")  # numba present, compiled on whatever the env
        assert _compiled.build()
    seen: list[int] = []
    with xpersson.set_options(compiled=compiled):
        with progress_reporting(seen.append):
            res = _cn()
        assert seen and all(n > 0 for n in seen)
        # more than one report: the counter moves during the solve, not only at its end
        assert len(seen) > 1
        # the reporter is gone after the block, and reporting changes no number
        n_seen = len(seen)
        plain = _cn()
    assert len(seen) == n_seen
    np.testing.assert_array_equal(res.area, plain.area)
    np.testing.assert_array_equal(res.error_estimate, plain.error_estimate)


def test_closed_form_reports_no_work():
    seen: list[int] = []
    with progress_reporting(seen.append):
        res = solve(TAU, P0, Wall.absorbing(0.0), None, rtol=1e-8, method="exact")
    assert res.status == "success"
    assert seen == []


def test_reporter_is_private_to_its_thread():
    mine: list[int] = []

    def work() -> None:  # a new thread starts with an empty context: no reporter
        _cn()

    with progress_reporting(mine.append):
        t = threading.Thread(target=work)
        t.start()
        t.join()
    assert mine == []  # the thread's solve did not report into this context's reporter
