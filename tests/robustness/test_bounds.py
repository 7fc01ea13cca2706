"""One budget for everything (issue 24): unit expressions parsed within bounds, a whole sweep
refused before any work when it exceeds the memory budget."""

from __future__ import annotations

import sys
import time
from pathlib import Path

import pytest

import xpersson
from xpersson import memory
from xpersson.cli import main
from xpersson.errors import MemoryBudgetError, UnitError
from xpersson.units import check_expression, to_si

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "sweep"))
from xpersson_sweep_testlib import scene  # noqa: E402

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "elastic.toml"


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("1 m**9**9**9", "towers"),
        ("1 Pa^9^9^9", "towers"),
        ("9**9**9**9 Pa", "towers"),
        ("1 (m**2)**9", "towers"),
        ("1 m**(9**9)", "plain number"),
        ("1 m**100", "beyond"),
        ("1 m**-1e9", "plain number|beyond"),
        ("(" * 20 + "1 Pa" + ")" * 20, "nested 20 deep"),
        ("1" * 300 + " Pa", "303 characters"),
    ],
)
def test_unbounded_unit_expressions_are_refused_at_once(text, match):
    t0 = time.perf_counter()
    with pytest.raises(UnitError, match=match):
        to_si(text, "Pa", "material.E")
    assert time.perf_counter() - t0 < 1.0


@pytest.mark.parametrize(
    ("text", "unit", "value"),
    [("2 m**2", "m**2", 2.0), ("1 m**(1/2)", "m**0.5", 1.0), ("3 kg*m/s**2", "N", 3.0)],
)
def test_ordinary_exponents_still_parse(text, unit, value):
    check_expression(text, "x")
    assert to_si(text, unit, "x") == pytest.approx(value)


def test_validate_answers_a_tower_of_exponents_quickly(capsys):
    t0 = time.perf_counter()
    assert main(["validate", str(EXAMPLE), "--set", 'material.E="1 MPa**9**9**9"']) == 2
    assert time.perf_counter() - t0 < 20
    assert "material.E" in capsys.readouterr().err


HUGE = scene(
    material={
        "E": {"start": "1 MPa", "stop": "10 MPa", "num": 100_000},
        "nu": {"start": 0.1, "stop": 0.4, "num": 100_000},
    }
)


@pytest.mark.parametrize("output", [None, "folder"])
def test_a_study_beyond_the_budget_is_refused_before_work(tmp_path, output):
    t0 = time.perf_counter()
    folder = None if output is None else tmp_path / "parts"
    with pytest.raises(MemoryBudgetError, match=r"10000000000 points x 3 loads") as info:
        xpersson.solve(HUGE, output=folder)
    assert "fewer points" in str(info.value)
    assert time.perf_counter() - t0 < 30
    assert folder is None or not folder.exists()  # refused before the folder is touched


def test_the_study_estimate_counts_points_loads_and_grids():
    one = memory.estimate_study(1, 3, 51)
    assert memory.estimate_study(1000, 3, 51) > 900 * (one - memory.estimate(3, 51))
    with_p = memory.estimate_study(1000, 3, 51, 200)
    assert with_p > memory.estimate_study(1000, 3, 51)
    folder = memory.estimate_study(1000, 3, 51, 200, block_points=10, in_memory=False)
    assert folder < with_p
    memory.set_budget(10**6)
    try:
        with pytest.raises(MemoryBudgetError, match="in parts"):
            memory.check_study(1000, 3, 51, 200)
    finally:
        memory.set_budget(None)
