"""``xpersson.analyse`` of a sweep's archive: every point analysed with its own swept values
gives, bit for bit and in the sweep's layout, what the analysis run inside the sweep gives;
and the round trip a user meets (solve, archive to netCDF, reopen, analyse) over seeded
scenes."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import xpersson
from xpersson.errors import ArchiveError

SPECTRUM = {
    "model": "self_affine",
    "H": 0.8,
    "q_L": "1e3 1/m",
    "q_r": "1e4 1/m",
    "q_1": "1e8 1/m",
    "h_rms": "1 um",
}
LEAKAGE = {"seal_width": "2 mm"}


def _scene(analyses, spectrum=None, E="10 MPa", p0=("0.1 MPa", "2 MPa")):
    return {
        "spectrum": dict(spectrum or SPECTRUM),
        "material": {"E": E, "nu": 0.5},
        "load": {"p0": p0 if isinstance(p0, str) else list(p0)},
        "output": {"zeta_per_decade": 4},
        "analyses": analyses,
    }


def _round_trip(ds, path):
    """``ds`` written with xpersson.to_netcdf and reopened (loaded) as a user reopens it."""
    xpersson.to_netcdf(ds, path)
    with xpersson.open_dataset(path) as archive:
        return archive.load()


def _assert_same_outputs(out, ref, base):
    """Every variable ``out`` adds to ``base`` is ``ref``'s, with its dims, bit for bit; and
    ``out`` lacks none of ``ref``'s variables."""
    added = [v for v in out.variables if v not in base.variables]
    assert added
    assert not [v for v in ref.variables if v not in out.variables]
    for v in added:
        assert out[v].dims == ref[v].dims, v
        np.testing.assert_array_equal(out[v].values, ref[v].values, err_msg=v)
        assert out[v].attrs.get("units") == ref[v].attrs.get("units"), v


@pytest.mark.parametrize(
    ("name", "params"),
    [("leakage", LEAKAGE), ("gap_pdf", {"u_points": 32}), ("elastic_energy", {})],
)
def test_sweep_archive_equals_the_sweeps_analysis(tmp_path, name, params):
    """E x H (the batched path over E): the layout (E and H in front, dropped where an
    output does not change), the model-error variables and the values."""
    scene = _scene({name: params}, E=["5 MPa", "10 MPa"])
    scene["spectrum"]["H"] = [0.6, 0.8]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = xpersson.solve(scene)
        scene["analyses"] = {}
        bare = _round_trip(xpersson.solve(scene), tmp_path / "bare.nc")
    out = xpersson.analyse(bare, name, **params)
    _assert_same_outputs(out, ref, bare)
    assert not [v for v in out.variables if v not in bare.variables and v not in ref.variables]


def test_single_load_sweep_keeps_its_scalar_load():
    scene = _scene({"leakage": LEAKAGE}, E=["5 MPa", "10 MPa", "20 MPa"], p0="0.1 MPa")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = xpersson.solve(scene)
        scene["analyses"] = {}
        bare = xpersson.solve(scene)
    out = xpersson.analyse(bare, "leakage", **LEAKAGE)
    assert out.p0.ndim == 0 and "E" in out.leak_u1.dims
    _assert_same_outputs(out, ref, bare)


def test_sweep_without_its_coordinate_is_refused():
    scene = _scene({}, E=["5 MPa", "10 MPa"])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        swept = xpersson.solve(scene)
    with pytest.raises(ArchiveError, match="no sweep coordinate 'E'"):
        xpersson.analyse(swept.drop_vars("E"), "leakage")


