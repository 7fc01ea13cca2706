"""The rough sphere's BEM (xpersson.bem.sphere) and `xpersson crosscheck` of a sphere scene."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from xpersson.bem import CrosscheckError, crosscheck, sphere
from xpersson.cli import main
from xpersson.physics.body import hertz_sphere

tamaas = pytest.importorskip("tamaas")

R, E_STAR, FORCE = 0.05, 1e6, 9e-5  # Hertz radius 150 um


@pytest.mark.parametrize("cell", [6.0, 10.0])
def test_smooth_sphere_is_hertz(cell: float) -> None:
    """A smooth map: the approach referred to an isolated half-space is Hertz's whatever the
    periodic cell (the images' displacement removed), the radius holding 99 % of the force is
    Hertz's ``a sqrt(1 - 0.01^(2/3))``, the contact area ``pi a^2``."""
    a, delta, peak = hertz_sphere(FORCE, R, E_STAR)
    n = 128
    edges = np.linspace(0.0, cell * a / 2, 33)
    (st,) = sphere.solve_sphere(np.zeros((n, n)), cell * a, R, E_STAR, [FORCE], edges)
    assert st.converged
    assert st.approach == pytest.approx(delta, rel=0.01)
    assert st.radius == pytest.approx(a * math.sqrt(1 - 0.01 ** (2 / 3)), rel=0.015)
    assert st.real_area == pytest.approx(math.pi * a * a, rel=0.02)
    assert np.nanmax(st.profile) == pytest.approx(peak, rel=0.03)
    r = 0.5 * (edges[1:] + edges[:-1])
    assert np.all(st.profile[r > 1.1 * a] == 0.0)


def _scene(model: str = "sphere", h_rms: str = "5 nm") -> dict:
    q_L = 5.0 / 150e-6  # the Hertz radius holds 5 / (2 pi) roll-off wavelengths
    geo = {"model": model, "radius": f"{R} m"} | ({"length": "1 m"} if model != "sphere" else {})
    return {
        "geometry": geo,
        "load": {"force": [f"{FORCE / 2} N", f"{FORCE} N"] if model == "sphere" else "1 N"},
        "spectrum": {"model": "self_affine", "H": 0.8, "q_L": f"{q_L} 1/m",
                     "q_r": f"{q_L} 1/m", "q_1": f"{4 * q_L} 1/m", "h_rms": h_rms},
        "material": {"E": f"{0.75 * E_STAR} Pa", "nu": 0.5},
    }  # fmt: skip


def test_crosscheck_of_a_nearly_smooth_sphere() -> None:
    """Johnson's alpha 0.01-0.02: theory and BEM agree on the nominal radius and approach (both
    near Hertz); the Dataset carries the ratios, the ring-averaged p(r) and its L1 distance."""
    ds = crosscheck(_scene(), realisations=1, grid=96)
    assert ds.attrs["crosscheck_kind"] == "sphere"
    assert ds.sizes["force"] == 2 and ds.sizes["ring"] == sphere.RINGS
    for name in ("nominal_contact_radius", "approach"):
        ratio = ds[f"{name}_ratio"].values
        assert np.all(np.abs(ratio - 1) < 0.05), (name, ratio)
        np.testing.assert_allclose(ratio, ds[f"{name}_theory"].values / ds[name].values)
    assert ds["real_contact_area"].attrs["units"] == "m^2"
    assert np.all(ds["nominal_pressure_l1"].values < 0.15)
    assert ds.attrs["cell_side_m"] == pytest.approx(
        sphere.CELL_FACTOR * float(ds["nominal_contact_radius_theory"].max()), rel=0.05
    )


def test_crosscheck_refuses_a_cylinder_in_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture
) -> None:
    with pytest.raises(CrosscheckError, match="sphere only"):
        crosscheck(_scene("cylinder"), realisations=1, grid=128)
    path = tmp_path / "roller.toml"
    path.write_text(CYLINDER)
    assert main(["crosscheck", str(path), "--grid", "128"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "sphere only" in err[0]


CYLINDER = """
[geometry]
model = "cylinder"
radius = "50 mm"
length = "1 m"
[load]
force = "1 N"
[spectrum]
model = "self_affine"
H = 0.8
q_L = "3e4 1/m"
q_r = "3e4 1/m"
q_1 = "1.2e5 1/m"
h_rms = "20 nm"
[material]
E = "0.75 MPa"
nu = 0.5
"""


def test_crosscheck_refuses_a_grid_too_coarse_for_the_band() -> None:
    """The cell holds the nominal contact; a grid that cannot resolve 1.5 q_L there is
    refused with the grid that would."""
    scene = _scene()
    scene["spectrum"] |= {"q_L": "3e5 1/m", "q_r": "3e5 1/m", "q_1": "1.2e6 1/m"}
    with pytest.raises(CrosscheckError, match=r"use --grid \d+ or more"):
        crosscheck(scene, realisations=1, grid=64)
