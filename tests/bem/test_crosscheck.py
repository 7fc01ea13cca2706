"""xpersson.crosscheck and `xpersson crosscheck`: schema, ratios, schedulers, refusals."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

import xpersson
from xpersson.bem import CrosscheckError
from xpersson.cli import main

tamaas = pytest.importorskip("tamaas")

SCENE = {
    "spectrum": {"model": "self_affine", "H": 0.8, "q_L": "1e3 1/m", "q_r": "2e3 1/m",
                 "q_1": "4e3 1/m", "h_rms": "1 um"},
    "material": {"E": "10 MPa", "nu": 0.5},
    "load": {"p0": ["2 kPa", "5 kPa"]},
    "analyses": {"electrical_contact": {"resistivity_1": "1.7e-8 ohm*m",
                                        "resistivity_2": "1.7e-8 ohm*m"}},
}  # fmt: skip
TOML = """
[spectrum]
model = "self_affine"
H = 0.8
q_L = "1e3 1/m"
q_r = "2e3 1/m"
q_1 = "4e3 1/m"
h_rms = "1 um"
[material]
E = "10 MPa"
nu = 0.5
[load]
p0 = ["2 kPa", "5 kPa"]
"""
COMPARED = ("area_fraction", "mean_gap", "contact_stiffness", "electrical_constriction_conductance")


@pytest.fixture(scope="module")
def ds() -> object:
    return xpersson.crosscheck(SCENE, realisations=2, grid=32, seed=3)


def test_schema_units_provenance(ds: object) -> None:
    for name in COMPARED:
        for suffix in ("", "_se", "_theory", "_ratio", "_realisations"):
            assert name + suffix in ds.data_vars, name + suffix
        assert ds[name].attrs["units"] == ds[name + "_theory"].attrs["units"]
        assert ds[name + "_ratio"].attrs["units"] == "1"
    assert {"gap_pdf", "gap_pdf_theory", "gap_pdf_l1", "bem_converged"} <= set(ds.data_vars)
    assert all("units" in ds[v].attrs for v in ds.data_vars)
    assert ds.attrs["tamaas_version"] == tamaas.__version__
    assert (ds.attrs["crosscheck_seed"], ds.attrs["crosscheck_grid"]) == (3, 32)
    assert ds.attrs["crosscheck_realisations"] == 2
    assert ds["bem_converged"].values.all()


def test_ratio_is_theory_over_bem_mean(ds: object) -> None:
    for name in COMPARED:
        per = ds[name + "_realisations"].values
        np.testing.assert_allclose(ds[name].values, per.mean(axis=0), rtol=1e-13)
        se = per.std(axis=0, ddof=1) / np.sqrt(per.shape[0])
        np.testing.assert_allclose(ds[name + "_se"].values, se, rtol=1e-10)
        np.testing.assert_allclose(
            ds[name + "_ratio"].values, ds[name + "_theory"].values / ds[name].values, rtol=1e-13
        )


def test_barber_conductance_ratio_equals_stiffness_ratio(ds: object) -> None:
    """Plugin and BEM both obey g = c K with the same c: the two ratios are one number."""
    np.testing.assert_allclose(
        ds["electrical_constriction_conductance_ratio"].values,
        ds["contact_stiffness_ratio"].values,
        rtol=1e-9,
    )


def test_theory_is_the_scene_on_the_bem_band(ds: object) -> None:
    """The band fits the grid here (q_1 = q_L 32 / 8): the theory equals a plain solve."""
    plain = xpersson.solve(SCENE)
    np.testing.assert_allclose(
        ds["area_fraction_theory"].values, plain["area_fraction"].isel(zeta=-1).values, rtol=1e-9
    )
    assert ds.attrs["notes"] == "none"


def test_serial_equals_dask(ds: object) -> None:
    pytest.importorskip("dask")
    other = xpersson.crosscheck(SCENE, realisations=2, grid=32, seed=3, scheduler="threads")
    for name in ds.data_vars:
        np.testing.assert_array_equal(ds[name].values, other[name].values)


def test_cli_table_and_archive(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    scene = tmp_path / "s.toml"
    scene.write_text(TOML)
    out = tmp_path / "cc.nc"
    argv = ["crosscheck", str(scene), "-o", str(out), "--grid", "32", "--realisations", "2"]
    assert main(argv) == 0
    cap = capsys.readouterr()
    assert "theory / BEM" in cap.out and "area_fraction" in cap.out
    assert cap.err.startswith("crosscheck: 2 realisation(s) x 32^2 grid")
    back = xpersson.open_dataset(out)
    assert back["area_fraction_ratio"].attrs["units"] == "1"


def _one_error_line(argv: list[str], capsys: pytest.CaptureFixture[str]) -> str:
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    return err[0]


def test_missing_tamaas_is_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setitem(sys.modules, "tamaas", None)
    scene = tmp_path / "s.toml"
    scene.write_text(TOML)
    line = _one_error_line(["crosscheck", str(scene)], capsys)
    assert 'pip install "xpersson[bem]"' in line


@pytest.mark.parametrize(
    ("change", "words"),
    [
        ({"boundary": {"model": "plastic_scale_dependent", "Y1": "1 MPa", "n": 0.1}},
         "scale-dependent yield"),
        ({"coefficient": {"model": "viscoelastic", "modulus": "prony", "E_r": "3 MPa",
                          "E_g": "3 GPa", "velocity": "1 cm/s"}}, "viscoelastic"),
        ({"boundary": {"model": "dmt", "work_of_adhesion": "0.01 J/m**2", "range": "1 nm"}},
         "law 'lj93'"),
        ({"material": {"E": ["5 MPa", "10 MPa"], "nu": 0.5}}, "sweeps parameters"),
        ({"boundary": {"model": "adhesive", "work_of_adhesion": "0.05 J/m**2",
                       "range": "0.5 nm"}}, "cohesive zone"),
    ],
)  # fmt: skip
def test_physics_the_bem_cannot_do(change: dict, words: str) -> None:
    scene = {k: v for k, v in SCENE.items() if k != "analyses"} | change
    with pytest.raises(CrosscheckError, match=words):
        xpersson.crosscheck(scene, realisations=1, grid=32)


def test_grid_over_budget_is_one_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from xpersson import memory

    scene = tmp_path / "s.toml"
    scene.write_text(TOML)
    memory.set_budget("200 MB")
    try:
        line = _one_error_line(["crosscheck", str(scene), "--grid", "2048"], capsys)
    finally:
        memory.set_budget(None)
    assert "memory budget" in line and "--grid" in line
    line = _one_error_line(["crosscheck", str(scene), "--grid", "33"], capsys)
    assert "grid [1] must be an even integer" in line
