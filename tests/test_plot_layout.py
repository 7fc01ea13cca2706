"""Plots as figures for a paper: no text outside the canvas, human units, the scene's quantity.

Every kind is drawn from a bundled example (the plugins' examples where the kind needs one),
with the Dataset's title as suptitle (what ``xpersson plot`` writes), and every visible text
artist's window extent (matplotlib's renderer) must lie inside the figure's canvas.
"""

from __future__ import annotations

import os
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

import xpersson
import xpersson.plot as xplot

matplotlib = pytest.importorskip("matplotlib")
from matplotlib.text import Text  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
PLUGINS = ROOT / "plugins"


@pytest.fixture(autouse=True)
def _close_figures():
    """Every test's figures are closed after it (no pile-up of open pyplot figures)."""
    yield
    import matplotlib.pyplot as plt

    plt.close("all")


def _solve(path: Path, **overrides):
    if not path.is_file():
        pytest.skip(f"example {path.name} not in this checkout")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return xpersson.solve(path, **overrides)


@pytest.fixture(scope="module")
def scenes():
    """One Dataset per kind and bundled example (small grids where the example is big)."""
    seal = PLUGINS / "xpersson-interface" / "examples" / "rubber_seal.toml"
    tread = PLUGINS / "xpersson-viscoelastic" / "examples" / "tread_on_asphalt.toml"
    return {
        "elastic": _solve(ROOT / "examples" / "elastic.toml"),
        "sweep": _solve(ROOT / "examples" / "sweep.toml", load__p0=["10 kPa", "100 kPa", "1 MPa"]),
        "measured": _solve(ROOT / "examples" / "measured" / "two_scales.toml"),
        "sphere": _solve(ROOT / "examples" / "sphere.toml"),
        "steel": _solve(PLUGINS / "xpersson-plasticity" / "examples" / "steel_on_steel.toml"),
        "pdms": _solve(PLUGINS / "xpersson-adhesion" / "examples" / "pdms_on_glass.toml"),
        "seal": _solve(
            seal,
            analyses__gap_pdf={"u_points": 64},
            analyses__elastic_energy={},
            load__p0={"start": "0.05 MPa", "stop": "5 MPa", "num": 12},
        ),
        "tread": _solve(
            tread,
            coefficient__velocity=["1 um/s", "1 mm/s", "1 m/s"],
            coefficient__temperature=["273.15 K", "293.15 K", "313.15 K"],
            output__zeta_per_decade=4,
        ),
    }


CASES = [
    ("area", "elastic"),
    ("area", "sweep"),
    ("area", "steel"),
    ("area", "pdms"),
    ("area", "seal"),
    ("area", "tread"),
    ("pressure_pdf", "elastic"),
    ("gap_pdf", "seal"),
    ("leakage", "seal"),
    ("energy", "seal"),
    ("friction", "tread"),
    ("psd", "elastic"),
    ("psd", "measured"),
    ("body", "sphere"),
]


def test_every_kind_is_covered():
    assert {kind for kind, _ in CASES} == set(xplot.KINDS)


def _outside(fig, monkeypatch) -> list[str]:
    """Texts drawn (tick labels inside the view, legends, titles, labels) that reach beyond the
    canvas: each Text records its renderer window extent as it is drawn."""
    drawn = []
    original = Text.draw

    def record(self, renderer):
        original(self, renderer)
        if self.get_visible() and self.get_text().strip():
            drawn.append((self.get_text(), self.get_window_extent(renderer)))

    monkeypatch.setattr(Text, "draw", record)
    fig.canvas.draw()
    monkeypatch.setattr(Text, "draw", original)
    canvas = fig.bbox
    assert len(drawn) > 5  # labels, ticks, titles: the recorder saw the figure
    return [
        f"{text!r} at {box.bounds}"
        for text, box in drawn
        if box.x0 < canvas.x0 - 0.5
        or box.y0 < canvas.y0 - 0.5
        or box.x1 > canvas.x1 + 0.5
        or box.y1 > canvas.y1 + 0.5
    ]


@pytest.mark.parametrize(("kind", "scene"), CASES)
def test_no_text_outside_the_canvas(scenes, kind, scene, monkeypatch, tmp_path):
    ds = scenes[scene]
    plt = xplot.pyplot()
    closed = []
    monkeypatch.setattr(plt, "close", closed.append)  # keep the figure save() writes
    xplot.save(ds, kind, tmp_path / f"{kind}.png", dpi=72)
    fig = closed[0]
    assert _outside(fig, monkeypatch) == []
    ax = fig.axes[0]
    labels = " ".join([ax.get_xlabel(), ax.get_ylabel()])
    assert "e+0" not in labels and "[Pa]" not in labels  # human units, not 1e+04 Pa
    matplotlib.pyplot.close(fig)


def test_human_units():
    assert xplot.human("Pa", [1e4, 2e5]) == (1e3, "kPa")
    assert xplot.human("Pa", [5e6, 1e8]) == (1e6, "MPa")
    assert xplot.human("m", [2e-6]) == (1e-6, "µm")
    assert xplot.human("m s-1", [1e-2]) == (1e-2, "cm/s")
    assert xplot.text(1e4, "Pa") == "10 kPa"
    assert xplot.text(293.15, "K") == "20 °C"


