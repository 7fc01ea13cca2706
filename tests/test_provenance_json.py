"""The scene's JSON in the global attributes (issue 36): the output grid's text is made once
per grid and a list of loads' text by one join, spliced in; the result is
``json.dumps(resolved, sort_keys=True)`` exactly."""

from __future__ import annotations

import json

from hypothesis import given, settings
from hypothesis import strategies as st

from xpersson.provenance import _GRID_TOKEN, _LOADS_TOKEN, _strings_json, scene_json

_FLOAT = st.floats(allow_nan=True, allow_infinity=True) | st.sampled_from([0.0, -0.0, 1.0])


@settings(max_examples=100, deadline=None)
@given(
    zeta=st.lists(_FLOAT | st.integers(-3, 3), min_size=0, max_size=20),
    title=st.sampled_from(["a scene", _GRID_TOKEN, "zeta"]),
    extra=st.dictionaries(st.text(max_size=3), st.integers() | st.text(max_size=3), max_size=3),
)
def test_thescene_json_is_json_dumps_sorted(zeta, title, extra):
    resolved = {"title": title, "output": {"zeta": zeta, "p_points": 8, **extra}, "load": extra}
    assert scene_json(resolved) == json.dumps(resolved, sort_keys=True)
    assert scene_json(resolved) == scene_json(json.loads(json.dumps(resolved)))


_LOAD_TEXT = (
    st.text(st.sampled_from(list('0123456789.e+- Pak"\\/\n\t\x00\x7fµé\u2028')), max_size=8)
    | st.floats(1.0, 1e9).map(lambda x: f"{x!r} Pa")
    | st.just(_LOADS_TOKEN)
)


@settings(max_examples=80, deadline=None)
@given(
    p0=st.lists(_LOAD_TEXT, min_size=0, max_size=20)
    | st.lists(st.floats(1.0, 1e9).map(lambda x: f"{x!r} kPa"), min_size=9, max_size=40),
    zeta=st.lists(st.floats(1.0, 1e9), min_size=0, max_size=12),
    title=st.sampled_from(["a scene", _GRID_TOKEN, _LOADS_TOKEN, 'a "quoted" \\ title']),
    other=st.sampled_from([None, 3, "1 Pa", [1.0, "x"]]),
)
def test_a_list_of_loads_is_spliced_bit_for_bit(p0, zeta, title, other):
    """Load strings of any characters (quotes, backslashes, control and non-ASCII characters,
    the splice tokens), with or without an output grid: the text is json.dumps' exactly."""
    resolved = {"title": title, "output": {"zeta": zeta}, "load": {"p0": p0, "x": other}}
    if other is not None and len(p0) > 2:
        resolved["load"]["p0"] = [*p0[:2], other, *p0[2:]]  # a value that is not a string
    assert scene_json(resolved) == json.dumps(resolved, sort_keys=True)


def test_the_loads_of_a_study_are_joined_not_dumped():
    """1000 loads as written (``"<repr> Pa"``): their text by the join, equal to json.dumps';
    a string JSON escapes (a quote, a non-ASCII letter) sends the list to json.dumps."""
    p0 = [f"{1e3 * 1.007**k!r} Pa" for k in range(1000)]
    assert _strings_json(p0) == json.dumps(p0)
    for odd in ('1 "Pa"', "1 µPa", "1 Pa\\", "1\tPa"):
        assert _strings_json([*p0[:9], odd]) is None


def test_the_plugins_text_made_at_resolution_is_json_dumps_sorted():
    """``ResolvedScene.plugin_records_json`` (each record's text made once per discovery, by
    the registry) is the ``json.dumps`` of the plugins an archive records, also for a scene
    whose spectrum a sweep replaces by another model, and after a new discovery."""
    import copy

    from xpersson import Scene
    from xpersson.plugins import get_registry
    from xpersson.provenance import _plugins_json, plugins_used
    from xpersson.scene._resolve import with_spectrum

    reg = get_registry()
    data = {
        "spectrum": {"model": "self_affine", "H": 0.8, "q_L": "1e4 1/m", "q_1": "1e7 1/m",
                     "h_rms": "1 um"},
        "material": {"E": "10 MPa", "nu": 0.5},
        "load": {"p0": "100 kPa"},
        "analyses": {"mean_gap": {}},
    }  # fmt: skip
    rs = Scene(data).resolve(reg)
    want = json.dumps(plugins_used(rs), sort_keys=True)
    assert rs.plugin_records_json == want and _plugins_json(rs)[0] == want
    other = copy.deepcopy(data)
    other["spectrum"] = {
        "model": "tabulated",
        "q": ["1e4 1/m", "1e5 1/m", "1e7 1/m"],
        "C": ["1e-20 m^4", "1e-23 m^4", "1e-29 m^4"],
    }
    swapped = with_spectrum(rs, Scene(other), reg)
    assert "tabulated" in swapped.plugin_records_json
    assert swapped.plugin_records_json == json.dumps(plugins_used(swapped), sort_keys=True)
    reg.refresh()
    again = Scene(data).resolve(reg)
    assert again.plugin_records_json == want
    assert json.loads(again.plugin_records_json)[0]["group"] == plugins_used(again)[0]["group"]


def test_the_plugins_text_of_a_finite_body_records_its_geometry():
    from pathlib import Path

    from xpersson.plugins import get_registry
    from xpersson.provenance import plugins_used
    from xpersson.scene import load_scene

    sc = load_scene(Path(__file__).resolve().parents[1] / "examples" / "sphere.toml")
    rs = sc.resolve(get_registry())
    assert rs.plugin_records_json == json.dumps(plugins_used(rs), sort_keys=True)
    assert json.loads(rs.plugin_records_json)[-1]["group"] == "geometries"
