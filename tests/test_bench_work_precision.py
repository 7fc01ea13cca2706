"""The speed-up at matched error of ``benchmarks/engine_vs_peers.py`` (its report module):
for each peer run, the fastest engine run at least as accurate; the scene's figure is the
smallest ratio; the worst scene is the smallest over scenes; the C march pairs with its run."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

report = pytest.importorskip("engine_vs_peers_report")


def _row(scene: str, solver: str, t: float, err: float, kind: str, res: str = "") -> dict:
    return {"scene": scene, "solver": solver, "time_s": t, "err": err, "kind": kind,
            "resolution": res}  # fmt: skip


def _rows(scene: str = "a", scale: float = 1.0) -> list[dict]:
    cn, bdf = "xpersson cn", "scipy BDF MoL (tau)"
    return [
        _row(scene, cn, 1e-3, 1e-4, "engine", "rtol=0.0001, n=9"),
        _row(scene, "C march", 4e-4, 1e-4, "limit"),
        _row(scene, cn, 3e-3, 1e-6, "engine", "rtol=1e-06, n=17"),
        _row(scene, "C march", 2e-3, 1e-6, "limit"),
        _row(scene, bdf, 0.05 * scale, 5e-4, "peer"),  # 1 ms run matches: 50x
        _row(scene, bdf, 0.4 * scale, 2e-6, "peer"),  # the 3 ms run matches: 133x
        _row(scene, bdf, 1.0 * scale, 1e-7, "peer"),  # no engine run as accurate: skipped
        _row(scene, bdf, math.nan, math.nan, "peer"),  # a failed run: skipped
    ]


def test_matched_takes_the_fastest_engine_run_as_accurate_and_the_peers_best_showing():
    m = report.matched(_rows(), "a", "xpersson cn", "scipy BDF MoL (tau)")
    assert m["ratio"] == pytest.approx(50.0)
    assert m["peer"]["err"] == 5e-4 and m["engine"]["time_s"] == 1e-3


def test_no_engine_run_as_accurate_gives_none():
    rows = [r for r in _rows() if r["err"] != 5e-4 and r["err"] != 2e-6]
    assert report.matched(rows, "a", "xpersson cn", "scipy BDF MoL (tau)") is None


def test_the_worst_scene_is_the_smallest_speed_up():
    rows = _rows("fast peer", 0.1) + _rows("slow peer", 10.0)
    scene, m = report.worst_matched(rows, "xpersson cn", "scipy BDF MoL (tau)")
    assert scene == "fast peer" and m["ratio"] == pytest.approx(5.0)


def test_each_c_march_row_pairs_with_the_cn_run_before_it():
    lim = report.limit_ratios(_rows())
    assert [(s, round(r, 6)) for s, r, _ in lim["0.0001"]] == [("a", 2.5)]
    assert [(s, round(r, 6)) for s, r, _ in lim["1e-06"]] == [("a", 1.5)]
