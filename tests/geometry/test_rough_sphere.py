"""Greenwood & Tripp's trends for a rough sphere, and the kernel against closed forms."""

from __future__ import annotations

import math

import numpy as np
import pytest

import xpersson
from xpersson.physics.body import cell_areas, hertz_cylinder, hertz_sphere, kernel

from .conftest import body_scene


def test_roughness_widens_the_contact_and_lowers_the_peak() -> None:
    """Greenwood & Tripp (1967): at one force, a rougher flat spreads the nominal pressure."""
    rows = []
    for h in ("1 nm", "100 nm", "300 nm", "1 um"):
        ds = xpersson.solve(body_scene(force="1 mN", h_rms=h))
        rows.append(
            [float(ds[v]) for v in ("johnson_parameter", "nominal_contact_radius",
                                     "peak_pressure", "real_contact_area", "approach")]
        )  # fmt: skip
    alpha, radius, peak, area, approach = np.array(rows).T
    assert alpha[0] < 1e-3 and alpha[-1] > 0.3
    assert np.all(np.diff(radius) > 0) and np.all(np.diff(peak) < 0)
    assert np.all(np.diff(approach) < 0)  # the asperities hold the mean planes apart
    assert np.all(np.diff(area) < 0)  # less of the nominal contact is real contact
    assert radius[-1] > 1.2 * radius[0] and peak[-1] < 0.8 * peak[0]


def test_nominal_pressure_carries_the_force() -> None:
    ds = xpersson.solve(body_scene(force=["1 mN", "10 mN"], h_rms="300 nm"))
    r = ds["r"].values
    for k, f in enumerate(ds["force"].values):
        p = ds["nominal_pressure"].isel(force=k).values
        carried = np.trapezoid(2 * np.pi * r * p, r)
        assert carried == pytest.approx(f, rel=0.02)
    assert ds["nominal_pressure"].attrs["units"] == "Pa"
    assert ds["r"].attrs["units"] == "m"


@pytest.mark.parametrize("n", [64, 128])
def test_ring_kernel_gives_the_hertz_displacement(n: int) -> None:
    """Hertz's pressure on rings: w = delta - r^2/(2R) inside the contact (Johnson eq. 4.19)."""
    R, E_star, force = 0.01, 1e9, 1.0
    a, delta, peak = hertz_sphere(force, R, E_star)
    h = 2.0 * a / n
    r = (np.arange(n) + 0.5) * h
    p = peak * np.sqrt(np.clip(1 - (r / a) ** 2, 0, None))
    w = (h / E_star) * kernel("axisymmetric", n) @ p
    inside = r < 0.8 * a
    np.testing.assert_allclose(w[inside], delta - r[inside] ** 2 / (2 * R), rtol=2e-3 * 64 / n)
    far = (h / E_star) * kernel("axisymmetric", n)[-1] @ np.ones(n)  # a uniform disk, outside
    assert far > 0
    assert np.dot(cell_areas("axisymmetric", n, h), np.ones(n)) == pytest.approx(
        math.pi * (n * h) ** 2
    )


def test_strip_kernel_gives_the_hertz_line_displacement() -> None:
    R, E_star, load, n = 0.01, 1e9, 1e3, 128
    b, delta, peak = hertz_cylinder(load, R, E_star)
    h = 2.0 * b / n
    x = (np.arange(n) + 0.5) * h
    p = peak * np.sqrt(np.clip(1 - (x / b) ** 2, 0, None))
    K = kernel("plane", n) - (4.0 / math.pi) * math.log(h / R)
    w = (h / E_star) * K @ p
    inside = x < 0.8 * b
    np.testing.assert_allclose(w[inside], delta - x[inside] ** 2 / (2 * R), rtol=3e-3)