def _seeded(seed):
    """A seeded scene of the documented domain: H, roll-off, decades, modulus, loads."""
    rng = np.random.default_rng(seed)
    H = round(float(rng.uniform(0.3, 0.95)), 3)
    q_r = 1e3 * 10 ** float(rng.choice([0.0, 1.0]))
    q_1 = 1e3 * 10 ** float(rng.integers(3, 6))
    spectrum = dict(SPECTRUM, H=H, q_r=f"{q_r!r} 1/m", q_1=f"{q_1!r} 1/m")
    E = f"{float(10 ** rng.uniform(6, 8))!r} Pa"
    p0 = [f"{float(10**x)!r} Pa" for x in np.sort(rng.uniform(4, 6.5, 3))]
    return spectrum, E, p0


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_round_trip_of_seeded_scenes(tmp_path, seed):
    """solve -> to_netcdf -> reopen -> analyse(ds, "leakage") equals the analysis of the
    original solve bit for bit."""
    spectrum, E, p0 = _seeded(seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = xpersson.solve(_scene({"leakage": LEAKAGE}, spectrum, E, p0))
        bare = _round_trip(xpersson.solve(_scene({}, spectrum, E, p0)), tmp_path / "s.nc")
    _assert_same_outputs(xpersson.analyse(bare, "leakage", **LEAKAGE), ref, bare)


def test_round_trip_of_a_seeded_sweep(tmp_path):
    spectrum, E, p0 = _seeded(4)
    spectrum["H"] = [spectrum["H"], 0.85]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = xpersson.solve(_scene({"leakage": LEAKAGE}, spectrum, [E, "3e7 Pa"], p0))
        bare = xpersson.solve(_scene({}, spectrum, [E, "3e7 Pa"], p0))
    bare = _round_trip(bare, tmp_path / "w.nc")
    _assert_same_outputs(xpersson.analyse(bare, "leakage", **LEAKAGE), ref, bare)


@pytest.fixture(scope="module")
def sweep_pair():
    """An E x H sweep over three loads solved with leakage, and the same without it."""
    scene = _scene({"leakage": LEAKAGE}, E=["5 MPa", "10 MPa", "20 MPa"])
    scene["load"]["p0"] = ["0.05 MPa", "0.1 MPa", "0.5 MPa"]
    scene["spectrum"]["H"] = [0.6, 0.8]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = xpersson.solve(scene)
        scene["analyses"] = {}
        return ref, xpersson.solve(scene)


@pytest.mark.parametrize(
    "where", [{"E": [0, 2]}, {"E": 1}, {"E": 1, "H": 0}, {"H": [1, 0], "E": [2, 0]}]
)
def test_subset_of_a_sweep_is_the_sweep_of_its_values(sweep_pair, where):
    """A sweep selected along its dimensions (lists, single values, one point, reordered):
    each point with its own swept values, the full sweep's numbers and layout. (A dimension
    kept with one value stays on every output, as a sweep of one value keeps it.)"""
    ref, bare = sweep_pair
    out = xpersson.analyse(bare.isel(where), "leakage", **LEAKAGE)
    _assert_same_outputs(out, ref.isel(where), bare.isel(where))


def test_subset_of_loads_is_the_scene_of_those_loads():
    """Loads selected from a solve: the analysis of the scene with those loads (the analyses
    treat a Dataset's loads together: the full solve agrees to round-off)."""
    loads = ["0.05 MPa", "0.1 MPa", "0.5 MPa"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        bare = xpersson.solve(_scene({}, p0=loads))
        fewer = xpersson.solve(_scene({"leakage": LEAKAGE}, p0=loads[::2]))
        one = xpersson.solve(_scene({"leakage": LEAKAGE}, p0=loads[1]))
    _assert_same_outputs(
        xpersson.analyse(bare.isel(p0=[0, 2]), "leakage", **LEAKAGE), fewer, bare.isel(p0=[0, 2])
    )
    _assert_same_outputs(
        xpersson.analyse(bare.isel(p0=1), "leakage", **LEAKAGE), one, bare.isel(p0=1)
    )


def test_subset_of_magnifications_is_refused():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = xpersson.solve(_scene({}))
    with pytest.raises(ArchiveError, match="subset along zeta"):
        xpersson.analyse(ds.isel(zeta=slice(0, 5)), "leakage")
