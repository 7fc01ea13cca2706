"""A method asked for by name that cannot treat the walls is refused before any work: by the
engine with :class:`xpersson.engine.MethodError` naming the methods that can, by
:func:`xpersson.solve` with a :class:`~xpersson.SceneError` naming ``solver.method``.

Found by ``benchmarks/fuzz.py --methods 1 --seed 191``: 278 of 10,000 scenes asking for
``exact`` or ``sine`` on moving walls ended in a bare ``ValueError`` from inside the engine.
"""

from __future__ import annotations

import numpy as np
import pytest

import xpersson
from xpersson.engine import METHODS, MethodError, Wall, solve, solve_batch
from xpersson.scene import SceneError

TAU = np.geomspace(1e-3, 1.0, 5)
MOVING = Wall.absorbing(lambda t: -0.1 * np.sqrt(np.asarray(t, dtype=float)))


@pytest.mark.parametrize("method", ["exact", "sine"])
def test_the_engine_names_the_methods_that_can(method):
    with pytest.raises(MethodError, match=r"methods that can: 'auto' \(picks one\), 'cn'"):
        solve(TAU, 1.0, MOVING, method=method)


def test_every_group_is_checked_before_any_runs(monkeypatch):
    """Two groups of loads: the fixed wall's (which ``exact`` treats) and the moving wall's
    (which it cannot): refused before the first group is solved."""
    ran = []
    exact = METHODS["exact"]
    monkeypatch.setattr(exact, "run", lambda self: ran.append(1) or pytest.fail("ran"))
    walls = [(Wall.absorbing(0.0), None), (MOVING, None)]
    with pytest.raises(MethodError):
        solve_batch(TAU, [1.0, 2.0], walls, method="exact")
    assert not ran


def test_solve_names_the_scene_parameter():
    sc = {
        "spectrum": {
            "model": "self_affine",
            "H": 0.8,
            "q_L": "1e3 1/m",
            "q_1": "1e6 1/m",
            "h_rms": "1 um",
        },  # fmt: skip
        "material": {"E": "10 MPa", "nu": 0.5},
        "load": {"p0": "100 kPa"},
        "boundary": {"model": "plastic_scale_dependent", "Y1": "1 MPa", "n": 0.5},
        "solver": {"method": "sine"},
    }
    with pytest.raises(SceneError, match=r"solver\.method = 'sine'.*'cn'.*plastic_scale_dep"):
        xpersson.solve(sc)
    sc["solver"]["method"] = "cn"  # one that can: solved
    assert xpersson.solve(sc).attrs["status"] == "success"
