"""Cross-checks on measured maps and tabulated spectra, and the grid check."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import xpersson
from xpersson.bem import CrosscheckError, map_moments, synthesise
from xpersson.bem._plan import make_plan
from xpersson.bem._realise import Task, _surface
from xpersson.bem._surfaces import band_limited, mirrored
from xpersson.cli import main
from xpersson.physics.psd import Tabulated
from xpersson.pipeline import as_scene
from xpersson.scene import Scene

EXAMPLES = Path(__file__).parents[2] / "examples" / "measured"
SIDE = 20e-6  # [m]
N = 32
Q_CELL = 2 * math.pi / SIDE
LOADS = ["50 kPa"]


def _psd(q: np.ndarray) -> np.ndarray:
    return 1e-30 * np.where(q < 2 * Q_CELL, 1.0, (q / (2 * Q_CELL)) ** -3.6)


def _raw_map() -> np.ndarray:
    """A periodic 32^2 map [m], band-limited to 4 q_cell (the band a 32^2 grid keeps)."""
    h = synthesise(_psd, SIDE, N, seed=5, q_max=4 * Q_CELL)[0]
    return h * (0.1e-6 / h.std())


def _map_scene(tmp_path: Path, heights: np.ndarray, sizes: list[str]) -> Path:
    np.savetxt(tmp_path / "map.txt", heights * 1e6, fmt="%.17g")
    scene = tmp_path / "map.toml"
    scene.write_text(
        '[spectrum]\nmodel = "topography"\nfile = "map.txt"\n'
        f"physical_sizes = {sizes!r}\n"
        'unit = "um"\nperiodic = true\n[material]\nE = "10 MPa"\nnu = 0.5\n'
        f"[load]\np0 = {LOADS!r}\n".replace("'", '"')
    )
    return scene


# -- the surfaces (numpy only) ---------------------------------------------------------------


def test_band_limited_is_exact_interpolation() -> None:
    """A band-limited map keeps its values at the old nodes on a finer grid, and comes back."""
    h = synthesise(_psd, SIDE, 16, seed=1, q_max=6 * Q_CELL)[0]
    fine = band_limited(h, 64, SIDE)
    np.testing.assert_allclose(fine[::4, ::4], h, rtol=0, atol=1e-12 * np.abs(h).max())
    np.testing.assert_allclose(band_limited(fine, 16, SIDE), h, atol=1e-12 * np.abs(h).max())
    cut = band_limited(h, 16, SIDE, hi=3 * Q_CELL)  # the band: only modes |q| <= 3 q_cell
    spec = np.abs(np.fft.fft2(cut))
    k = np.fft.fftfreq(16, 1 / 16)
    assert spec[np.hypot(k[:, None], k[None, :]) > 3 + 1e-9].max() < 1e-12 * spec.max()


def test_band_limited_splits_the_nyquist_mode() -> None:
    """A map with power at its Nyquist wavevector: the finer map is real and keeps its nodes."""
    h = np.random.default_rng(2).standard_normal((8, 8))
    h -= h.mean()
    fine = band_limited(h, 16, SIDE)
    np.testing.assert_allclose(fine[::2, ::2], h, atol=1e-12)


def test_mirrored_keeps_every_height_and_has_no_step() -> None:
    h = np.random.default_rng(3).standard_normal((6, 6))
    m = mirrored(h)
    assert m.shape == (12, 12)
    np.testing.assert_array_equal(np.sort(m.ravel()), np.sort(np.tile(h.ravel(), 4)))
    np.testing.assert_array_equal(m[0], m[-1])  # the periodic wrap joins equal rows
    np.testing.assert_array_equal(m[:, 0], m[:, -1])


def test_tabulated_spectrum_synthesis_keeps_the_table_moments() -> None:
    """Syntheses of a tabulated spectrum on the plan's cell and band: their mean-square height
    and slope are the table's on that band (the lattice's discreteness: 1-2 % at 64^2)."""
    q = np.geomspace(1e3, 1e6, 31)
    C = 1e-30 * np.where(q < 4e3, 1.0, (q / 4e3) ** -3.6)
    scene = Scene(
        {
            "spectrum": {"model": "tabulated", "q": [f"{float(x)!r} 1/m" for x in q],
                         "C": [f"{float(x)!r} m**4" for x in C]},
            "material": {"E": "10 MPa", "nu": 0.5},
            "load": {"p0": "5 kPa"},
        }
    )  # fmt: skip
    plan = make_plan(scene, 64, 48, 0)
    assert plan.source.kind == "synthesis" and plan.L == pytest.approx(2 * math.pi / 1e3)
    assert plan.q_max == pytest.approx(8e3)
    table = Tabulated(q, C, q_1=8e3)
    assert plan.theory_scene.resolve().psd.h_rms() == pytest.approx(table.h_rms(), rel=1e-9)
    maps = [_surface(Task(plan, i, None)) for i in range(48)]
    h2, s2 = np.mean([np.square(map_moments(h, plan.L)) for h in maps], axis=0)
    assert math.sqrt(h2) == pytest.approx(table.h_rms(), rel=0.03)
    assert math.sqrt(s2) == pytest.approx(table.rms_slope(), rel=0.02)


def test_line_scan_is_synthesised_from_its_table() -> None:
    pytest.importorskip("SurfaceTopography")
    plan = make_plan(as_scene(EXAMPLES / "line_scan.toml"), 256, 2, 0)
    assert plan.source.kind == "synthesis" and plan.source.heights is None
    assert any("line scan" in n and "syntheses" in n for n in plan.notes)
    with pytest.raises(CrosscheckError, match="holds no roughness"):  # the table's first rings
        make_plan(as_scene(EXAMPLES / "line_scan.toml"), 32, 2, 0)


def test_measured_map_is_the_cell(tmp_path: Path) -> None:
    pytest.importorskip("SurfaceTopography")
    raw = _raw_map()
    plan = make_plan(as_scene(_map_scene(tmp_path, raw, ["20 um"] * 2)), 32, 1, 0)
    assert plan.source.kind == "map" and plan.L == pytest.approx(SIDE)
    assert plan.q_max == pytest.approx(4 * Q_CELL)
    # SurfaceTopography reads a text matrix's rows along y: the map is the file's transpose
    np.testing.assert_allclose(_surface(Task(plan, 0, None)), raw.T, atol=1e-12 * raw.std())


def test_non_square_map_refused(tmp_path: Path) -> None:
    pytest.importorskip("SurfaceTopography")
    scene = _map_scene(tmp_path, _raw_map()[:, :16], ["20 um", "10 um"])
    with pytest.raises(CrosscheckError, match="square"):
        make_plan(as_scene(scene), 32, 1, 0)


# -- end to end with tamaas -------------------------------------------------------------------


def _direct_tamaas_area(h: np.ndarray, L: float, E_star: float, p0: float) -> float:
    """The contact area of one map by a plain tamaas call (reduced units L = E* = 1)."""
    import tamaas as tm

    model = tm.ModelFactory.createModel(tm.model_type.basic_2d, [1.0, 1.0], list(h.shape))
    model.E, model.nu = 1.0, 0.0
    solver = tm.PolonskyKeerRey(model, np.ascontiguousarray(h / L), 1e-12)
    solver.max_iter = 5000
    solver.solve(p0 / E_star)
    return float(np.mean(np.asarray(model.traction) > 0))


@pytest.fixture(scope="module")
def map_run(tmp_path_factory: pytest.TempPathFactory) -> tuple:
    pytest.importorskip("tamaas")
    pytest.importorskip("SurfaceTopography")
    path = _map_scene(tmp_path_factory.mktemp("map"), _raw_map(), ["20 um"] * 2)
    lines: list[str] = []
    ds = xpersson.crosscheck(path, realisations=2, grid=N, grid_check=True, echo=lines.append)
    return ds, lines, path


def test_map_realisation_is_the_map_itself(map_run: tuple) -> None:
    """Realisation 0 is the measured map: its BEM area is a direct tamaas call's on the same
    heights, and its rms height is the map's; realisation 1 is synthesised."""
    ds, lines, _ = map_run
    raw = _raw_map()
    E_star = 10e6 / 0.75
    for p, got in zip(ds["p0"].values, ds["area_fraction_realisations"].values[0], strict=True):
        assert got == pytest.approx(_direct_tamaas_area(raw, SIDE, E_star, p), abs=1.01 / N**2)
    assert float(ds["bem_h_rms"][0]) == pytest.approx(raw.std(), rel=1e-9)
    assert ds["bem_surface"].values.tolist() == [1, 0]
    assert ds["bem_surface"].attrs["flag_meanings"].split()[1] == "measured_map"
    assert "measured map 'map.txt'" in ds.attrs["surfaces"]
    assert any("measured map" in line and "periodic" in line for line in lines)