def test_plastic_area_shows_total_and_plastic(scenes):
    ds = scenes["steel"]
    ax = xplot.area(ds)
    total = ds["total_contact_fraction"].values
    drawn = [np.asarray(ln.get_ydata()) for ln in ax.lines]
    # the total (A_el + A_pl)/A0 of every load is drawn; at zeta_max it is p0 / sigma_Y
    for row in total:
        assert any(np.allclose(d, row, equal_nan=True) for d in drawn)
    assert total[:, -1] == pytest.approx(ds["p0"].values / 3e9, rel=1e-3)
    assert ax.get_ylim()[0] > 1e-6  # the elastic area's fall to 0 does not stretch the axis


def test_leakage_marks_sealed_loads_and_limits_the_axis(scenes):
    ds = scenes["seal"]
    ax = xplot.leakage(ds)
    assert len(ax.lines) == 2  # critical junction and effective medium
    lo, hi = ax.get_ylim()
    assert hi / lo < 1e12  # at most ~11 decades, not down to 1e-44
    assert any("sealed" in t.get_text() for t in ax.texts) == bool(ds["leak_sealed"].any())


def test_friction_draws_mu_of_v_at_each_temperature(scenes):
    ds = scenes["tread"]
    ax = xplot.friction(ds)
    assert "sliding speed" in ax.get_xlabel() and ax.get_xscale() == "log"
    colours = {ln.get_color() for ln in ax.lines}
    assert len(colours) == ds.sizes["T"] == 3
    heavy = ds["mu"].isel(p0=-1).transpose("T", "v").values
    drawn = [np.asarray(ln.get_ydata()) for ln in ax.lines]
    for row in heavy:
        assert any(np.allclose(d, row) for d in drawn)


@pytest.fixture(scope="module")
def one_speed():
    """The tread example at one sliding speed and one load (small grid)."""
    return _solve(
        PLUGINS / "xpersson-viscoelastic" / "examples" / "tread_on_asphalt.toml",
        output__zeta_per_decade=4,
        load__p0="0.3 MPa",
    )


def test_friction_of_one_speed_is_resolved_over_speeds(one_speed):
    ds = one_speed
    ax = xplot.friction(ds, speeds=[1e-4, 1e-2, 1.0])
    curves = [ln for ln in ax.lines if len(ln.get_xdata()) == 3]
    assert len(curves) == 6  # 3 temperatures x (total, viscoelastic part)
    star = [ln for ln in ax.lines if ln.get_marker() == "*"]
    assert len(star) == 1 and star[0].get_ydata()[0] == pytest.approx(float(ds["mu"]))


def test_friction_that_cannot_resolve_is_an_error_not_another_figure(one_speed):
    """No silent fallback: a one-speed Dataset without its scene is refused, naming the way out
    (resolve=False), which draws mu versus p0 at the one speed."""
    ds = one_speed.copy()
    del ds.attrs["xpersson_scene"]
    with pytest.raises(ValueError, match="stores no scene.*resolve=False"):
        xplot.friction(ds)
    with pytest.raises(ValueError, match="rubber_temperature.*resolve=False"):
        xplot.friction(one_speed.drop_vars("rubber_temperature"))
    ax = xplot.friction(ds, resolve=False)
    assert len(ax.lines) == 1 and ax.lines[0].get_ydata() == pytest.approx([float(ds["mu"])])


def test_pyplot_leaves_the_backend_to_matplotlib():
    """No process-wide side effect: a backend the user chose stays, display or not."""
    code = "import matplotlib, xpersson.plot as p\np.pyplot()\nprint(matplotlib.get_backend())\n"
    env = {k: v for k, v in os.environ.items() if k != "DISPLAY"} | {"MPLBACKEND": "svg"}
    run = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, env=env
    )
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == "svg"


def test_missing_matplotlib_is_one_clear_line(tmp_path):
    code = (
        "import sys; sys.modules['matplotlib'] = None\n"
        "import xpersson, xpersson.plot as p\n"
        "try:\n"
        "    p.pyplot()\n"
        "except p.MatplotlibMissingError as e:\n"
        "    assert isinstance(e, ImportError); print(e)\n"
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT)
    assert run.returncode == 0, run.stderr
    lines = run.stdout.strip().splitlines()
    assert len(lines) == 1 and "pip install" in lines[0] and "matplotlib" in lines[0]


def test_the_check_sees_clipped_text(monkeypatch):
    """The canvas check itself: a label pushed off the figure is reported, one inside is not."""
    plt = xplot.pyplot()
    fig, ax = plt.subplots(figsize=(3, 2))
    ax.set_ylabel("a long label " * 6)
    ax.text(1.3, 0.5, "beyond the right edge", transform=ax.transAxes)
    bad = _outside(fig, monkeypatch)
    assert any("beyond the right edge" in b for b in bad) and any("long label" in b for b in bad)
    assert not any("0.5" == b.split("'")[1] for b in bad)  # tick labels fit
    plt.close(fig)
