"""No state passes between plugin calls through ``self``: a solve leaves every first-party
boundary instance as it was, and ``Boundary.interpret`` reads the run's clock as
``ctx.clock`` (issue 33, part 4)."""

from __future__ import annotations

import pickle
import warnings

import numpy as np
import pytest

import xpersson
from xpersson.pipeline import run
from xpersson.plugins import Boundary, get_registry
from xpersson.testing import check_plugin, sample_params, tiny_scene

FIRST_PARTY = (
    "xpersson",
    "xpersson-plasticity",
    "xpersson-interface",
    "xpersson-viscoelastic",
    "xpersson-adhesion",
)
#: SI parameters of boundaries whose required parameters declare no example; ``jkr_area``
#: is jkr with the pull-off policy that solves the scene's wall on the run's clock
PARAMS = {
    "plastic_scale_dependent": {"Y1": 3e6, "n": 0.2},
    "jkr": {"work_of_adhesion": 0.05},
    "jkr_area": {"work_of_adhesion": 0.5, "pull_off_area": 1e-3},
    "dmt": {"work_of_adhesion": 1e-3, "range": 5e-9, "law": "exponential"},
}
NAMES = sorted(
    name
    for name, bucket in get_registry().entries("boundaries").items()
    if any(info.dist in FIRST_PARTY for info in bucket)
) + ["jkr_area"]


def _snapshot(inst: object) -> dict[str, tuple[int, bytes]]:
    """Each attribute: the object bound to it and its pickled content."""
    return {k: (id(v), pickle.dumps(v)) for k, v in vars(inst).items()}


@pytest.mark.parametrize("name", NAMES)
def test_a_solve_leaves_the_boundary_instance_unchanged(name):
    model = name.removesuffix("_area")
    cls = get_registry().load("boundaries", model)
    params = sample_params(cls, PARAMS.get(name))
    scene = tiny_scene(cls, params, {"load": {"p0": ["1e4 Pa", "1e5 Pa"]}})
    scene["boundary"]["model"] = model
    rs = xpersson.Scene(scene).resolve()
    before, shipped = _snapshot(rs.boundary), pickle.dumps(rs.boundary)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # validity notes of approximations
        ds = run(rs)
    assert np.all(np.isfinite(ds["area_fraction"].values))
    assert _snapshot(rs.boundary) == before, f"{name}: the solve changed the instance"
    assert pickle.dumps(rs.boundary) == shipped


def test_interpret_reads_the_clock_walls_received():
    """jkr's pull-off at an area solves the wall of ``ctx.clock``: the pipeline's value equals
    the one computed with the clock passed explicitly."""
    from xpersson.pipeline.frontend import diffusion_clock, scene_context, spectrum_kinks

    scene = tiny_scene(
        get_registry().load("boundaries", "jkr"), PARAMS["jkr_area"], {"load": {"p0": "1e4 Pa"}}
    )
    scene["boundary"]["model"] = "jkr"
    rs = xpersson.Scene(scene).resolve()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        ds = run(rs)
    ctx = scene_context(rs)
    clock = diffusion_clock(ctx, rs.coefficient, kinks=spectrum_kinks(rs.psd))
    tau_end = float(ds["diffusion_time"].values[-1])
    expected = rs.boundary.pull_off(ctx, tau_end, clock)
    assert 0.0 < expected < rs.boundary.sigma_a_start(ctx)  # the area policy, not sigma_a(1)
    assert float(ds["pull_off_stress"]) == expected


class _Remembering(Boundary):
    """Keeps walls()'s clock on self for interpret(): what check_plugin must refuse."""

    summary = "test boundary that passes state through self"

    def __init__(self, **params):
        super().__init__(**params)
        self._clock = None

    def walls(self, ctx, p0, clock):
        from xpersson.engine import Wall

        self._clock = clock
        return Wall.absorbing(0.0), None

    def interpret(self, ctx, results):
        return {}


def test_check_plugin_refuses_state_passed_through_self():
    with pytest.raises(AssertionError, match=r"walls\(\) changed the instance's attributes"):
        check_plugin(_Remembering, cheap_import=False, engine=False)
