"""Measured surfaces as users have them (issue 35): the table keeps the map's own roughness,
every format with what it lacks given in the scene, line scans, several scans of one surface,
and bad input refused in one line before any work."""

from __future__ import annotations

import json
import math
import warnings

import numpy as np
import pytest

import xpersson
from xpersson.cli import main
from xpersson.errors import XperssonWarning
from xpersson.physics import psd as P
from xpersson.physics.elastic import area_fraction
from xpersson.scene import SceneError
from xpersson.testing.surfaces import rolled_off, synthetic_map

ST = pytest.importorskip("SurfaceTopography")

L = 1e-3  # map size [m]
Q = 2 * math.pi / L  # its smallest wavevector [1/m]
E_STAR = 10e6 / (1 - 0.25)  # E = 10 MPa, nu = 0.5 [Pa]
MATERIAL = {"E": "10 MPa", "nu": 0.5}


def _spectral_slope(h: np.ndarray, size: float) -> float:
    """A periodic map's rms 2-D gradient by the spectral derivative (independent code)."""
    k = 2 * np.pi * np.fft.fftfreq(h.shape[0], size / h.shape[0])
    gx = np.real(np.fft.ifft2(1j * k[:, None] * np.fft.fft2(h)))
    gy = np.real(np.fft.ifft2(1j * k[None, :] * np.fft.fft2(h)))
    return float(np.sqrt(np.mean(gx**2 + gy**2)))


def _loads(slope: float) -> dict:
    """Three loads with A/A0 from ~0.05 to ~0.3 at this rms slope."""
    return {"p0": [f"{f * E_STAR * slope!r} Pa" for f in (0.04, 0.12, 0.25)]}


def _closed_form(ds: xpersson.Dataset, slope: float) -> np.ndarray:
    """A/A0 = erf(p0 / (2 sqrt(tau))), tau = E*^2 <|grad h|^2> / 8 at full magnification."""
    return np.asarray(area_fraction(ds.p0.values, E_STAR**2 * slope**2 / 8.0)[0])


MAPS = {  # name: (H, roll-off q_r / Q, band limit q_s / Q or None)
    "H0.8-rolloff-bandlimited": (0.8, 4, 16),
    "H0.8-no-rolloff": (0.8, 1, None),
    "H0.5-rolloff": (0.5, 4, None),
    "H0.5-no-rolloff-bandlimited": (0.5, 1, 32),
}


def _solve_quietly(scene: dict) -> xpersson.Dataset:
    with warnings.catch_warnings():
        warnings.simplefilter("error", XperssonWarning)  # no roughness-mismatch warning
        return xpersson.solve(scene)


@pytest.mark.parametrize("name", sorted(MAPS))
def test_map_keeps_its_roughness_and_area(name):
    """256^2 periodic maps: the Dataset's h_rms and rms slope are the map's (1e-9, target
    1 %), recorded as map_h_rms / map_rms_slope, nothing dropped; A/A0 at three loads is the
    closed form at the map's own slope within 1 %."""
    H, q_r, q_s = MAPS[name]
    h = synthetic_map(256, L, rolled_off(H, Q, q_r * Q, q_s and q_s * Q), 1e-6, seed=3)
    topo = ST.Topography(h, (L, L), periodic=True, unit="m")
    slope = _spectral_slope(h, L)
    ds = _solve_quietly({"spectrum": topo, "material": MATERIAL, "load": _loads(slope)})
    # the ring estimator's gradient keeps the Nyquist modes (|k|^2 v_k) that numpy's spectral
    # derivative drops: 0.16 % of the mean-square slope at H = 0.5 without a band limit
    assert float(ds.h_rms) == pytest.approx(h.std(), rel=1e-9)
    assert float(ds.rms_slope) == pytest.approx(slope, rel=2e-3)
    assert float(ds.map_h_rms) == pytest.approx(h.std(), rel=1e-12)
    assert float(ds.map_rms_slope) == pytest.approx(float(ds.rms_slope), rel=1e-9)
    assert abs(float(ds.psd_dropped_height)) < 1e-9 and abs(float(ds.psd_dropped_slope)) < 1e-9
    assert ds.map_h_rms.attrs["units"] == "m"
    a = ds.area_fraction.isel(zeta=-1).values
    np.testing.assert_allclose(a, _closed_form(ds, slope), rtol=0.01)
    # SurfaceTopography's own: the same rms height; its finite-difference gradient is below
    # the spectral one (by 0.5 % with a band limit at 1/8 of the Nyquist wavevector, by 11 %
    # at H = 0.8 with roughness up to it)
    assert topo.rms_height_from_area() == pytest.approx(float(ds.map_h_rms), rel=1e-9)
    assert 0.85 < topo.rms_gradient() / float(ds.map_rms_slope) <= 1.0


