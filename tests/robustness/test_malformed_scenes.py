"""The malformed-scene matrix: every bad input is refused before any work, naming the
parameter (and, for quantities, its unit or allowed range)."""

from __future__ import annotations

import copy
from typing import Any

import pytest
from xpersson_core_reference import REFERENCE_SCENE

import xpersson
from xpersson.scene import Scene, SceneError

_DELETE = object()

# (dotted parameter, SI unit as written in messages, a value outside the allowed range,
#  the allowed-range text the message must quote)
QUANTITIES = [
    ("material.E", "Pa", "-1 MPa", "(0, 1e+13] Pa"),
    ("load.p0", "Pa", "-5 kPa", "(0, 1e+13] Pa"),
    ("output.p_max", "Pa", "0 Pa", "(0, 1e+13] Pa"),
    ("spectrum.q_L", "1/m", "1e-20 1/m", "[1e-12, 1e+15] 1/m"),
    ("spectrum.q_r", "1/m", "1e20 1/m", "[1e-12, 1e+15] 1/m"),
    ("spectrum.q_1", "1/m", "1e300 1/m", "[1e-12, 1e+15] 1/m"),
    ("spectrum.h_rms", "m", "-1 um", "(0, 1e+06] m"),
]
NUMBERS = [  # dimensionless
    ("material.nu", 0.7, "(-1, 0.5]"),
    ("spectrum.H", 1.5, "(0, 1]"),
    ("solver.rtol", 0.5, "[1e-12, 0.1)"),
    ("solver.atol", -1.0, "[0, 0.1]"),
    ("output.zeta_max", 0.5, "[1, 1e+12]"),
]
INTEGERS = [
    ("output.zeta_per_decade", 0, "[1, 1000]"),
    ("output.p_points", 4, "[8, 100000]"),
]


