"""Measured topographies as spectra; file-based spectra archive their table (reproduce works
after the source file is deleted)."""

from __future__ import annotations

import json

import numpy as np
import pytest

import xpersson
from xpersson.cli import main
from xpersson.physics.psd import SelfAffineRollOff
from xpersson.scene import SceneError

Q_L, H, N = 1e3, 0.8, 512
Q_R, Q_1 = 4 * Q_L, 128 * Q_L
ANALYTIC = {
    "model": "self_affine",
    "H": H,
    "q_L": f"{Q_L} 1/m",
    "q_r": f"{Q_R} 1/m",
    "q_1": f"{Q_1} 1/m",
    "h_rms": "1 um",
}
SOLID = {
    "material": {"E": "10 MPa", "nu": 0.5},
    "load": {"p0": ["5 kPa", "15 kPa", "30 kPa"]},
    "output": {"zeta_per_decade": 10},
}


@pytest.fixture(scope="module")
def topography_file(tmp_path_factory):
    """A synthetic self-affine map with the analytic spectrum (constant Fourier amplitudes,
    random phases: its PSD is the prescribed one mode by mode)."""
    gen = pytest.importorskip("SurfaceTopography.Generation")
    psd = SelfAffineRollOff.from_h_rms(1e-6, H=H, q_L=Q_L, q_r=Q_R, q_1=Q_1)

    def c_jjp(q):
        q = np.asarray(q, float)
        return np.where(q <= Q_1, psd.C(np.clip(q, Q_L, Q_1)), 0.0) * (2 * np.pi) ** 2

    size = 2 * np.pi / Q_L
    topo = gen.fourier_synthesis(
        (N, N),
        (size, size),
        psd=c_jjp,
        unit="m",
        amplitude_distribution=lambda n: np.ones(n),
        rng=np.random.default_rng(7),
    )
    path = tmp_path_factory.mktemp("topo") / "map.nc"
    topo.to_netcdf(str(path))
    return path


def test_synthetic_topography_area_within_2_percent_of_analytic(topography_file):
    ana = xpersson.solve({"spectrum": ANALYTIC, **SOLID})
    meas = xpersson.solve(
        {
            "spectrum": {
                "model": "topography",
                "file": str(topography_file),
                "q_L": f"{Q_L} 1/m",
                "q_1": f"{Q_1} 1/m",
            },
            **SOLID,
        }
    )
    a_ana = ana.area_fraction.isel(zeta=-1).values
    a_meas = meas.area_fraction.isel(zeta=-1).values
    assert 0.05 < a_ana.min() and a_ana.max() < 0.9
    np.testing.assert_allclose(a_meas, a_ana, rtol=0.02)
    scene = json.loads(meas.attrs["xpersson_scene"])["spectrum"]
    from xpersson.builtin.topography import sha256_of

    assert scene["sha256"] == sha256_of(topography_file)
    assert len(scene["q"]) == meas.sizes["q_psd"]  # the PSD used is recorded


def test_topography_default_range_and_bad_range(topography_file):
    ds = xpersson.solve(
        {
            "spectrum": {"model": "topography", "file": str(topography_file), "q_1": f"{Q_1} 1/m"},
            **SOLID,
        }
    )
    # the table starts where the cells of the |k| = 2 pi / L modes begin: q_L / sqrt(pi)
    assert float(ds.q_psd[0]) == pytest.approx(Q_L / np.sqrt(np.pi), rel=1e-6)
    with pytest.raises(SceneError, match=r"spectrum.q_1: need q_L < q_1 <= "):
        xpersson.solve(
            {
                "spectrum": {"model": "topography", "file": str(topography_file), "q_1": "1e9 1/m"},
                **SOLID,
            }
        )


def test_tabulated_archive_reproduces_after_the_csv_is_deleted(tmp_path):
    psd = SelfAffineRollOff.from_h_rms(1e-6, H=H, q_L=Q_L, q_r=Q_R, q_1=1e6)
    q = np.geomspace(Q_L, 1e6, 40)
    csv = tmp_path / "psd.csv"
    np.savetxt(csv, np.column_stack([q, psd.C(q)]), delimiter=",", header="q,C")
    scene = tmp_path / "tab.toml"
    scene.write_text(
        '[spectrum]\nmodel = "tabulated"\nfile = "psd.csv"\n'
        '[material]\nE = "10 MPa"\nnu = 0.5\n[load]\np0 = ["0.1 MPa", "1 MPa"]\n'
    )
    assert main(["run", str(scene), "-o", str(tmp_path / "a.nc")]) == 0
    csv.unlink()
    assert main(["reproduce", str(tmp_path / "a.nc"), "-o", str(tmp_path / "b.nc")]) == 0
    a, b = (xpersson.open_dataset(tmp_path / f) for f in ("a.nc", "b.nc"))
    np.testing.assert_allclose(b.area_fraction, a.area_fraction, rtol=1e-12)
    np.testing.assert_array_equal(b.psd_C, a.psd_C)


def test_tabulated_archive_names_the_file_without_its_directory(tmp_path):
    """The archived scene keeps the spectrum file's name and checksum as provenance, not the
    machine's directory (a relative path in a scene file is resolved against the scene's
    folder, which would otherwise go into the archive)."""
    import json

    q = np.geomspace(Q_L, 1e6, 40)
    psd = SelfAffineRollOff.from_h_rms(1e-6, H=H, q_L=Q_L, q_r=Q_R, q_1=1e6)
    np.savetxt(tmp_path / "psd.csv", np.column_stack([q, psd.C(q)]), delimiter=",")
    scene = tmp_path / "tab.toml"
    scene.write_text(
        '[spectrum]\nmodel = "tabulated"\nfile = "psd.csv"\n'
        '[material]\nE = "10 MPa"\nnu = 0.5\n[load]\np0 = ["0.1 MPa", "1 MPa"]\n'
    )
    ds = xpersson.solve(scene)
    archived = json.loads(ds.attrs["xpersson_scene"])["spectrum"]
    assert archived["file"] == "psd.csv"
    assert len(archived["sha256"]) == 64
    assert not [k for k, v in ds.attrs.items() if str(tmp_path) in str(v)]
