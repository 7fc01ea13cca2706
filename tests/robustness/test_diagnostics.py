"""P-resolution diagnostics, regime warnings and ``xpersson info``."""

from __future__ import annotations

import copy
import json
import warnings

import numpy as np
import pytest
from xpersson_core_reference import REFERENCE_SCENE

import xpersson
from xpersson import XperssonWarning
from xpersson.cli import main
from xpersson.pipeline.diagnostics import P_RTOL


def _solve(scene):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ds = xpersson.solve(scene)
    return ds, [str(w.message) for w in caught if issubclass(w.category, XperssonWarning)]


def _scene(**output):
    scene = copy.deepcopy(REFERENCE_SCENE)
    scene["output"] = {"zeta_per_decade": 4, **output}
    return scene


def test_unresolved_P_is_marked_and_warned():
    ds, warned = _solve(_scene(pressure_pdf=True, p_points=64))
    p = ds["p"].values
    integral = np.trapezoid(ds["P"].transpose("p0", "zeta", "p").values, p, axis=-1)
    np.testing.assert_allclose(ds["P_integral"].transpose("p0", "zeta").values, integral)
    ok = ds["P_resolved"].transpose("p0", "zeta").values.astype(bool)
    area = ds["area_fraction"].transpose("p0", "zeta").values
    assert np.all(np.abs(integral[ok] - area[ok]) <= P_RTOL * area[ok])
    assert np.all(np.abs(integral[~ok] - area[~ok]) > P_RTOL * area[~ok])
    assert not ok[:, 0].any()  # zeta = 1: the initial delta
    assert (~ok[:, 1:]).any()  # 64 points cannot resolve the narrow early distribution
    assert any("P_resolved" in w for w in warned)
    assert "P_resolved" in ds.attrs["status_message"]


def test_resolved_P_raises_no_warning():
    scene = _scene(
        pressure_pdf=True,
        zeta=[1.0, 1e4, 1e5],
        p=[f"{float(x)!r} Pa" for x in np.linspace(0, 3e6, 3001)],
    )
    scene["load"]["p0"] = ["1e5 Pa"]
    ds, warned = _solve(scene)
    assert ds["P_resolved"].values[..., 1:].all()
    assert not warned and ds.attrs["status"] == "success"


@pytest.mark.parametrize(
    ("change", "words"),
    [
        ({"spectrum": {"h_rms": None, "rms_slope": 8.0}}, "rms slope 8"),
        ({"load": {"p0": ["1e4 Pa", "2e7 Pa"]}}, "exceed the contact modulus"),
    ],
)
def test_regime_warnings_recorded_and_issued(change, words):
    scene = _scene()
    for section, values in change.items():
        for k, v in values.items():
            if v is None:
                scene[section].pop(k)
            else:
                scene[section][k] = v
    ds, warned = _solve(scene)
    assert any(words in w for w in warned)
    assert words in ds.attrs["status_message"]
    assert any(words in n for n in json.loads(ds.attrs["regime_warnings"]))


def test_no_regime_warning_inside_the_regime():
    ds, warned = _solve(_scene())
    assert json.loads(ds.attrs["regime_warnings"]) == []
    assert not warned


def test_info_counts_the_loads_it_leaves_out(tmp_path, capsys):
    scene = _scene()
    scene["load"]["p0"] = {"start": "1 kPa", "stop": "1 MPa", "num": 13}
    path = xpersson.to_netcdf(xpersson.solve(scene), tmp_path / "a.nc")
    assert main(["info", str(path)]) == 0
    out = capsys.readouterr().out
    assert "first 10 of 13 loads; 3 more not shown" in out
    assert "area_fraction" in out and "non_contact_fraction" not in out.split("area fractions")[1]


def test_info_shows_the_boundary_areas(tmp_path, capsys):
    pytest.importorskip("xpersson_plasticity")
    scene = _scene()
    scene["load"]["p0"] = ["1 MPa"]
    scene["material"]["E"] = "200 GPa"
    scene["boundary"] = {"model": "plastic", "sigma_Y": "5 MPa"}
    ds = xpersson.solve(scene)
    path = xpersson.to_netcdf(ds, tmp_path / "p.nc")
    assert main(["info", str(path)]) == 0
    out = capsys.readouterr().out
    pl = float(ds["plastic_area_fraction"].isel(zeta=-1).values.ravel()[0])
    assert pl > 0
    table = out.split("area fractions at zeta_max")[1]
    line = next(x for x in table.splitlines() if x.strip().startswith("plastic_area_fraction"))
    assert f"{pl:.6g}" in line
