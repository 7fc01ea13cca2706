"""End-to-end elastic Persson theory through ``xpersson.solve`` (physics.md §1)."""

from __future__ import annotations

import copy
import csv
import math

import numpy as np
import pytest
from scipy.special import erf

import xpersson

# physics.md §1.4: p0 -> (G(zeta_1), A/A0, kappa p0/(E* h'), full-contact sqrt(V))
TABLE_14 = {
    1e4: (1930.095, 1.284154e-2, 1.284209e-2, 6.213043e5),
    1e5: (19.30095, 0.1278686, 0.1284209, 6.213043e5),
    1e6: (0.1930095, 0.8924967, None, 6.213043e5),
}


def test_reference_table_1_4(scene):
    ds = xpersson.solve(scene)
    assert ds.attrs["status"] == "success"
    last = ds.isel(zeta=-1)
    assert float(ds.zeta[-1]) == pytest.approx(1e5)
    for p0, (G, A, lin, sqrtV) in TABLE_14.items():
        row = last.sel(p0=p0)
        assert float(row.G) == pytest.approx(G, rel=5e-7)
        assert float(row.area_fraction) == pytest.approx(A, rel=5e-7)
        slope = float(ds.rms_slope)
        if lin is not None:
            kappa_lin = math.sqrt(8 / math.pi) * p0 / (float(ds.E_star) * slope)
            assert kappa_lin == pytest.approx(lin, rel=5e-7)
        assert float(ds.E_star) * slope / 2 == pytest.approx(sqrtV, rel=5e-7)
    assert float(ds.rms_slope) == pytest.approx(0.0931956, rel=5e-7)


def test_area_monotone_and_unity_at_zeta_one(scene):
    scene["load"]["p0"] = {"start": "1 Pa", "stop": "10 MPa", "num": 15}
    ds = xpersson.solve(scene)
    a = ds.area_fraction.values
    assert np.all(a[:, 0] == 1.0)
    assert np.all(np.diff(a, axis=1) <= 0)
    # strictly monotone where it can be resolved: 1 - A (from erfc) grows at every step
    nc = ds.non_contact_fraction.values
    resolvable = nc[:, :-1] > 1e-290  # below that erfc underflows (p0 >> sqrt(V))
    assert np.all(np.diff(nc, axis=1)[resolvable] > 0)
    assert np.all(a > 0)


def test_pdf_identities_load_conservation_and_balance(scene):
    scene["load"]["p0"] = ["1e5 Pa", "1e6 Pa"]
    scene["output"] = {"pressure_pdf": True, "p_points": 4001, "zeta_per_decade": 2}
    ds = xpersson.solve(scene)
    p = ds.p.values
    for p0 in (1e5, 1e6):
        P = ds.P.sel(p0=p0)
        mass = np.trapezoid(P.values, p, axis=-1)
        load = np.trapezoid(P.values * p, p, axis=-1)
        a = ds.area_fraction.sel(p0=p0).values
        # zeta = 1 is a delta: skip it in quadrature checks
        np.testing.assert_allclose(mass[1:], a[1:], rtol=2e-5)
        np.testing.assert_allclose(load[1:] / p0, 1.0, rtol=2e-5)
        assert np.all(P.values >= 0)
    assert float(abs(ds.load_balance).max()) < 1e-10
    assert float(abs(ds.probability_balance).max()) < 1e-12


def test_full_contact_std_equals_E_star_slope_over_two(scene):
    # G << 1: Gaussian of std E* h'_rms / 2 around p0 (physics.md §1.3-3)
    scene["load"]["p0"] = "5 MPa"
    scene["output"] = {"pressure_pdf": True, "p_points": 6001}
    ds = xpersson.solve(scene)
    P = ds.P.isel(zeta=-1).values
    p = ds.p.values
    mean = np.trapezoid(P * p, p) / np.trapezoid(P, p)
    std = math.sqrt(np.trapezoid(P * (p - mean) ** 2, p) / np.trapezoid(P, p))
    assert std == pytest.approx(float(ds.E_star) * float(ds.rms_slope) / 2, rel=1e-6)
    # 1 - A is tiny and must come from erfc, not 1 - erf
    nc = float(ds.non_contact_fraction.isel(zeta=-1))
    G = float(ds.G.isel(zeta=-1))
    assert 0 < nc < 1e-12
    assert nc == pytest.approx(math.erfc(1 / (2 * math.sqrt(G))), rel=1e-12)


def test_small_load_kappa_and_rayleigh_shape(scene):
    scene["load"]["p0"] = "1 Pa"
    scene["output"] = {"pressure_pdf": True, "p_points": 3001}
    ds = xpersson.solve(scene)
    last = ds.isel(zeta=-1)
    a = float(last.area_fraction)
    slope = float(ds.rms_slope)
    E_star = float(ds.E_star)
    lin = math.sqrt(8 / math.pi) * 1.0 / (E_star * slope)
    assert a / lin == pytest.approx(1.0, abs=1e-6)
    V = 2 * float(last.diffusion_time)
    p = ds.p.values
    rayleigh = p / V * np.exp(-(p**2) / (2 * V))
    cond = last.P.values / a
    assert np.max(np.abs(cond - rayleigh)) * math.sqrt(V) < 1e-5