def _cases() -> list[tuple[str, Any, list[str]]]:
    out: list[tuple[str, Any, list[str]]] = []
    for path, unit, outside, rng in QUANTITIES:
        out += [
            (path, "3 s", [path, unit]),  # wrong dimension
            (path, "12 blorps", [path, "cannot parse"]),  # unknown unit
            (path, "abc", [path, "cannot parse"]),
            (path, "", [path, "empty string"]),
            (path, 12.5, [path, "no unit"]),  # bare number
            (path, True, [path, "boolean"]),
            (path, f"nan {unit}", [path, "finite"]),
            (path, f"inf {unit}", [path, "finite"]),
            (path, outside, [path, rng]),
            (path, {"a": 1}, [path]),
        ]
    for path, outside, rng in NUMBERS:
        out += [
            (path, outside, [path, rng]),
            (path, "1 Pa", [path, "dimension"]),
            (path, "x", [path, "cannot parse"]),
            (path, True, [path, "boolean"]),
            (path, float("nan"), [path, "finite"]),
            (path, float("inf"), [path, "finite"]),
            (path, {"a": 1}, [path]),
        ]
    for path, outside, rng in INTEGERS:
        out += [
            (path, outside, [path, rng]),
            (path, 2.5, [path, "integer"]),
            (path, "10", [path, "integer"]),
            (path, True, [path, "integer"]),
            (path, 10**9, [path, rng]),
        ]
    out += [
        # the list
        ("output.zeta", [], ["output.zeta", "empty"]),
        ("output.p", [], ["output.p", "empty"]),
        ("output.p", ["1 MPa"], ["output.p", "at least 2"]),
        ("output.p", ["1 MPa", "0.5 MPa"], ["output.p", "increasing"]),
        ("output.p", ["1 MPa", "nan MPa"], ["output.p", "finite"]),
        ("output.p", ["1 MPa", "2 s"], ["output.p", "Pa"]),
        ("output.zeta", [0.5, 2.0], ["output.zeta", "[1, 1e+12]"]),
        ("output.zeta", [1.0, 1e9], ["output.zeta", "q_1/q_L"]),
        ("output.zeta", ["2 m"], ["output.zeta", "dimension"]),
        ("output.zeta", list(range(1, 100_003)), ["output.zeta", "at most 100000"]),
        ("output.zeta_max", 1e9, ["output.zeta_max", "q_1/q_L"]),
        ("output.pressure_pdf", "yes", ["output.pressure_pdf", "true or false"]),
        ("output.pressure_pdf", 1, ["output.pressure_pdf", "true or false"]),
        ("output.colour", "red", ["output.colour", "unknown parameter"]),
        ("solver.method", "rk45", ["solver.method", "rk45", "auto"]),
        ("solver.method", "", ["solver.method", "auto"]),
        ("solver.method", 3, ["solver.method", "string"]),
        ("solver.method", int, ["solver.method", "EngineMethod"]),
        ("solver.max_steps", 10, ["solver.max_steps", "unknown parameter"]),
        ("coefficient.gamma", 0.5, ["coefficient.gamma", "persson01"]),
        ("coefficient.closure", "yp09", ["coefficient.closure", "yp08"]),
        ("coefficient.model", "viscous_magic", ["coefficient.model", "viscous_magic"]),
        ("coefficient.colour", 1, ["coefficient.colour", "unknown parameter"]),
        ("load.p0", [f"{1000 + i} Pa" for i in range(200_000)], ["load.p0", "at most 100000"]),
        ("load.p0", [], ["load.p0", "empty"]),
        ("load.p0", ["1 MPa", "1 MPa"], ["load.p0", "increasing"]),
        ("load.p0", ["1 MPa", "x"], ["load.p0[1]", "cannot parse"]),
        ("load.p0", {"start": "1 kPa", "stop": "1 MPa", "num": 200_000}, ["load.p0.num", "100000"]),
        ("load.p0", {"start": "1 kPa", "stop": "1 MPa", "num": 0}, ["load.p0.num"]),
        ("load.p0", {"start": "1 kPa", "stop": "1 MPa"}, ["load.p0.num", "required"]),
        ("load.p0", {"start": "1 kPa", "stop": "1 MPa", "num": 3, "step": 2}, ["load.p0"]),
        ("load.p0", {"start": "1 MPa", "stop": "1 kPa", "num": 3}, ["load.p0", "stop"]),
        ("load.p0", {"start": "-1 kPa", "stop": "1 MPa", "num": 3}, ["load.p0", "start > 0"]),
        (
            "load.p0",
            {"start": "1 kPa", "stop": "1 MPa", "num": 3, "spacing": "cubic"},
            ["load.p0.spacing"],
        ),
        ("load.p0", _DELETE, ["load.p0", "required"]),
        ("load.force", "1 N", ["load.force", "finite body", "geometry"]),
        ("material.nu", _DELETE, ["material.nu", "required"]),
        ("material.G", "1 GPa", ["material.G", "unknown parameter"]),
        ("spectrum.model", "fractal_magic", ["spectrum.model", "fractal_magic"]),
        ("spectrum.Hurst", 0.8, ["spectrum.Hurst", "unknown parameter"]),
        ("spectrum.q_r", "1e2 1/m", ["spectrum.q_r", "q_L <= q_r"]),
        ("spectrum.q_1", "1e3 1/m", ["spectrum.q_1", "q_r < q_1"]),
        ("spectrum.rms_slope", 0.1, ["h_rms", "rms_slope", "C_r"]),
        ("spectrum.H", _DELETE, ["spectrum.H", "required"]),
        ("spectrum.q_L", "1e-12 1/m", ["q_1/q_L", "1e+12"]),
        ("boundary.model", "nonexistent_wall", ["boundary.model", "nonexistent_wall"]),
        ("boundary.sigma_Y", "1 GPa", ["boundary.sigma_Y", "unknown parameter"]),
        ("materials", {"E": "1 Pa"}, ["materials", "unknown section"]),
        ("analyses.not_an_analysis", {}, ["analyses", "not_an_analysis"]),
        ("analyses.contact_area", "yes", ["analyses.contact_area", "table"]),
        ("analyses.contact_area.level", 3, ["analyses.contact_area.level", "unknown"]),
        ("title", 3, ["title", "string"]),
        ("output", 3, ["output", "table"]),
    ]
    for section in ("analyses", "material", "boundary", "coefficient", "metadata", "spectrum"):
        out += [(section, bad, [section, "table"]) for bad in (None, [1], 2.5)]  # not tables
    return out