def test_512_maps_keep_their_roughness():
    """The 512^2 maps of the issue's table (H = 0.8 band-limited, cutoff 8 px; H = 0.5 to the
    Nyquist wavevector): the table's moments equal the map's; the psd is unbiased ring by ring
    (within 3 % in the band where rings hold > 20 modes; a smooth roll-off: a sharp kink is
    smeared over a ring either side, up to 8 % there)."""
    for H, q_s in ((0.8, 32), (0.5, None)):
        shape = rolled_off(H, Q, 4 * Q, q_s and q_s * Q, sharp=False)
        h = synthetic_map(512, L, shape, seed=5)  # absolute: the mode variances are C dq^2
        rings = P.map_rings(h, (L, L), 20)
        q, C = P.table_from_rings(rings)
        table = P.Tabulated(q, C)
        assert table.h_rms() == pytest.approx(h.std(), rel=1e-9)
        assert table.rms_slope() == pytest.approx(_spectral_slope(h, L), rel=2e-3)
        inner = np.concatenate(([False], rings.modes > 20, [False]))
        inner &= q < (q_s or 200) * Q * 0.8
        np.testing.assert_allclose(C[inner], shape(q[inner]), rtol=0.03)


def test_line_scan_keeps_its_roughness_and_area():
    """A periodic line scan: h_rms is the scan's, the rms 2-D gradient sqrt(2) times its
    profile slope (isotropy), A/A0 the closed form at that slope, within 1 %."""
    h2d = synthetic_map(512, L, rolled_off(0.8, Q, 4 * Q, 64 * Q), 1e-6, seed=11)
    line = h2d[0]
    k = 2 * np.pi * np.fft.fftfreq(line.size, L / line.size)
    profile_slope = float(np.sqrt(np.mean(np.real(np.fft.ifft(1j * k * np.fft.fft(line))) ** 2)))
    scan = ST.UniformLineScan(line, L, periodic=True, unit="m")
    slope = math.sqrt(2.0) * profile_slope
    ds = _solve_quietly({"spectrum": scan, "material": MATERIAL, "load": _loads(slope)})
    assert float(ds.h_rms) == pytest.approx(line.std(), rel=0.01)
    assert float(ds.rms_slope) == pytest.approx(slope, rel=0.01)
    np.testing.assert_allclose(ds.area_fraction.isel(zeta=-1).values, _closed_form(ds, slope),
                               rtol=0.01)  # fmt: skip


@pytest.mark.parametrize("q_r", [1, 4])
def test_line_scans_give_the_known_2d_spectrum(q_r):
    """The 2-D spectrum from 1-D ones (the annulus-strip inversion) on a map whose 2-D
    spectrum is known: 256 parallel scans (the rows), within 20 % over the band from 3 q_L to
    a third of the scans' Nyquist wavevector (measured: 16 %)."""
    shape = rolled_off(0.8, Q, q_r * Q, None, sharp=False)
    h = synthetic_map(256, L, shape, seed=2)
    rings = P.profile_rings(h, L, 10)
    q, C = P.table_from_rings(rings, low_end=True)
    band = (q > 3 * Q) & (q < 128 * Q / 3)
    ratio = C[band] / shape(q[band])
    assert np.all(np.abs(ratio - 1) < 0.2), np.round(ratio, 3)


