"""The scene's JSON in the global attributes (issue 36): the output grid's text is made once
per grid and spliced in; the result is ``json.dumps(resolved, sort_keys=True)`` exactly."""

from __future__ import annotations

import json

from hypothesis import given, settings
from hypothesis import strategies as st

from xpersson.provenance import _GRID_TOKEN, _scene_json

_FLOAT = st.floats(allow_nan=True, allow_infinity=True) | st.sampled_from([0.0, -0.0, 1.0])


@settings(max_examples=100, deadline=None)
@given(
    zeta=st.lists(_FLOAT | st.integers(-3, 3), min_size=0, max_size=20),
    title=st.sampled_from(["a scene", _GRID_TOKEN, "zeta"]),
    extra=st.dictionaries(st.text(max_size=3), st.integers() | st.text(max_size=3), max_size=3),
)
def test_the_scene_json_is_json_dumps_sorted(zeta, title, extra):
    resolved = {"title": title, "output": {"zeta": zeta, "p_points": 8, **extra}, "load": extra}
    assert _scene_json(resolved) == json.dumps(resolved, sort_keys=True)
    assert _scene_json(resolved) == _scene_json(json.loads(json.dumps(resolved)))
