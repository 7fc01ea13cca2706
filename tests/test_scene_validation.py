"""Malformed scenes are rejected before any work, with a message naming the parameter."""

from __future__ import annotations

import copy

import numpy as np
import pytest
from xpersson_core_reference import REFERENCE_SCENE

import xpersson
from xpersson.scene import Scene, SceneError, load_scene


def _with(path: str, value):
    data = copy.deepcopy(REFERENCE_SCENE)
    node = data
    keys = path.split(".")
    for k in keys[:-1]:
        node = node.setdefault(k, {})
    if value is _DELETE:
        del node[keys[-1]]
    else:
        node[keys[-1]] = value
    return data


_DELETE = object()

MALFORMED = [
    # (path, value, words the message must contain)
    ("material.E", "10 m", ["material.E", "Pa"]),
    ("material.E", "-1 MPa", ["material.E", "outside the allowed range"]),
    ("material.E", 1e7, ["material.E", "no unit"]),
    ("material.nu", 0.6, ["material.nu", "(-1, 0.5]"]),
    ("material.nu", -1.0, ["material.nu", "(-1, 0.5]"]),
    ("material.nu", _DELETE, ["material.nu", "required"]),
    ("spectrum.H", 1.5, ["spectrum.H", "(0, 1]"]),
    ("spectrum.H", 0.0, ["spectrum.H", "(0, 1]"]),
    ("spectrum.q_r", "1e2 1/m", ["q_r", "q_L <= q_r"]),
    ("spectrum.q_1", "1e3 1/m", ["q_1", "q_r < q_1"]),
    ("spectrum.q_L", "1 mm", ["spectrum.q_L", "1/m"]),
    ("spectrum.h_rms", "abc", ["spectrum.h_rms", "cannot parse"]),
    ("spectrum.rms_slope", 0.1, ["exactly one of h_rms"]),
    ("spectrum.model", "fractal_magic", ["spectrum.model", "fractal_magic"]),
    ("spectrum.Hurst", 0.8, ["spectrum.Hurst", "unknown parameter"]),
    ("load.p0", "-5 kPa", ["load.p0", "outside the allowed range"]),
    ("load.p0", "0 Pa", ["load.p0", "(0, 1e+13] Pa"]),
    ("load.p0", ["1e5 Pa", "1e4 Pa"], ["load.p0", "increasing"]),
    ("load.p0", "1 N", ["load.p0", "Pa"]),
    ("load.force", "1 N", ["load.force", "finite body", "geometry"]),
    ("coefficient.closure", "yp09", ["coefficient.closure", "yp08"]),
    ("coefficient.gamma", 1.5, ["coefficient.gamma", "(0, 1]"]),
    ("solver.rtol", 0.5, ["solver.rtol", "[1e-12, 0.1)"]),
    ("output.zeta_max", 1e9, ["output.zeta_max", "q_1/q_L"]),
    ("output.zeta_per_decade", 2.5, ["output.zeta_per_decade", "integer"]),
    ("output.pressure_pdf", "yes", ["output.pressure_pdf", "true or false"]),
    ("boundary.model", "nonexistent_wall", ["boundary.model", "nonexistent_wall"]),
    ("materials", {"E": "1 Pa"}, ["materials", "unknown section"]),
    ("analyses.not_an_analysis", {}, ["analyses", "not_an_analysis"]),
]


@pytest.mark.parametrize(("path", "value", "words"), MALFORMED, ids=[m[0] for m in MALFORMED])
def test_malformed_scene_is_rejected_naming_the_parameter(path, value, words):
    with pytest.raises(SceneError) as info:
        Scene(_with(path, value)).resolve()
    msg = str(info.value)
    for w in words:
        assert w in msg, f"{w!r} not in {msg!r}"


def test_at_least_fifteen_malformed_scenes():
    assert len(MALFORMED) >= 15


def test_missing_sections_named():
    with pytest.raises(SceneError, match="spectrum"):
        Scene({"material": REFERENCE_SCENE["material"], "load": {"p0": "1 MPa"}}).resolve()
    with pytest.raises(SceneError, match="load.p0"):
        Scene({k: v for k, v in REFERENCE_SCENE.items() if k != "load"}).resolve()


def test_invalid_toml_and_missing_file(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[spectrum\nH = 0.8\n")
    with pytest.raises(SceneError, match="invalid TOML"):
        load_scene(bad)
    with pytest.raises(SceneError, match="cannot read scene file"):
        load_scene(tmp_path / "nope.toml")


def test_quantities_are_converted_to_si(scene):
    scene["material"]["E"] = "10000 kPa"
    scene["spectrum"]["h_rms"] = "1000 nm"
    rs = Scene(scene).resolve()
    assert rs.E == pytest.approx(1e7, rel=1e-15)
    assert rs.psd.h_rms() == pytest.approx(1e-6, rel=1e-12)
    assert rs.E_star == pytest.approx(1e7 / 0.75, rel=1e-15)


def test_pint_quantities_accepted(scene):
    ureg = pytest.importorskip("pint").UnitRegistry()
    scene["material"]["E"] = 10 * ureg.MPa
    rs = Scene(scene).resolve()
    assert rs.E == pytest.approx(1e7)


def test_load_range_and_zeta_grid(scene):
    scene["load"]["p0"] = {"start": "1 kPa", "stop": "1 MPa", "num": 4}
    scene["output"] = {"zeta_per_decade": 3}
    rs = Scene(scene).resolve()
    np.testing.assert_allclose(rs.p0, [1e3, 1e4, 1e5, 1e6], rtol=1e-12)
    assert rs.zeta[0] == 1.0 and rs.zeta[-1] == 1e5
    assert rs.zeta.size == 3 * 5 + 1
    assert np.all(np.diff(np.log10(rs.zeta)) == pytest.approx(1 / 3))


def test_resolved_scene_round_trips(scene):
    rs = Scene(scene).resolve()
    again = Scene(rs.resolved).resolve()
    np.testing.assert_array_equal(again.p0, rs.p0)
    np.testing.assert_array_equal(again.zeta, rs.zeta)
    assert again.E == rs.E and again.psd.h_rms() == pytest.approx(rs.psd.h_rms(), rel=1e-14)


def test_solve_rejects_before_work(scene, monkeypatch):
    import xpersson.engine as engine

    def boom(*a, **k):  # pragma: no cover - must not be reached
        raise AssertionError("the engine ran on a malformed scene")

    monkeypatch.setattr(engine, "solve", boom)
    scene["material"]["nu"] = 0.7
    with pytest.raises(SceneError, match="material.nu"):
        xpersson.solve(scene)