def test_two_scan_sizes_combine_to_the_known_spectrum(tmp_path):
    """A 1 mm and a 125 um scan of one surface (the same continuous spectrum), 256^2 each:
    the combined table is within 5 % of the known spectrum over both bands; each part's
    provenance (file, SHA-256, grid, size, band) is in the archive."""
    shape = rolled_off(0.8, Q, 4 * Q, 2000 * Q, sharp=False)
    for name, size, seed in (("coarse.nc", L, 1), ("fine.nc", L / 8, 2)):
        ST.Topography(synthetic_map(256, size, shape, seed=seed), (size, size), periodic=True,
                      unit="m").to_netcdf(str(tmp_path / name))  # fmt: skip
    (tmp_path / "two.toml").write_text(
        '[spectrum]\nmodel = "topography"\nfile = "coarse.nc"\nfile_2 = "fine.nc"\n'
        '[material]\nE = "10 MPa"\nnu = 0.5\n[load]\np0 = "0.1 MPa"\n'
    )
    assert main(["run", str(tmp_path / "two.toml"), "-o", str(tmp_path / "two.nc")]) == 0
    ds = xpersson.open_dataset(tmp_path / "two.nc")
    q, C = ds.q_psd.values, ds.psd_C.values
    band = (q > 1.5 * Q) & (q < 0.6 * 8 * 128 * Q)
    assert q[band][0] < 2 * Q and q[band][-1] > 500 * Q  # both bands: 2.5 decades
    np.testing.assert_allclose(C[band], shape(q[band]), rtol=0.05)
    parts = json.loads(json.loads(ds.attrs["xpersson_scene"])["spectrum"]["parts"])
    assert [p["file"].rsplit("/", 1)[-1] for p in parts] == ["coarse.nc", "fine.nc"]
    from xpersson.builtin.topography import sha256_of

    assert parts[1]["sha256"] == sha256_of(tmp_path / "fine.nc")
    assert parts[1]["nb_grid_pts"] == [256, 256]
    assert parts[1]["physical_sizes_m"][0] == pytest.approx(L / 8, rel=1e-6)


def _matrix(tmp_path, name="map.txt", n=64, nan=False):
    h = synthetic_map(n, L, rolled_off(0.8, Q, 2 * Q, None), 1e-6, seed=4) * 1e6  # in um
    if nan:
        h[3, 5] = np.nan
    np.savetxt(tmp_path / name, h)
    return tmp_path / name, h


def _toml(tmp_path, spectrum: str, name="scene.toml"):
    (tmp_path / name).write_text(
        f'[spectrum]\nmodel = "topography"\n{spectrum}\n[material]\nE = "10 MPa"\n'
        'nu = 0.5\n[load]\np0 = "0.1 MPa"\n'
    )
    return tmp_path / name


def test_text_matrix_with_its_size_in_the_scene(tmp_path):
    """A plain-matrix text map (no metadata): the scene gives physical_sizes, unit and
    periodic; the Dataset's h_rms is the matrix's."""
    path, h = _matrix(tmp_path)
    scene = _toml(tmp_path, f'file = "{path.name}"\nphysical_sizes = ["1 mm", "1 mm"]\n'
                            'unit = "um"\nperiodic = true')  # fmt: skip
    assert main(["run", str(scene), "-o", str(tmp_path / "out.nc")]) == 0
    ds = xpersson.open_dataset(tmp_path / "out.nc")
    assert float(ds.h_rms) == pytest.approx(h.std() * 1e-6, rel=1e-6)
    assert float(ds.map_h_rms) == pytest.approx(h.std() * 1e-6, rel=1e-6)
    assert float(ds.q_psd[0]) == pytest.approx(Q / math.sqrt(math.pi), rel=1e-6)


