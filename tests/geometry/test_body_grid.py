"""The body's reported grid error bounds what the solved pressure grid changes (issue 39)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import xpersson
import xpersson.scene._geometry as geometry
from xpersson.physics.body import Separation, start_at_area

from .conftest import body_scene

_OUT = ("nominal_contact_radius", "real_contact_area", "approach")


def _solve(monkeypatch: pytest.MonkeyPatch, per_decade: int) -> xpersson.Dataset:
    monkeypatch.setattr(geometry, "PER_DECADE", per_decade)
    return xpersson.solve(body_scene(force=["0.1 mN", "1 mN", "10 mN"], h_rms="300 nm"))


def test_reported_grid_error_bounds_the_pressure_grid_change(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """8 and 16 pressures per decade: radius, area and approach move by less than the stated
    ``body_grid_error`` (the continuation of u(p) starts at A/A0 = 1e-3 exactly, not at the
    grid node above it, which moved the radius by 6e-4 with a stated error of 3e-4)."""
    coarse, fine = _solve(monkeypatch, 8), _solve(monkeypatch, 16)
    assert float(coarse["johnson_parameter"].max()) > 0.3  # rough enough to use the continuation
    for name in _OUT:
        change = np.abs(coarse[name].values / fine[name].values - 1)
        assert np.all(change <= coarse["body_grid_error"].values), name


def test_continuation_starts_where_the_area_reaches_its_threshold() -> None:
    """``start_at_area``: A/A0 = 1e-3 at the first node (a power law's own root), u and its
    slope there those of the Hermite cubic (a cubic in ln p is reproduced exactly)."""
    p = np.geomspace(1.0, 1e4, 9)
    area = 1e-4 * p**0.9
    s = np.log(p)
    u = 2e-6 - 3e-7 * s + 1e-9 * s**2 - 2e-10 * s**3
    du = -3e-7 + 2e-9 * s - 6e-10 * s**2
    p2, u2, du2, a2 = start_at_area(p, u, du, area, 1e-3)
    s0 = math.log(p2[0])
    assert a2[0] == 1e-3 and p2[0] == pytest.approx(10 ** (1 / 0.9), rel=1e-12)
    assert u2[0] == pytest.approx(2e-6 - 3e-7 * s0 + 1e-9 * s0**2 - 2e-10 * s0**3, rel=1e-12)
    assert du2[0] == pytest.approx(-3e-7 + 2e-9 * s0 - 6e-10 * s0**2, rel=1e-12)
    assert np.all(p2[1:] > p2[0]) and np.array_equal(u2[1:], u[p > p2[0]])
    sep = Separation(p2, u2, du2, a2)
    assert float(sep.area_fraction(p2[:1])[0]) == pytest.approx(1e-3, rel=1e-12)
    assert start_at_area(p, u, du, area, 1e-5)[0] is p  # already above: unchanged