def test_grid_check_ratio_is_fine_over_coarse(map_run: tuple) -> None:
    """X_grid_ratio is the BEM on 64^2 over the BEM on 32^2 (same surfaces), CF-attributed,
    linked as an ancillary variable, and in the estimate."""
    ds, lines, path = map_run
    for name in ("area_fraction", "mean_gap", "contact_stiffness"):
        var = ds[f"{name}_grid_ratio"]
        assert var.attrs["units"] == "1" and "64^2" in var.attrs["long_name"]
        assert f"{name}_grid_ratio" in ds[name].attrs["ancillary_variables"].split()
        assert var.dims == ds[name].dims
    fine = _fine_values(path, "area_fraction")
    coarse = ds["area_fraction_realisations"].values.mean(axis=0)
    np.testing.assert_allclose(ds["area_fraction_grid_ratio"].values, fine / coarse, rtol=1e-12)
    assert ds["bem_converged_fine"].values.all()
    assert "(+ grid check on 64^2)" in lines[0]


def _fine_values(path: Path, name: str) -> np.ndarray:
    """The mean over both realisations of the fine grid's value, solved here directly."""
    from xpersson.bem import solve

    plan = make_plan(as_scene(path), N, 2, 0)
    out = []
    for i in range(2):
        h = band_limited(_surface(Task(plan, i, None)), 2 * N, plan.L)
        mid = [solve(h, plan.L, plan.E_star, [p * math.exp(-0.05), p, p * math.exp(0.05)])[1]
               for p in plan.p0]  # fmt: skip
        out.append([getattr(s, name) for s in mid])
    return np.mean(out, axis=0)


def test_estimate_counts_the_grid_check(tmp_path: Path) -> None:
    pytest.importorskip("SurfaceTopography")
    scene = as_scene(_map_scene(tmp_path, _raw_map(), ["20 um"] * 2))
    plain, checked = make_plan(scene, 64, 2, 0), make_plan(scene, 64, 2, 0, grid_check=True)
    assert checked.seconds == pytest.approx(plain.seconds * (1 + 2**2.5))
    assert checked.memory > plain.memory


def test_cli_refuses_a_non_square_map_in_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    pytest.importorskip("tamaas")
    pytest.importorskip("SurfaceTopography")
    scene = _map_scene(tmp_path, _raw_map()[:, :16], ["20 um", "10 um"])
    assert main(["crosscheck", str(scene), "--grid-check"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "square" in err[0]


def test_synthesis_from_a_later_realisation_is_the_same_map() -> None:
    """``first`` draws map ``i`` alone: the same heights as in a call from 0."""
    all_ = synthesise(_psd, SIDE, 16, seed=7, realisations=4)
    np.testing.assert_array_equal(synthesise(_psd, SIDE, 16, seed=7, first=3)[0], all_[3])
