"""``xpersson psd`` and the ``psd`` plot kind (issue 35): the measured spectrum as a user sees
it, in the Persson convention, with a self-affine fit and the measured bands."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import xpersson
from xpersson.cli import main
from xpersson.testing.surfaces import rolled_off, synthetic_map

ST = pytest.importorskip("SurfaceTopography")

L = 1e-3
Q = 2 * math.pi / L


@pytest.fixture(scope="module")
def maps(tmp_path_factory):
    """A 1 mm and a 125 um periodic scan of one self-affine surface (H = 0.8, roll-off 4 q_L)."""
    folder = tmp_path_factory.mktemp("psd")
    shape = rolled_off(0.8, Q, 4 * Q, None)
    for name, size, seed in (("coarse.nc", L, 1), ("fine.nc", L / 8, 2)):
        h = synthetic_map(128, size, shape, seed=seed) * 2e-11  # coarse h_rms ~ 1 um
        ST.Topography(h, (size, size), periodic=True, unit="m").to_netcdf(str(folder / name))
    return folder


def test_psd_csv_states_the_convention_fits_and_solves_as_a_table(maps):
    out = maps / "psd.csv"
    assert main(["psd", str(maps / "coarse.nc"), str(maps / "fine.nc"), "-o", str(out)]) == 0
    head = [line for line in out.read_text().splitlines() if line.startswith("#")]
    assert "Persson convention" in head[0] and "q in 1/m" in head[0] and "m^4" in head[0]
    fit = next(line for line in head if line.startswith("# fit:"))
    H = float(fit.split("H = ")[1].split(" +- ")[0])
    q_r = float(fit.split("q_r = ")[1].split(" +- ")[0])
    assert H == pytest.approx(0.8, abs=0.02) and q_r == pytest.approx(4 * Q, rel=0.1)
    parts = [json.loads(line.split(": ", 1)[1]) for line in head if line.startswith("# part")]
    assert [p["file"].rsplit("/", 1)[-1] for p in parts] == ["coarse.nc", "fine.nc"]
    solid = {"material": {"E": "10 MPa", "nu": 0.5}, "load": {"p0": "1 MPa"}}
    table = xpersson.solve({"spectrum": {"model": "tabulated", "file": str(out)}, **solid})
    spectrum = {"model": "topography", "file": str(maps / "coarse.nc"),
                "file_2": str(maps / "fine.nc")}  # fmt: skip
    scans = xpersson.solve({"spectrum": spectrum, **solid})
    np.testing.assert_allclose(table.psd_C.values, scans.psd_C.values, rtol=1e-12)
    assert float(table.h_rms) == pytest.approx(float(scans.map_h_rms), rel=1e-9)


def test_psd_refuses_a_map_without_size_and_writes_nothing(tmp_path):
    np.savetxt(tmp_path / "m.txt", np.random.default_rng(0).random((16, 16)))
    assert main(["psd", str(tmp_path / "m.txt"), "-o", str(tmp_path / "p.csv")]) == 2
    assert not (tmp_path / "p.csv").exists()
    assert main(["psd", str(tmp_path / "m.txt"), "--physical-sizes", "1 um", "1 um",
                 "--unit", "nm", "-o", str(tmp_path / "p.csv")]) == 0  # fmt: skip
    assert (tmp_path / "p.csv").exists()


def test_plot_kind_psd_draws_the_table_fit_and_bands(maps, tmp_path):
    pytest.importorskip("matplotlib")
    from xpersson import plot

    scene = {"spectrum": {"model": "topography", "file": str(maps / "coarse.nc"),
                          "file_2": str(maps / "fine.nc")},
             "material": {"E": "10 MPa", "nu": 0.5}, "load": {"p0": "1 MPa"}}  # fmt: skip
    xpersson.to_netcdf(xpersson.solve(scene), tmp_path / "o.nc")
    ds = xpersson.open_dataset(tmp_path / "o.nc")
    ax = plot.plot(ds, "psd")
    table, fit = ax.lines[0], ax.lines[1]
    np.testing.assert_array_equal(table.get_ydata(), ds.psd_C.values)
    assert fit.get_label().startswith("fit: H = 0.8")
    assert len(ax.patches) == 2  # the two scans' bands
    assert (
        main(["plot", str(tmp_path / "o.nc"), "--kind", "psd", "-o", str(tmp_path / "p.png")]) == 0
    )
