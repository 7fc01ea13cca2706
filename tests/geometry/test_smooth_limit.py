"""The smooth limit: a rough sphere with a tiny roughness is Hertz's sphere (Johnson 1985)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import xpersson

from .conftest import body_scene

#: Hertz: the radius holding 99 % of the force, per contact radius a: 1 - (1 - t^2)^(3/2) = 0.99
SPHERE_99 = math.sqrt(1.0 - 0.01 ** (2.0 / 3.0))


def _line_99() -> float:
    """Hertz line contact: (2/pi)(asin t + t sqrt(1 - t^2)) = 0.99, by bisection."""
    lo, hi = 0.0, 1.0
    for _ in range(80):
        t = 0.5 * (lo + hi)
        frac = 2.0 / math.pi * (math.asin(t) + t * math.sqrt(1.0 - t * t))
        lo, hi = (t, hi) if frac < 0.99 else (lo, t)
    return lo


def test_sphere_is_hertz_over_three_decades_of_force() -> None:
    forces = ["1 mN", "10 mN", "100 mN", "1 N"]
    ds = xpersson.solve(body_scene(force=forces, h_rms="1 nm"))
    E_star = 1e6 / (1 - 0.25)
    F = ds["force"].values
    a = (3 * F * 0.01 / (4 * E_star)) ** (1 / 3)
    assert F[-1] / F[0] == pytest.approx(1e3)
    assert float(ds["johnson_parameter"].max()) < 1e-3
    np.testing.assert_allclose(ds["hertz_radius"], a, rtol=1e-12)
    np.testing.assert_allclose(ds["nominal_contact_radius"], SPHERE_99 * a, rtol=0.01)
    np.testing.assert_allclose(ds["approach"], a * a / 0.01, rtol=0.01)
    np.testing.assert_allclose(ds["peak_pressure"], 3 * F / (2 * np.pi * a * a), rtol=0.01)
    np.testing.assert_allclose(ds["normal_stiffness"], 2 * E_star * a, rtol=0.01)
    # a smooth contact is full: the real area is the Hertz disk, to the grid's resolution of
    # the edge (a cell is 1.25 % of the radius; the error estimate says so)
    np.testing.assert_allclose(ds["real_contact_area"], np.pi * a * a, rtol=0.03)
    assert 1e-5 < float(ds["body_grid_error"].max()) < 0.03
    assert float(ds["body_residual"].max()) < 1e-9


def test_cylinder_is_hertz_line_contact() -> None:
    ds = xpersson.solve(body_scene("cylinder", force=["10 mN", "1 N"], h_rms="0.01 nm"))
    E_star = 1e6 / (1 - 0.25)
    P = ds["force"].values / 0.02  # force per length
    b = np.sqrt(4 * P * 0.01 / (np.pi * E_star))
    np.testing.assert_allclose(ds["nominal_contact_radius"], _line_99() * b, rtol=0.01)
    delta = P / (np.pi * E_star) * (2 * np.log(2 * 0.01 / b) + 1)
    np.testing.assert_allclose(ds["approach"], delta, rtol=0.01)
    np.testing.assert_allclose(ds["peak_pressure"], 2 * P / (np.pi * b), rtol=0.01)
    assert ds["real_contact_area"].attrs["units"] == "m^2"
    np.testing.assert_allclose(ds["real_contact_area"], 2 * b * 0.02, rtol=0.02)
