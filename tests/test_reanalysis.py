"""Analyses compute from the solved Dataset: an archive reopened from netCDF, with no scene
context, gives the numbers of the solving process (``xpersson.analyse``,
``xpersson.plugins.stored``)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import xarray as xr

import xpersson
from xpersson.errors import ArchiveError
from xpersson.physics.psd import SelfAffineRollOff
from xpersson.plugins.stored import contact_modulus, spectrum_of

SPECTRUM = {
    "model": "self_affine",
    "H": 0.8,
    "q_L": "1e3 1/m",
    "q_r": "1e4 1/m",
    "q_1": "1e8 1/m",
    "h_rms": "1 um",
}
THERMAL = {
    "conductivity_1": "167 W/(m*K)",
    "conductivity_2": "167 W/(m*K)",
    "gap_medium": "gas",
    "gas_conductivity": "0.026 W/(m*K)",
    "gas_mean_free_path": "68 nm",
    "temperature": "300 K",
}
ANALYSES = {
    "gap_pdf": {"u_points": 64},
    "leakage": {"seal_width": "2 mm"},
    "elastic_energy": {},
    "thermal_contact": THERMAL,
    "contact_area": {},
}


def _scene(analyses, p0=("0.1 MPa", "2 MPa")):
    return {
        "spectrum": dict(SPECTRUM),
        "material": {"E": "10 MPa", "nu": 0.5},
        "load": {"p0": p0 if isinstance(p0, str) else list(p0)},
        "output": {"zeta_per_decade": 4},
        "analyses": analyses,
    }


@pytest.fixture(scope="module")
def solved(tmp_path_factory):
    """The in-process analyses, and the archive of the same scene solved without them."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = xpersson.solve(_scene(ANALYSES))
        bare = xpersson.solve(_scene({}))
    path = tmp_path_factory.mktemp("reanalysis") / "bare.nc"
    xpersson.to_netcdf(bare, path)
    return ds, path


@pytest.mark.parametrize("name", sorted(ANALYSES))
def test_reopened_archive_equals_the_solving_process(solved, name):
    """gap_pdf, leakage, elastic energy, a transport quantity: bit for bit."""
    ds, path = solved
    with xr.open_dataset(path) as archive:
        reopened = archive.load()
    out = xpersson.analyse(reopened, name, **ANALYSES[name])
    added = [v for v in out.data_vars if v not in reopened.data_vars]
    assert added
    for v in added:
        np.testing.assert_array_equal(out[v].values, ds[v].values, err_msg=v)
    assert "gap_pdf" not in reopened  # the input is never modified


def test_spectrum_of_the_archive_is_the_solves(solved):
    _, path = solved
    ds = xpersson.open_dataset(path)
    psd = spectrum_of(ds)
    ref = SelfAffineRollOff.from_h_rms(1e-6, 0.8, 1e3, 1e4, 1e8)
    q = np.geomspace(1e3, 1e8, 101)
    np.testing.assert_array_equal(psd.I3(q), ref.I3(q))
    assert psd.moment(1.0) == ref.moment(1.0)
    assert contact_modulus(ds) == 10e6 / (1 - 0.25)


def test_one_load_archive_keeps_its_shape(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        one = xpersson.solve(_scene({"leakage": {}}, p0="1 MPa"))
        xpersson.to_netcdf(xpersson.solve(_scene({}, p0="1 MPa")), tmp_path / "one.nc")
    out = xpersson.analyse(xpersson.open_dataset(tmp_path / "one.nc"), "leakage")
    assert out.leak_rate.dims == () and "p0" not in out.dims
    assert float(out.leak_rate_emt) == float(one.leak_rate_emt)


@pytest.mark.parametrize("missing", ["psd_C", "q_psd", "E_star"])
def test_removed_spectrum_variables_are_named(solved, missing):
    _, path = solved
    ds = xpersson.open_dataset(path).drop_vars(missing)
    with pytest.raises(ArchiveError, match=f"no variable '{missing}'"):
        xpersson.analyse(ds, "gap_pdf")


def test_without_scene_attribute_is_refused(solved):
    _, path = solved
    ds = xpersson.open_dataset(path)
    ds.attrs.pop("xpersson_scene")
    with pytest.raises(ArchiveError, match="xpersson_scene"):
        xpersson.analyse(ds, "leakage")


def test_archive_without_exponents_to_round_off(solved):
    """An archive written before ``psd_exponent``: the log-log table, values within
    round-off of the spectrum (mean gap and energy within 1e-13)."""
    ds, path = solved
    old = xpersson.open_dataset(path).drop_vars("psd_exponent")
    out = xpersson.analyse(old, "elastic_energy")
    np.testing.assert_allclose(out.elastic_energy, ds.elastic_energy, rtol=1e-13, atol=0)


def test_sweep_points_read_their_own_spectrum():
    """A stacked sweep over H: each point's kappa from its own row of psd_C/psd_exponent
    equals the point solved alone; analyse of the sweep gives the sweep's own kappa."""
    scene = _scene({"contact_area": {}})
    scene["spectrum"]["H"] = [0.5, 0.9]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        swept = xpersson.solve(scene)
        scene["spectrum"]["H"] = 0.9
        alone = xpersson.solve(scene)
    assert swept.psd_exponent.dims == ("H", "q_psd")
    np.testing.assert_array_equal(swept.kappa.sel(H=0.9).values, alone.kappa.values)
    assert spectrum_of(swept, H=1).moment(3.0) == spectrum_of(alone).moment(3.0)
    again = xpersson.analyse(swept.drop_vars(["kappa"]), "contact_area")
    np.testing.assert_array_equal(again.kappa.values, swept.kappa.values)