def _zhou_scene(closure: str, gamma: float | None, loads) -> dict:
    coef = {"model": "elastic", "closure": closure}
    if gamma is not None:
        coef["gamma"] = gamma
    return {
        "spectrum": {
            "model": "self_affine",
            "H": 0.8,
            "q_L": "1e4 1/m",
            "q_1": "1e6 1/m",
            "h_rms": "6 um",
        },
        "material": {"E": "0.75 Pa", "nu": 0.5},
        "load": {"p0": [f"{p!r} Pa" for p in loads]},
        "coefficient": coef,
        "output": {"zeta": [1.0, 100.0]},
        "solver": {"rtol": 1e-8},
    }


@pytest.mark.parametrize(
    ("column", "closure", "gamma", "rtol"),
    [
        ("A_Persson01", "persson01", None, 1e-6),
        ("A_YP08_g0.45", "yp08", 0.45, 1e-3),
        ("A_WM17_g5/9", "wm17", 5 / 9, 1e-3),
        ("A_Xu24_g0.45", "xu24", 0.45, 1e-3),
    ],
)
def test_refdata_persson_variants_area(refdata, column, closure, gamma, rtol):
    rows = list(
        csv.DictReader(
            line for line in open(refdata / "persson_variants_area_octave.csv") if line[0] != "#"
        )
    )
    loads = [float(r["p_bar"]) for r in rows]
    expected = np.array([float(r[column]) for r in rows])
    ds = xpersson.solve(_zhou_scene(closure, gamma, loads))
    got = ds.area_fraction.isel(zeta=-1).values
    np.testing.assert_allclose(got, expected, rtol=rtol)


def test_surface_topography_convention_gives_same_area(tmp_path, scene):
    from xpersson.physics.psd import SelfAffineRollOff

    psd = SelfAffineRollOff.from_h_rms(1e-6, 0.8, 1e3, 1e4, 1e8)
    q = np.geomspace(1e3, 1e8, 400)
    q = np.unique(np.concatenate([q, [1e4]]))
    np.savetxt(tmp_path / "persson.txt", np.c_[q, psd.C(q)], header="q [1/m], C [m^4]")
    np.savetxt(
        tmp_path / "st.csv",
        np.c_[q * 1e-6, psd.C(q) * (2 * np.pi) ** 2 * 1e24],
        delimiter=",",
        header="q [1/um], C [um^4]",
    )
    base = copy.deepcopy(scene)
    base["spectrum"] = {"model": "tabulated", "file": str(tmp_path / "persson.txt")}
    st = copy.deepcopy(scene)
    st["spectrum"] = {
        "model": "tabulated",
        "file": str(tmp_path / "st.csv"),
        "convention": "surface_topography",
        "q_unit": "1/um",
        "C_unit": "um**4",
    }
    a1 = xpersson.solve(base).area_fraction.isel(zeta=-1).values
    a2 = xpersson.solve(st).area_fraction.isel(zeta=-1).values
    np.testing.assert_allclose(a2, a1, rtol=1e-12)
    # and both match the analytic model
    a0 = xpersson.solve(scene).area_fraction.isel(zeta=-1).values
    np.testing.assert_allclose(a1, a0, rtol=1e-10)
    # the (2 pi)^2 bug: reading the ST file as Persson's changes the area a lot
    wrong = copy.deepcopy(st)
    wrong["spectrum"]["convention"] = "persson"
    a3 = xpersson.solve(wrong).area_fraction.isel(zeta=-1).values
    assert np.all(np.abs(a3 / a1 - 1) > 0.5)


def test_closure_area_exceeds_persson01(scene):
    base = xpersson.solve(scene).area_fraction.isel(zeta=-1).values
    for closure in ("yp08", "wm17", "xu24"):
        scene["coefficient"] = {"closure": closure}
        ds = xpersson.solve(scene)
        a = ds.area_fraction.isel(zeta=-1).values
        assert np.all(a > base)
        G = ds.G.isel(zeta=-1).values
        np.testing.assert_allclose(
            a,
            erf(
                1
                / (2 * np.sqrt(ds.effective_diffusion_time.isel(zeta=-1).values / ds.p0.values**2))
            ),
            rtol=1e-12,
        )
        assert np.all(G > 0)


def test_contact_area_analysis_kappa_and_mean_pressure(scene):
    scene["load"]["p0"] = ["1 Pa", "1 MPa"]
    scene["analyses"] = {"contact_area": {}}
    ds = xpersson.solve(scene)
    kappa = ds.kappa.values
    assert kappa[0] == pytest.approx(math.sqrt(8 / math.pi), rel=1e-6)
    assert kappa[1] < kappa[0]  # sub-linear area growth at high load
    np.testing.assert_allclose(
        ds.mean_contact_pressure.values * ds.area_fraction.values,
        np.broadcast_to(ds.p0.values[:, None], ds.area_fraction.shape),
        rtol=1e-14,
    )
    assert ds.kappa.attrs["units"] == "1"
