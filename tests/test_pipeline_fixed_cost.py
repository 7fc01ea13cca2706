"""The short cuts of a solve's fixed cost give what the long ways give: a reused resolution
(no sweep search), a context copied by field, a key made once, a fixed wall checked without
a call, an empty contribution skipped."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import xpersson
from xpersson.cache import MadeKey, content_key, made_key
from xpersson.checks import PluginFailure, check_walls
from xpersson.engine import Wall
from xpersson.pipeline.frontend import replaced, reused
from xpersson.plugins import SceneContext, get_registry

SCENE = {
    "spectrum": {"model": "self_affine", "H": 0.7, "q_L": "1e4 1/m", "q_1": "1e7 1/m",
                 "h_rms": "1 um"},
    "material": {"E": "10 MPa", "nu": 0.5},
    "load": {"p0": "100 kPa"},
    "output": {"zeta_per_decade": 4},
}  # fmt: skip


def _ctx() -> SceneContext:
    return SceneContext(
        psd=None, E=1e7, nu=0.5, E_star=4e7 / 3, p0=np.array([1e5]), zeta=np.geomspace(1, 1e3, 7)
    )


def test_replaced_equals_dataclasses_replace():
    ctx = _ctx()
    for changes in ({"clock": object()}, {"p": np.arange(3.0), "p0": np.ones(2)}, {}):
        new, ref = replaced(ctx, **changes), dataclasses.replace(ctx, **changes)
        assert type(new) is SceneContext and new is not ctx
        for f in dataclasses.fields(SceneContext):
            assert getattr(new, f.name) is getattr(ref, f.name), f.name
    with pytest.raises(dataclasses.FrozenInstanceError):
        new.E = 2.0  # still frozen
    with pytest.raises(TypeError, match="no field 'nope'"):
        replaced(ctx, nope=1)


@pytest.mark.parametrize(
    "item",
    [(1.0, "a", (2.5, None)), {"a": 1.0, "b": [1, -0.0]}, np.arange(3.0), (np.arange(400.0),)],
)
def test_a_made_key_stands_for_itself(item):
    plain, made = content_key(item), made_key(item)
    assert made == plain and hash(made) == hash(plain)
    assert content_key(made) is made  # not walked again
    assert content_key(("x", made, 2.0)) == content_key(("x", item, 2.0))


def test_a_made_key_of_a_plain_value_is_the_value():
    assert made_key("text") == "text" and type(made_key("text")) is str
    assert type(made_key((1.0,))) is MadeKey


def test_a_fixed_wall_is_checked_as_before():
    assert check_walls((Wall.absorbing(0.0), None), 1e5, "who") == (Wall.absorbing(0.0), None)
    with pytest.raises(PluginFailure, match="not strictly below the load"):
        check_walls((Wall.absorbing(2e5), None), 1e5, "who")
    with pytest.raises(PluginFailure, match="must be finite"):
        check_walls((Wall.absorbing(float("nan")), None), 1e5, "who")
    with pytest.raises(PluginFailure, match="not strictly above the load"):
        check_walls((Wall.absorbing(0.0), Wall.absorbing(1e5)), 1e5, "who")


def test_no_breakpoints_from_an_empty_array():
    assert Wall.absorbing(lambda t: -t, breakpoints=np.array([])).breakpoints == ()
    assert Wall.absorbing(lambda t: -t, breakpoints=np.array([2.0, 1.0])).breakpoints == (1.0, 2.0)


def test_a_kept_resolution_skips_only_what_it_may():
    reg = get_registry()
    scene = {**SCENE, "output": {"zeta_per_decade": 3}}  # (not kept by another test)
    assert reused(xpersson.Scene(scene), reg) is None  # nothing kept yet
    first = xpersson.solve(scene)
    again = reused(xpersson.Scene(scene), reg)
    if again is not None:  # (kept with the caches and fast paths on)
        assert again.resolved == xpersson.Scene(scene).resolve(reg).resolved
    second = xpersson.solve(scene)
    for name in first.data_vars:
        np.testing.assert_array_equal(first[name].values, second[name].values)
    swept = {**scene, "material": {"E": ["10 MPa", "20 MPa"], "nu": 0.5}}
    assert reused(xpersson.Scene(swept), reg) is None  # another content: the sweep search
    assert xpersson.solve(swept).sizes["E"] == 2


def test_clean_decides_as_each_arrays_own_check():
    from xpersson.checks._dataset import _clean, _within

    rng = np.random.default_rng(7)
    bounds = [(None, None), (0.0, None), (0.0, 1.0), (1, None), (None, 0.5), (-np.inf, np.inf)]
    for _ in range(300):
        arrays, chosen = [], []
        for _ in range(rng.integers(1, 6)):
            shape = [(), (1,), (5,), (2, 3), (0,)][rng.integers(5)]
            arr = rng.uniform(-0.2, 1.2, shape).astype([np.float64, np.float32][rng.integers(2)])
            if arr.size and rng.random() < 0.2:
                arr.flat[rng.integers(arr.size)] = [np.nan, np.inf, -np.inf][rng.integers(3)]
            arrays.append(arr)
            chosen.append(bounds[rng.integers(len(bounds))])
        expected = all(_within(a, *b) for a, b in zip(arrays, chosen, strict=True))
        assert _clean(arrays, chosen) == expected, (arrays, chosen)
    assert not _clean([np.arange(3)], [(None, None)])  # not floats: not decided here
    assert not _clean([np.ones(2)], [(2**60, None)])  # a bound a float does not hold exactly
