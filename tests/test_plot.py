"""Plots: every kind renders to PNG from the bundled examples, with units and log axes."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import xpersson
from xpersson.cli import main

ROOT = Path(__file__).resolve().parents[1]
PNG = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(autouse=True)
def _close_figures():
    """Every test's figures are closed after it (no pile-up of open pyplot figures)."""
    yield
    import matplotlib.pyplot as plt

    plt.close("all")


@pytest.fixture(scope="module")
def elastic():
    return xpersson.solve(ROOT / "examples" / "elastic.toml")


@pytest.fixture(scope="module")
def seal():
    sc = xpersson.load_scene(
        ROOT / "plugins" / "xpersson-interface" / "examples" / "rubber_seal.toml"
    )
    sc.data["analyses"].update({"gap_pdf": {"u_points": 64}, "elastic_energy": {}})
    sc.data["load"]["p0"] = {"start": "0.05 MPa", "stop": "5 MPa", "num": 5}
    return xpersson.solve(sc)


def test_matplotlib_is_imported_only_when_plotting():
    code = (
        "import sys, xpersson, xpersson.sweep, xpersson.cli; "
        "assert 'matplotlib' not in sys.modules; import xpersson.plot; "
        "assert 'matplotlib' not in sys.modules"
    )
    subprocess.run([sys.executable, "-c", code], cwd=ROOT, check=True)


def test_area_one_curve_per_load_log_zeta(elastic):
    ax = xpersson.plot.area(elastic)
    assert len(ax.lines) == elastic.sizes["p0"] == 3
    assert ax.get_xscale() == "log" and ax.get_xlabel() == r"magnification $\zeta$"
    legend = ax.figure.legends[0]  # outside the axes, human units, heaviest load first
    assert [t.get_text() for t in legend.get_texts()] == ["1 MPa", "100 kPa", "10 kPa"]


def test_sweep_area_one_curve_per_swept_value():
    ds = xpersson.solve(ROOT / "examples" / "sweep.toml")
    ax = xpersson.plot.plot(ds, "area")
    assert len(ax.lines) == 6 and ax.get_xscale() == ax.get_yscale() == "log"
    assert ax.get_xlabel() == "nominal pressure $p_0$ [MPa]"
    # colour = H, line style and marker = E: no two curves look alike
    looks = {(ln.get_color(), ln.get_linestyle(), ln.get_marker()) for ln in ax.lines}
    assert len(looks) == 6
    labels = [[t.get_text() for t in lg.get_texts()] for lg in ax.figure.legends]
    assert labels == [["0.8", "0.7", "0.6"], ["5 MPa", "10 MPa"]]


@pytest.mark.parametrize(
    ("kind", "xlabel", "lines", "points"),
    [
        ("leakage", "nominal pressure $p_0$ [MPa]", 2, 5),  # critical junction and EMT
        ("energy", "nominal pressure $p_0$ [MPa]", 1, 5),
        ("gap_pdf", "[µm]", 5, 64),  # one curve per load over the gap grid
    ],
)
def test_interface_kinds(seal, kind, xlabel, lines, points):
    ax = xpersson.plot.plot(seal, kind)
    assert len(ax.lines) == lines and len(ax.lines[0].get_xdata()) == points
    ys = np.concatenate([ln.get_ydata() for ln in ax.lines])
    ys = ys[np.isfinite(ys) & (ys > 0)]
    # log y exactly when the values span a decade or more
    assert xlabel in ax.get_xlabel()
    assert ax.get_yscale() == ("log" if ys.max() >= 10 * ys.min() else "linear")


def test_every_kind_writes_a_png_via_the_cli(tmp_path, elastic, seal):
    xpersson.to_netcdf(elastic, tmp_path / "e.nc")
    xpersson.to_netcdf(seal, tmp_path / "s.nc")
    for kind, src in [
        ("area", "e"),
        ("pressure_pdf", "e"),
        ("leakage", "s"),
        ("gap_pdf", "s"),
        ("energy", "s"),
    ]:
        out = tmp_path / f"{kind}.png"
        assert main(["plot", str(tmp_path / f"{src}.nc"), "--kind", kind, "-o", str(out)]) == 0
        assert out.read_bytes()[:8] == PNG and out.stat().st_size > 5000
    assert (
        main(["plot", str(tmp_path / "e.nc"), "--kind", "leakage", "-o", str(tmp_path / "x.png")])
        == 2
    )  # a clear error: no leak_rate in the archive


def test_friction_kind_versus_swept_sliding_speed():
    ex = ROOT / "plugins" / "xpersson-viscoelastic" / "examples" / "tread_on_asphalt.toml"
    if not ex.is_file():
        pytest.skip("the viscoelastic plugin's example is not in this checkout")
    sc = xpersson.load_scene(ex)
    sc.data["coefficient"]["velocity"] = ["1 mm/s", "1 cm/s", "10 cm/s"]
    sc.data["output"] = {"zeta_per_decade": 4}
    ds = xpersson.solve(sc)
    ax = xpersson.plot.plot(ds, "friction")
    # the heaviest load: total mu and its viscoelastic part, one point per speed
    assert len(ax.lines) == 2 and len(ax.lines[0].get_xdata()) == 3
    assert ax.get_xscale() == "log" and "[cm/s]" in ax.get_xlabel()
    assert ax.get_ylabel().startswith("friction coefficient")
    mu = ds["mu"].isel(p0=-1).values
    assert ax.lines[0].get_ydata() == pytest.approx(mu)