MALFORMED = _cases()


def _with(path: str, value: Any) -> dict[str, Any]:
    data = copy.deepcopy(REFERENCE_SCENE)
    keys = path.split(".")
    node = data
    for k in keys[:-1]:
        node = node.setdefault(k, {})
    if value is _DELETE:
        del node[keys[-1]]
    else:
        node[keys[-1]] = value
    if path == "output.p":
        data.setdefault("output", {})["pressure_pdf"] = True
    return data


def _id(case: tuple[str, Any, list[str]]) -> str:
    path, value, _ = case
    if value is _DELETE:  # (its repr holds an address: ids must agree across processes)
        return f"{path}=<deleted>"
    text = repr(value) if not isinstance(value, list) or len(value) < 5 else f"list{len(value)}"
    return f"{path}={text[:30]}"


def test_the_matrix_has_at_least_120_cases():
    assert len(MALFORMED) >= 120


@pytest.mark.parametrize(("path", "value", "words"), MALFORMED, ids=[_id(c) for c in MALFORMED])
def test_malformed_scene_is_refused_before_any_work(path, value, words, monkeypatch):
    import xpersson.engine as engine

    def boom(*a, **k):  # pragma: no cover - must not be reached
        raise AssertionError("the engine ran on a malformed scene")

    monkeypatch.setattr(engine, "solve", boom)
    with pytest.raises(SceneError) as info:
        xpersson.solve(Scene(_with(path, value)))
    msg = str(info.value)
    for w in words:
        assert w in msg, f"{w!r} not in {msg!r}"


# -- tabulated PSD files: the error names the parameter, the file and the line -----------------
PSD_FILES = [
    ("q C\n1 1\n2 nan\n3 0.5\n", "line 3", "C = nan is not finite"),
    ("1 1\nnan 2\n", "line 2", "q = nan is not finite"),
    ("1 1\n2 inf\n", "line 2", "not finite"),
    ("1 1\n2 -1\n", "line 2", "C = -1 must be > 0"),
    ("1 1\n2 0\n", "line 2", "C = 0 must be > 0"),
    ("-1 1\n2 1\n", "line 1", "q = -1 must be > 0"),
    ("1 1\n3 1\n2 1\n", "line 3", "is below q = 3 of line 2"),
    ("# header comment\n1 1\n2 1\n2 3\n", "line 4", "duplicates q = 2 of line 3"),
    ("", "line 0", "no data rows"),
    ("# only a comment\n\n", "line 2", "no data rows"),
    ("q C\n1 1\n", "line 2", "only one data row"),
    ("1 1\n2 x\n", "line 2", "cannot read"),
    ("1, 1\n2; 1\n3 1 extra\n4\n", "line 4", "cannot read"),
]


@pytest.mark.parametrize(("text", "line", "what"), PSD_FILES)
def test_psd_file_errors_name_the_file_and_the_line(tmp_path, text, line, what):
    path = tmp_path / "psd.txt"
    path.write_text(text)
    scene = copy.deepcopy(REFERENCE_SCENE)
    scene["spectrum"] = {"model": "tabulated", "file": str(path)}
    with pytest.raises(SceneError) as info:
        Scene(scene).resolve()
    msg = str(info.value)
    for w in ("spectrum.file", str(path), f"{line}:", what):
        assert w in msg, f"{w!r} not in {msg!r}"


def test_missing_psd_file_is_named(tmp_path):
    scene = copy.deepcopy(REFERENCE_SCENE)
    scene["spectrum"] = {"model": "tabulated", "file": str(tmp_path / "nope.txt")}
    with pytest.raises(SceneError, match=r"spectrum.file: cannot read .*nope.txt"):
        Scene(scene).resolve()
