"""Plots tested by their numbers (issue 38): every kind's drawn data, read back from the Axes,
equals the Dataset's values in the axis' units. Each test fixes the human unit it expects (from
the label) and its factor independently of the plot code, so dropping a unit conversion (the
pressure PDF drawn in 1/Pa under a 1/MPa label) fails here."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import xpersson
import xpersson.plot

ROOT = Path(__file__).resolve().parents[1]
PLUGINS = ROOT / "plugins"


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    import matplotlib.pyplot as plt

    plt.close("all")


def _solve(scene):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return xpersson.solve(scene)


@pytest.fixture(scope="module")
def elastic(tmp_path_factory):
    """The flagship example, read back from its archive (units in the stored caret form)."""
    path = tmp_path_factory.mktemp("el") / "e.nc"
    xpersson.to_netcdf(_solve(ROOT / "examples" / "elastic.toml"), path)
    return xpersson.open_dataset(path)


@pytest.fixture(scope="module")
def sweep():
    return _solve(ROOT / "examples" / "sweep.toml")


@pytest.fixture(scope="module")
def seal():
    sc = xpersson.load_scene(PLUGINS / "xpersson-interface" / "examples" / "rubber_seal.toml")
    sc.data["analyses"].update({"gap_pdf": {"u_points": 64}, "elastic_energy": {}})
    sc.data["load"]["p0"] = {"start": "0.05 MPa", "stop": "5 MPa", "num": 5}
    return _solve(sc)


def assert_drawn(ax, da, x, xfactor, yfactor, lines=None):
    """Every curve of ``ax`` is one curve of ``da`` along ``x``: x data * ``xfactor`` equals the
    coordinate and y data * ``yfactor`` one row of ``da`` (both back in the Dataset's units)."""
    drawn = [ln for ln in ax.lines if len(ln.get_xdata()) > 1]
    assert drawn and (lines is None or len(drawn) == lines)
    rows = np.asarray(da.transpose(..., x).values, float).reshape(-1, da.sizes[x])
    for ln in drawn:
        np.testing.assert_allclose(np.asarray(ln.get_xdata()) * xfactor, da[x].values, rtol=1e-12)
        y = np.asarray(ln.get_ydata(), float) * yfactor
        assert any(np.allclose(y, r, rtol=1e-12, atol=0, equal_nan=True) for r in rows), ln


def test_pressure_pdf_peak_equals_the_datasets_in_1_per_mpa(elastic):
    ax = xpersson.plot.pressure_pdf(elastic)
    assert ax.get_ylabel().endswith("[1/MPa]") and ax.get_xlabel().endswith("[MPa]")
    P = elastic["P"].isel(zeta=-1)
    assert_drawn(ax, P, "p", 1e6, 1e-6, lines=3)
    peak = max(np.nanmax(ln.get_ydata()) for ln in ax.lines)
    assert peak == pytest.approx(float(P.max()) * 1e6, rel=1e-12)  # 0.64 /MPa, not 6.4e-7
    assert 0.5 < peak < 1.0


def test_area_versus_zeta_few_loads(elastic):
    ax = xpersson.plot.area(elastic)
    assert ax.get_xlabel() == r"magnification $\zeta$"
    assert_drawn(ax, elastic["area_fraction"], "zeta", 1.0, 1.0, lines=3)


def test_area_of_a_sweep_versus_load_in_mpa(sweep):
    ax = xpersson.plot.area(sweep)
    assert ax.get_xlabel().endswith("[MPa]")
    assert_drawn(ax, sweep["area_fraction"].isel(zeta=-1), "p0", 1e6, 1.0, lines=6)


@pytest.mark.parametrize(
    ("kind", "var", "x", "units", "xfactor", "yfactor", "lines"),
    [
        ("leakage", "leak_rate", "p0", ("[MPa]", "[mm³/s]"), 1e6, 1e-9, None),
        ("leakage", "leak_rate_emt", "p0", ("[MPa]", "[mm³/s]"), 1e6, 1e-9, None),
        ("energy", "elastic_energy", "p0", ("[MPa]", "[mJ/m²]"), 1e6, 1e-3, 1),
        ("gap_pdf", "gap_pdf", "u", ("[µm]", "[1/µm]"), 1e-6, 1e6, 5),
    ],
)
def test_interface_kinds_draw_the_datasets_numbers(
    seal, kind, var, x, units, xfactor, yfactor, lines
):
    ax = xpersson.plot.plot(seal, kind)
    assert ax.get_xlabel().endswith(units[0]) and ax.get_ylabel().endswith(units[1])
    da = seal[var].where(seal[var] > 0)
    drawn = [ln for ln in ax.lines if len(ln.get_xdata()) > 1]
    if kind == "leakage":  # one curve per theory: this variable's is one of them
        rows = [
            ln
            for ln in drawn
            if np.allclose(
                np.asarray(ln.get_ydata()) * yfactor, da.values, equal_nan=True, rtol=1e-12, atol=0
            )
        ]
        assert len(rows) == 1
        np.testing.assert_allclose(rows[0].get_xdata() * xfactor, seal["p0"].values, rtol=1e-12)
        return
    assert_drawn(ax, da, x, xfactor, yfactor, lines=lines)


def test_friction_draws_mu_versus_speed_in_cm_per_s_and_explains_the_star():
    sc = xpersson.load_scene(
        PLUGINS / "xpersson-viscoelastic" / "examples" / "tread_on_asphalt.toml"
    )
    sc.data["output"] = {"zeta_per_decade": 4}
    ds = _solve(sc)
    ax = xpersson.plot.friction(ds, speeds=[1e-3, 1e-2, 1e-1])
    assert ax.get_xlabel().endswith("[cm/s]")
    star = [ln for ln in ax.lines if ln.get_marker() == "*"]
    assert len(star) == 1  # the archive's own point, at its speed in cm/s and its mu
    assert star[0].get_xdata()[0] * 1e-2 == pytest.approx(float(ds["sliding_speed"]))
    assert star[0].get_ydata()[0] == pytest.approx(float(ds["mu"].isel(p0=-1)))
    texts = [t.get_text() for lg in ax.figure.legends for t in lg.get_texts()]
    assert "the archive's point (1 cm/s, 20 °C)" in texts
    curves = [ln for ln in ax.lines if len(ln.get_xdata()) > 1]
    for ln in curves:  # speeds back in m/s
        np.testing.assert_allclose(ln.get_xdata() * 1e-2, [1e-3, 1e-2, 1e-1], rtol=1e-12)
    # the curve at the archive's temperature passes through the star
    mid = [ln for ln in curves if ln.get_linestyle() == "-"]
    assert any(ln.get_ydata()[1] == pytest.approx(star[0].get_ydata()[0], rel=1e-9) for ln in mid)


def _synthetic(n_colour: int) -> xr.Dataset:
    """area_fraction(E, H, p0, zeta) with ``n_colour`` Young's moduli (no solve)."""
    E = np.geomspace(1e6, 1e8, n_colour)
    H = np.array([0.6, 0.7, 0.8, 0.9, 0.95, 0.99])
    p0, zeta = np.array([1e4, 1e5, 1e6]), np.geomspace(1, 1e4, 5)
    a = (p0[None, None, :, None] / E[:, None, None, None]) * zeta[None, None, None, :] ** -0.1
    a = a * (1 + H[None, :, None, None])
    ds = xr.Dataset(
        {"area_fraction": (("E", "H", "p0", "zeta"), a, {"units": "1"})},
        coords={
            "E": ("E", E, {"units": "Pa"}),
            "H": ("H", H, {"units": "1"}),
            "p0": ("p0", p0, {"units": "Pa"}),
            "zeta": ("zeta", zeta, {"units": "1", "long_name": "magnification"}),
        },
    )
    return ds


@pytest.mark.parametrize("n", [5, 100])
def test_a_sweep_plot_says_how_many_swept_values_it_drew(n):
    ax = xpersson.plot.area(_synthetic(n))
    fig = ax.figure
    titles = [
        lg.get_title().get_text()
        for lg in [*fig.legends, *ax.get_children()]
        if hasattr(lg, "get_title") and hasattr(lg, "get_texts")
    ]
    bars = [a.get_ylabel() for a in fig.axes if a is not ax]
    said = " ".join(titles + bars)
    drawn, total = len({ln.get_color() for ln in ax.lines}), max(n, 6)  # colour: the larger dim
    assert drawn < total  # 12 curves at most: 2 colours x 6 styles, or 2 x 5
    if drawn < total:
        assert f"({drawn} of {total} drawn)" in said
    else:
        assert "drawn)" not in said
    assert_drawn(ax, _synthetic(n)["area_fraction"].isel(zeta=-1), "p0", 1e6, 1.0)


def test_save_titles_from_the_archives_metadata(sweep, tmp_path):
    ds = sweep.copy()
    ds.attrs["history"] += " (xpersson run examples/sweep.toml -o s.nc --set 'material.nu=0.4')"
    title = xpersson.plot.suptitle(ds)
    lines = title.split("\n")
    assert lines[0] == ds.attrs["title"]
    assert lines[1] == "sweep: H = 0.6, 0.7, 0.8; E = 5 MPa, 10 MPa"
    assert lines[2] == "with --set material.nu=0.4"


def test_gap_pdf_and_energy_have_their_own_titles(seal):
    for kind in ("gap_pdf", "energy"):
        ax = xpersson.plot.plot(seal, kind)
        assert ax.get_title() and ax.get_title() != seal.attrs["title"]


def test_body_draws_the_nominal_pressure_in_its_units():
    """The body kind: each drawn curve is ``nominal_pressure(force, r)`` in the axis' pressure
    unit against ``r`` in the axis' length unit (fixed here from the labels, not by the plot
    code), and the dotted lines sit at the Hertz radii."""
    ds = _solve(ROOT / "examples" / "sphere.toml")
    ax = xpersson.plot.plot(ds, "body")
    y_unit = ax.get_ylabel().split("(")[-1].rstrip(")")
    x_unit = ax.get_xlabel().split("(")[-1].rstrip(")")
    to_pa = {"Pa": 1.0, "kPa": 1e3, "MPa": 1e6, "GPa": 1e9}[y_unit]
    to_m = {"mm": 1e-3, "µm": 1e-6, "nm": 1e-9}[x_unit]
    curves = [line for line in ax.lines if line.get_linestyle() == "-"]
    marks = [line for line in ax.lines if line.get_linestyle() == ":"]
    assert len(curves) == ds.sizes["force"] == len(marks)
    for i, line in enumerate(curves):
        np.testing.assert_allclose(line.get_xdata() * to_m, ds["r"].values, rtol=1e-12)
        want = ds["nominal_pressure"].transpose("force", "r").values[i]
        np.testing.assert_allclose(line.get_ydata() * to_pa, want, rtol=1e-12)
        np.testing.assert_allclose(marks[i].get_xdata()[0] * to_m, ds["hertz_radius"].values[i])
    with pytest.raises(ValueError, match="finite-body archive"):
        xpersson.plot.plot(_solve(ROOT / "examples" / "elastic.toml"), "body")