def test_height_scale_detrend_and_line_scan_file(tmp_path):
    """height_scale multiplies the heights; a single-column text file is a line scan given
    its length; detrend 'height' (tilt removed) on a non-periodic map."""
    path, h = _matrix(tmp_path)
    common = f'file = "{path.name}"\nphysical_sizes = ["1 mm", "1 mm"]\nunit = "um"\n'
    one = xpersson.solve(_toml(tmp_path, common + "periodic = true"))
    two = xpersson.solve(_toml(tmp_path, common + "periodic = true\nheight_scale = 2"))
    assert float(two.h_rms) == pytest.approx(2 * float(one.h_rms), rel=1e-9)
    tilted = xpersson.solve(_toml(tmp_path, common + 'detrend = "height"'))
    assert float(tilted.map_h_rms) <= float(one.map_h_rms)
    np.savetxt(tmp_path / "line.txt", h[0])
    line = xpersson.solve(_toml(tmp_path, 'file = "line.txt"\nphysical_sizes = ["1 mm"]\n'
                                          'unit = "um"\nperiodic = true'))  # fmt: skip
    assert float(line.h_rms) == pytest.approx(h[0].std() * 1e-6, rel=0.01)


def test_netcdf_unit_the_file_wins(tmp_path):
    """A netCDF map states its unit: the same unit in the scene is accepted (in any
    spelling), a different one is one clear error naming the file and both values."""
    h = synthetic_map(64, L, rolled_off(0.8, Q, 2 * Q, None), 1e-6, seed=1)
    ST.Topography(h * 1e6, (1e3, 1e3), periodic=True, unit="um").to_netcdf(str(tmp_path / "m.nc"))
    same = xpersson.solve(_toml(tmp_path, 'file = "m.nc"\nunit = "micrometer"'))
    assert float(same.h_rms) == pytest.approx(1e-6, rel=1e-5)  # float32 in the file
    with pytest.raises(SceneError, match=r"spectrum.unit: the file '.*m.nc' states 'µm'; the "
                                         r"scene gives 'nm'\. What the file"):  # fmt: skip
        xpersson.solve(_toml(tmp_path, 'file = "m.nc"\nunit = "nm"'))
    with pytest.raises(SceneError, match=r"spectrum.physical_sizes: the file '.*m.nc' states "
                                         r"\(0.001, 0.001\)"):  # fmt: skip
        xpersson.solve(_toml(tmp_path, 'file = "m.nc"\nphysical_sizes = ["2 mm", "2 mm"]'))
    corrupt = tmp_path / "bad.nc"
    corrupt.write_bytes(b"CDF\x01 not really")
    with pytest.raises(SceneError, match=r"spectrum.file: cannot read '.*bad.nc'"):
        xpersson.solve(_toml(tmp_path, 'file = "bad.nc"'))


def test_object_without_unit_takes_the_scenes(tmp_path):
    """A Topography object without a unit solves when the scene gives spectrum.unit; without
    it, the error names the key."""
    h = synthetic_map(64, L, rolled_off(0.8, Q, 2 * Q, None), 1e-6, seed=1)
    topo = ST.Topography(h * 1e6, (1e3, 1e3), periodic=True)  # um, no unit
    ds = xpersson.solve({"spectrum": {"topography": topo, "unit": "um"}, "material": MATERIAL,
                         "load": {"p0": "0.1 MPa"}})  # fmt: skip
    assert float(ds.h_rms) == pytest.approx(1e-6, rel=1e-9)
    with pytest.raises(SceneError, match=r"spectrum.topography: unit: .* has no unit; give "
                                         r"spectrum.unit"):  # fmt: skip
        xpersson.solve({"spectrum": {"topography": topo}, "material": MATERIAL,
                        "load": {"p0": "0.1 MPa"}})  # fmt: skip


