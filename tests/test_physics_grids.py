"""Output grids of a solve (xpersson.physics.grids): closed-form ends, errors, G = tau / p0^2."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from xpersson.physics.grids import GridError, persson_G, pressure_grid


def _wall(position):
    return SimpleNamespace(position=position)


def test_default_grid_spans_zero_to_load_plus_eight_sigma():
    p0 = np.array([1e5, 3e5])
    tau = np.array([[0.0, 2e9, 8e9], [0.0, 1e9, 2e9]])  # the largest final tau sets the width
    grid = pressure_grid(p0, [(_wall(0.0), None)] * 2, tau, 11)
    assert grid[0] == 0.0
    assert grid[-1] == 3e5 + 8.0 * np.sqrt(2.0 * 8e9)
    np.testing.assert_allclose(np.diff(grid), grid[-1] / 10, rtol=1e-12)


def test_walls_cut_the_grid_and_p_max_replaces_the_upper_end():
    p0 = np.array([1e5])
    tau = np.array([[0.0, 1e10]])
    lower = _wall(lambda t: -1e-6 * t)  # an adhesive wall moving below zero
    upper = _wall(2e5)
    grid = pressure_grid(p0, [(lower, upper)], tau, 5)
    assert (grid[0], grid[-1]) == (-1e4, 2e5)
    assert pressure_grid(p0, [(lower, upper)], tau, 5, p_max=5e5)[-1] == 5e5
    with pytest.raises(GridError, match="must exceed the lower wall -10000 Pa"):
        pressure_grid(p0, [(lower, upper)], tau, 5, p_max=-2e4)


def test_persson_G_is_tau_over_p0_squared_and_infinite_at_zero_load():
    tau = np.array([0.0, 4.0, 16.0])
    G = persson_G(tau, np.array([2.0, 4.0]))
    np.testing.assert_array_equal(G, [[0.0, 1.0, 4.0], [0.0, 0.25, 1.0]])
    G0 = persson_G(tau, np.array([0.0, 2.0]))
    assert np.all(np.isinf(G0[0])) and G0[0, 0] > 0
    np.testing.assert_array_equal(G0[1], [0.0, 1.0, 4.0])
