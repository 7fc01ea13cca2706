"""solve_sourced: point injections above a reflecting wall (physics.md §5.5b in diffusion time)."""

from __future__ import annotations

import numpy as np
import pytest

from xpersson.engine import Wall, solve, solve_sourced


def _reflected_kernel(p, x0, tau):
    """N(p; x0, 2 tau) + N(p; -x0, 2 tau)."""
    var = 2.0 * tau
    return (np.exp(-((p - x0) ** 2) / (2 * var)) + np.exp(-((p + x0) ** 2) / (2 * var))) / (
        np.sqrt(2 * np.pi * var)
    )


@pytest.mark.parametrize("rtol", [1e-2, 1e-3])
def test_single_injection_matches_reflected_heat_kernel(rtol):
    x0, tau = 1.0, np.array([0.01, 0.05, 0.2])
    p = np.linspace(0.0, 4.0, 801)
    res = solve_sourced(tau, [0.0], [x0], [1.0], lower=Wall.reflecting(0.0), p_out=p, rtol=rtol)
    assert res.success, res.message
    assert res.P.shape == (tau.size, p.size)
    for k, t in enumerate(tau):
        exact = _reflected_kernel(p, x0, t)
        assert np.max(np.abs(res.P[k] - exact)) <= rtol * exact.max()
    np.testing.assert_allclose(res.injected, 1.0, rtol=0, atol=1e-15)
    assert np.max(np.abs(res.mass_balance)) < 1e-10


def test_shifted_wall_and_batch():
    """A wall at p = 5 is a translation; a (n_batch, n_src) source array solves all at once."""
    tau = np.array([0.05])
    p = np.linspace(5.0, 8.0, 301)
    res = solve_sourced(
        tau, [0.0], [[6.0], [5.5]], [[1.0], [0.5]], lower=Wall.reflecting(5.0), p_out=p, rtol=1e-3
    )
    assert res.P.shape == (2, 1, p.size)
    for r, (x0, w) in enumerate(((1.0, 1.0), (0.5, 0.5))):
        exact = w * _reflected_kernel(p - 5.0, x0, tau[0])
        assert np.max(np.abs(res.P[r, 0] - exact)) <= 1e-3 * exact.max()
    np.testing.assert_allclose(res.mass[:, 0], [1.0, 0.5], atol=1e-10)
    # a source injected after the output time is not counted
    late = solve_sourced([0.05], [0.1], [1.0], [1.0], p_out=p - 5.0)
    assert late.injected[0] == 0.0 and np.all(late.P == 0.0)


@pytest.mark.parametrize(
    ("kwargs", "words"),
    [
        (dict(tau_out=[0.0, 1.0]), ("tau_out", "Pa^2", "> 0")),
        (dict(sources_tau=[-1.0]), ("sources_tau", "Pa^2", ">= 0")),
        (dict(sources_position=[-0.5]), ("sources_position", "Pa", ">= the wall")),
        (dict(sources_weight=[-1.0]), ("sources_weight", "1", ">= 0")),
        (dict(rtol=0.5), ("rtol", "(0, 0.1)")),
        (dict(lower=Wall.absorbing(0.0)), ("lower", "Wall.reflecting")),
        (dict(options={"p_max": 0.5}), ("p_max", "Pa", "above every source")),
    ],
)
def test_bad_input_names_parameter(kwargs, words):
    args = dict(tau_out=[1.0], sources_tau=[0.0], sources_position=[1.0], sources_weight=[1.0])
    args.update(kwargs)
    with pytest.raises(ValueError) as err:
        solve_sourced(**args, p_out=[0.0, 1.0])
    for w in words:
        assert w in str(err.value)


def test_solve_rejects_reflecting_wall():
    with pytest.raises(ValueError, match="solve_sourced"):
        solve([1.0], 1.0, Wall.reflecting(0.0))
