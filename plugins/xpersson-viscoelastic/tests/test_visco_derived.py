"""A (v, T) sweep's points derived from one resolved point per block (issue 25): equal to the
points resolved one by one, and a bad value fails before any work with the same message."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import xpersson
from xpersson.plugins import get_registry
from xpersson.sweep import derived, plain_paths
from xpersson.sweep.execute import _resolve_index, resolve_points
from xpersson.sweep.plan import expand

SCENE = Path(__file__).resolve().parents[1] / "examples" / "tread_on_asphalt.toml"


def _plan(**coefficient):
    scene = xpersson.load_scene(SCENE)
    data = dict(scene.data)
    data["coefficient"] = {**data["coefficient"], **coefficient}
    return expand(xpersson.Scene(data, scene.source))


def test_derived_points_equal_resolved_points():
    plan = _plan(velocity=["1e-4 m/s", "0.03 m/s", "2 m/s"], temperature=["280 K", "300 K"])
    reg = get_registry()
    got = resolve_points(plan, reg)
    assert got[1].psd is got[0].psd  # derived: the first point's spectrum shared
    for k, index in enumerate(plan.indices()):
        ref = _resolve_index(plan, index, reg)
        rs = got[k]
        assert rs.coefficient == ref.coefficient  # every parameter, SI values
        assert rs.coefficient.shift_factor == ref.coefficient.shift_factor
        assert rs.resolved == ref.resolved  # the archived (provenance) scene
        assert [a for _, a in rs.analyses] == [a for _, a in ref.analyses]
        assert str(rs.labels["coefficient"]) == str(ref.labels["coefficient"])
        np.testing.assert_array_equal(rs.zeta, ref.zeta)


@pytest.mark.fast_paths
def test_only_declared_parameters_are_derived(monkeypatch):
    plan = _plan(velocity=["1e-4 m/s", "0.03 m/s"])
    reg = get_registry()
    calls = []
    got = derived.derived_region(
        plan, (0,), (2,), lambda i: calls.append(i) or _resolve_index(plan, i, reg), str, reg
    )
    assert calls == [(0,)] and len(got) == 2
    with plain_paths():
        assert derived.derived_region(plan, (0,), (2,), None, str, reg) is None
    plan = _plan(gamma=[0.4, 0.5])  # not a declared stacked parameter: each point resolved
    one = lambda i: _resolve_index(plan, i, reg)  # noqa: E731
    assert derived.derived_region(plan, (0,), (2,), one, str, reg) is None


@pytest.mark.parametrize("enabled", [True, False])
def test_bad_temperature_names_point_parameter_unit_and_range(enabled):
    # WLF with T_ref = 293.15 K, C2 = 114.75 K: temperatures at or below 178.4 K are refused
    plan = _plan(velocity=["1e-4 m/s", "0.03 m/s"], temperature=["300 K", "150 K"])
    with pytest.raises(xpersson.SceneError) as err:
        if enabled:
            resolve_points(plan, get_registry())
        else:
            with plain_paths():
                resolve_points(plan, get_registry())
    msg = str(err.value)
    assert msg.startswith("sweep point coefficient.velocity = 0.0001")
    assert "coefficient.temperature: 150 K is outside the range of the WLF law" in msg
    assert "allowed (T_ref - C2, inf) = (178.4, inf) K" in msg


def test_stacked_stieltjes_weights_equal_the_per_grid_weights():
    from xpersson_viscoelastic._stencil import stacked_weights
    from xpersson_viscoelastic.kernel import _cubic_weights, stieltjes_increments

    rng = np.random.default_rng(3)
    grids = [np.sort(rng.uniform(-5, 5, n)) for n in (3, 4, 17, 60)]
    got = stacked_weights(grids)
    assert got[0] is None
    for x, w in zip(grids[1:], got[1:], strict=True):
        W, start = _cubic_weights(tuple(float(v) for v in x))
        np.testing.assert_array_equal(w[1], start)
        np.testing.assert_allclose(w[0], W, rtol=1e-13, atol=0)
        g, L = rng.uniform(0, 1, (2, x.size)), np.cumsum(rng.uniform(0, 1, x.size))
        np.testing.assert_allclose(
            stieltjes_increments(g, L, x, w), stieltjes_increments(g, L, x), rtol=1e-13, atol=0
        )
