"""Maps with a short-wavelength cutoff (issue 22) and SurfaceTopography objects in Python
scenes (issue 26): zero-PSD bands are handled, and what validate accepts also runs."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import xpersson
from xpersson.cli import main
from xpersson.scene import SceneError

L, H = 1e-3, 0.8  # map size [m], Hurst exponent
Q_L = 2 * math.pi / L
SOLID = {"material": {"E": "10 MPa", "nu": 0.5}, "load": {"p0": ["10 kPa", "100 kPa"]}}


@pytest.fixture(scope="module")
def cut_map():
    """``fourier_synthesis`` with a short cutoff at L/64: the map's PSD is FFT round-off
    (~1e-30 of the peak) above q_s = 64 q_L. Unit amplitudes, random phases: mode by mode the
    prescribed spectrum (flat below q_r = 4 q_L, H = 0.8 above, h_rms = 1 um)."""
    gen = pytest.importorskip("SurfaceTopography.Generation")
    return gen.fourier_synthesis(
        (512, 512), (L, L), H, rms_height=1e-6, short_cutoff=L / 64, long_cutoff=L / 4,
        unit="m", amplitude_distribution=lambda n: np.ones(n), rng=np.random.default_rng(1),
    )  # fmt: skip


def _analytic(zeta_max: float) -> object:
    spectrum = {"model": "self_affine", "H": H, "q_L": f"{Q_L} 1/m", "q_r": f"{4 * Q_L} 1/m",
                "q_1": f"{64 * Q_L} 1/m", "h_rms": "1 um"}  # fmt: skip
    return xpersson.solve({"spectrum": spectrum, **SOLID, "output": {"zeta_max": zeta_max}})


def test_cutoff_map_file_runs_with_the_default_range(cut_map, tmp_path):
    """`validate` and `run` agree; the default q_1 ends where the roughness ends."""
    cut_map.to_netcdf(str(tmp_path / "cut.nc"))
    (tmp_path / "cut.toml").write_text(
        '[spectrum]\nmodel = "topography"\nfile = "cut.nc"\n[material]\nE = "10 MPa"\n'
        'nu = 0.5\n[load]\np0 = ["10 kPa", "100 kPa"]\n'
    )
    assert main(["validate", str(tmp_path / "cut.toml")]) == 0
    assert main(["run", str(tmp_path / "cut.toml"), "-o", str(tmp_path / "cut_out.nc")]) == 0
    ds = xpersson.open_dataset(tmp_path / "cut_out.nc")
    q_end = float(ds.q[-1])
    assert 0.98 * 64 * Q_L < q_end <= 64 * Q_L  # the roughness ends at q_s = 64 q_L
    a, b = ds.area_fraction.isel(zeta=-1).values, _analytic(64.0).area_fraction.isel(zeta=-1)
    np.testing.assert_allclose(a, b.values, rtol=0.02)


def test_topography_object_in_a_python_scene(cut_map):
    """A Topography object is accepted; the archive records the table and the map's identity."""
    ds = xpersson.solve({"spectrum": cut_map, **SOLID})
    np.testing.assert_allclose(
        ds.area_fraction.isel(zeta=-1).values,
        _analytic(64.0).area_fraction.isel(zeta=-1).values,
        rtol=0.02,
    )
    rec = json.loads(ds.attrs["xpersson_scene"])["spectrum"]
    assert rec["model"] == "topography" and "nb_grid_pts (512, 512)" in rec["source"]
    heights = np.ascontiguousarray(cut_map.heights(), dtype=float)
    import hashlib

    assert rec["sha256"] == hashlib.sha256(heights.tobytes()).hexdigest()
    again = xpersson.solve({"spectrum": rec, **SOLID})  # the record alone re-solves
    np.testing.assert_array_equal(again.area_fraction.values, ds.area_fraction.values)


def test_psd_computed_by_surface_topography(cut_map):
    """(q, C) from power_spectrum_from_area, in its convention and the map's units, solves;
    it loses part of the map's roughness (the |k| = 1 ring at q_L, the band above its last
    bin centre), which the map's own table keeps (issue 35)."""
    q, C = cut_map.power_spectrum_from_area(nb_points_per_decade=20)
    q, C = q[C > 1e-40], C[C > 1e-40]
    spectrum = {"model": "tabulated", "convention": "surface_topography",
                "q": [f"{x} 1/m" for x in q], "C": [f"{x} m**4" for x in C]}  # fmt: skip
    ds = xpersson.solve({"spectrum": spectrum, **SOLID})
    obj = xpersson.solve({"spectrum": cut_map, **SOLID})
    assert float(ds.h_rms) < 0.995e-6  # the binned table: 0.988 um of 1 um
    assert float(obj.h_rms) == pytest.approx(1e-6, rel=1e-9)
    rec = json.loads(ds.attrs["xpersson_scene"])["spectrum"]
    assert rec["convention"] == "persson"  # the archived table is converted once


def test_validate_refuses_a_band_without_power():
    """A table whose PSD is round-off above a cutoff: refused at resolution, naming the band."""
    q = np.geomspace(1e3, 1e6, 31)
    C = np.where(q <= 1e5, 1e-20 * (q / 1e3) ** -3.6, 1e-80)
    spectrum = {"model": "tabulated", "q": [f"{x} 1/m" for x in q],
                "C": [f"{x} m**4" for x in C]}  # fmt: skip
    with pytest.raises(SceneError, match=r"spectrum: the PSD carries no power .* spectrum.q_1 <="):
        xpersson.Scene({"spectrum": spectrum, **SOLID}).resolve()
