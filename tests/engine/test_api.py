"""Input validation, method selection and the registry."""

from __future__ import annotations

import numpy as np
import pytest

from xpersson.engine import EngineMethod, EngineResult, Wall, register_method, solve
from xpersson.engine._result import Raw

TAU = np.array([0.0, 0.5, 2.0])


@pytest.mark.parametrize(
    ("kwargs", "words"),
    [
        (dict(tau_out=[0.0, 2.0, 1.0]), ("tau_out", "Pa^2", "increasing")),
        (dict(tau_out=[-1.0, 1.0]), ("tau_out", "Pa^2", ">= 0")),
        (dict(tau_out=[0.0, np.nan]), ("tau_out", "Pa^2", "finite")),
        (dict(p0=-1.0), ("p0", "Pa", "above the lower wall")),
        (dict(p0=np.nan), ("p0", "Pa", "finite")),
        (dict(p0=3.0, upper=Wall.absorbing(2.0)), ("p0", "Pa", "below the upper wall")),
        (dict(rtol=0.5), ("rtol", "(0, 0.1)")),
        (dict(rtol=0.0), ("rtol", "(0, 0.1)")),
        (dict(atol=-1.0), ("atol", "(0, 0.1)")),
        (dict(p_out=[[1.0]]), ("p_out", "Pa")),
        (dict(lower=None), ("lower", "Wall")),
    ],
)
def test_bad_input_names_parameter_unit_and_range(kwargs, words):
    args = dict(tau_out=TAU, p0=1.0)
    args.update(kwargs)
    with pytest.raises(ValueError) as info:
        solve(args.pop("tau_out"), args.pop("p0"), **args)
    for w in words:
        assert w in str(info.value)


def test_auto_picks_exact_when_possible_and_cn_otherwise():
    assert solve(TAU, 1.0).method == "exact"
    assert solve(TAU, 1.0, upper=Wall.absorbing(3.0)).method == "exact"
    moving = Wall.absorbing(lambda t: -0.1 * np.sqrt(t))
    assert solve(TAU, 1.0, moving, rtol=1e-3).method == "cn"
    with pytest.raises(ValueError, match="cannot treat"):
        solve(TAU, 1.0, moving, method="sine")
    with pytest.raises(ValueError, match="method"):
        solve(TAU, 1.0, method="nope")


def test_result_fields_and_balances():
    r = solve(TAU, 1.0, Wall.absorbing(-0.5), Wall.absorbing(4.0))
    assert isinstance(r, EngineResult) and r.success and r.status == "success"
    for name in (
        "area",
        "non_area",
        "absorbed_lower",
        "absorbed_upper",
        "load",
        "wall_lower",
        "wall_upper",
        "error_estimate",
        "probability_balance",
        "load_balance",
    ):
        assert getattr(r, name).shape == TAU.shape
    np.testing.assert_array_equal(r.tau, TAU)
    np.testing.assert_allclose(
        r.probability_balance, r.area + r.absorbed_lower + r.absorbed_upper - 1, atol=0
    )
    # two fixed walls: (load + a*abs_l + b*abs_u - p0) / max(|p0|, |a|) (the upper wall's
    # position is not in the scale: _cn_outputs.load_scale)
    lb = (r.load - 0.5 * r.absorbed_lower + 4.0 * r.absorbed_upper - 1.0) / 1.0
    np.testing.assert_allclose(r.load_balance, lb, atol=1e-16)
    with pytest.raises(AttributeError):
        r.status = "x"  # frozen


def test_register_method_and_class_method():
    class Constant(EngineMethod):
        name = "constant"

        @classmethod
        def admits(cls, problem):
            return True

        def run(self):
            n = self.problem.tau.size
            one, zero = np.ones(n), np.zeros(n)
            return Raw(one, zero, zero, zero, np.full(n, self.problem.p0), zero, zero + 1e-20)

    r = solve(TAU, 1.0, method=Constant)
    assert r.method == "constant" and r.success
    register_method("constant", Constant)
    assert solve(TAU, 1.0, method="constant").method == "constant"
    with pytest.raises(ValueError):
        register_method("auto", Constant)
    with pytest.raises(ValueError):
        register_method("x", dict)


def test_max_steps_is_reported_honestly():
    moving = Wall.absorbing(lambda t: -0.1 * np.sqrt(t))
    r = solve(np.logspace(-3, 1, 5), 1.0, moving, rtol=1e-6, max_steps=50)
    assert r.status == "max_steps" and not r.success and "max_steps" in r.message


def test_unmet_tolerance_is_reported_not_hidden():
    moving = Wall.absorbing(lambda t: -0.1 * np.sqrt(t))
    r = solve(np.logspace(-3, 1, 5), 1.0, moving, rtol=1e-9, options={"levels": 2})
    assert r.status == "tolerance_not_met" and not r.success
    assert "tolerance" in r.message