def test_tip_radius_and_q_1_drop_roughness_with_a_warning():
    """A tip radius (SurfaceTopography's reliability cutoff) ends the table at its limit; the
    roughness dropped is recorded and warned about per spectrum."""
    h = synthetic_map(128, L, rolled_off(0.8, Q, 2 * Q, None), 1e-6, seed=1)
    topo = ST.Topography(h, (L, L), periodic=True, unit="m")
    tip = topo.scanning_probe_reliability_cutoff(50e-6)  # a 50 um radius tip: lambda_c [m]
    with pytest.warns(XperssonWarning, match=r"the table keeps .*rms slope .* tip_radius"):
        ds = xpersson.solve({"spectrum": {"topography": topo, "tip_radius": "50 um"},
                             "material": MATERIAL, "load": {"p0": "0.1 MPa"}})  # fmt: skip
    assert float(ds.q_psd[-1]) == pytest.approx(2 * math.pi / tip, rel=1e-9)
    dropped = float(ds.psd_dropped_slope)
    assert dropped == pytest.approx(1 - (float(ds.rms_slope) / float(ds.map_rms_slope)) ** 2)
    assert 0.05 < dropped < 1


@pytest.mark.parametrize(
    ("spectrum", "message"),
    [
        ('file = "map.txt"', r"spectrum.physical_sizes: the file '.*map.txt' does not state its "
                             r"physical size; give spectrum.physical_sizes"),
        ('file = "nan.txt"\nphysical_sizes = ["1 mm", "1 mm"]\nunit = "um"',
         r"spectrum.file: the file '.*nan.txt' has 1 undefined \(NaN or infinite\) heights"),
        ('file = "xy.txt"\nunit = "um"',
         r"spectrum.file: the file '.*xy.txt' is a non-uniform line scan"),
        ('file = "map.txt"\nphysical_sizes = ["1 mm", "1 mm"]\nunit = "um"\nq_L = "1 1/m"',
         r"spectrum.q_L: 1 1/m asks for wavelengths up to 6.283 m, longer than the scan "
         r"'.*map.txt'"),
    ],
)  # fmt: skip
def test_bad_input_is_one_line_naming_the_file_and_nothing_is_written(tmp_path, spectrum,
                                                                      message):  # fmt: skip
    _matrix(tmp_path)
    _matrix(tmp_path, "nan.txt", nan=True)
    x = np.sort(np.random.default_rng(0).random(50)) * 1e3
    np.savetxt(tmp_path / "xy.txt", np.column_stack([x, np.sin(x)]))
    scene = _toml(tmp_path, spectrum)
    with pytest.raises(SceneError, match=message) as err:
        xpersson.solve(scene)
    assert "\n" not in str(err.value)
    assert main(["run", str(scene), "-o", str(tmp_path / "out.nc")]) != 0
    assert not (tmp_path / "out.nc").exists()


EXAMPLES = __import__("pathlib").Path(__file__).resolve().parents[1] / "examples" / "measured"


@pytest.mark.parametrize(
    ("scene", "heights", "factor"),
    [("text_matrix", "map.txt", 1e-9), ("line_scan", "line.txt", 1e-6), ("netcdf", None, 1e-6)],
)
def test_the_documented_examples_keep_their_files_roughness(scene, heights, factor):
    """examples/measured: each scene solves, h_rms is its file's (read here with numpy or
    SurfaceTopography; the text matrix's mean plane removed here by least squares)."""
    ds = _solve_quietly(str(EXAMPLES / f"{scene}.toml"))
    if heights is None:
        raw = ST.read_topography(str(EXAMPLES / "map.nc")).heights() * factor
    else:
        raw = np.loadtxt(EXAMPLES / heights) * factor
    assert float(ds.h_rms) == pytest.approx(float(ds.map_h_rms), rel=1e-9)
    if scene == "text_matrix":  # detrend = "height": the least-squares plane removed
        i, j = np.indices(raw.shape)
        basis = np.column_stack([np.ones(raw.size), i.ravel(), j.ravel()])
        raw = raw.ravel() - basis @ np.linalg.lstsq(basis, raw.ravel(), rcond=None)[0]
    assert float(ds.map_h_rms) == pytest.approx(raw.std(), rel=1e-6)
