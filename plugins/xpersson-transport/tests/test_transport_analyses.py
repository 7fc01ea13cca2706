"""The analyses through xpersson.solve: identities on the solved Dataset, metadata, contract."""

from __future__ import annotations

import math

import numpy as np
import pytest
from transport_testlib import AIR, CU_RHO, E_STAR, electrical, scene, thermal

import xpersson
from xpersson.plugins import Analysis
from xpersson_transport import _physics as ph
from xpersson_transport.plugins import ElectricalContact, ThermalContact

LOADS = [1e4, 1e5, 1e6]


@pytest.fixture(scope="module")
def ds():
    ana = {"electrical_contact": electrical(nominal_area="1 cm**2"),
           "thermal_contact": thermal(**AIR)}  # fmt: skip
    return xpersson.solve(scene(LOADS, ana))


@pytest.mark.parametrize("cls", [ElectricalContact, ThermalContact])
def test_metadata(cls):
    assert issubclass(cls, Analysis) and not cls.abstract
    assert set(cls.provides) == set(cls.outputs)
    assert "contact_stiffness" in cls.requires
    assert all(r.startswith("10.") for r in cls.references)


def test_units_are_cf(ds):
    units = {
        "electrical_constriction_conductance": "S m^-2", "electrical_contact_resistance": "ohm",
        "holm_conductance": "S m^-2", "thermal_contact_conductance": "W m^-2 K^-1",
        "thermal_gas_conductance": "W m^-2 K^-1", "thermal_contact_resistance": "K W^-1",
        "gas_jump_length": "m",
    }  # fmt: skip
    for name, unit in units.items():
        assert ds[name].attrs["units"] == unit and ds[name].attrs["long_name"], name


def test_conductance_over_stiffness_is_the_analogy_constant(ds):
    K = ds["contact_stiffness"].values
    g_e = ds["electrical_constriction_conductance"].values
    g_t = ds["thermal_constriction_conductance"].values
    np.testing.assert_allclose(g_e / K, 2.0 / (2 * CU_RHO * E_STAR), rtol=1e-14)
    np.testing.assert_allclose(g_t / K, 2.0 * 200.0 / E_STAR, rtol=1e-14)  # kappa_s = 200
    # no film: contact = constriction; resistance of 1 cm^2 = 1/(g A0)
    # (1/g)^-1: equal to rounding
    np.testing.assert_allclose(ds["electrical_contact_conductance"].values, g_e, rtol=1e-15)
    np.testing.assert_allclose(ds["electrical_contact_resistance"].values, 1 / (g_e * 1e-4),
                               rtol=1e-15)  # fmt: skip
    assert np.all(np.diff(g_e) > 0)  # conductance grows with load


def test_scaling_with_moduli_at_fixed_reduced_load():
    """Elastic Persson theory: K(p0; E*) = E* k(p0/E*) on a fixed spectrum, so at p0 ~ E* the
    constriction conductance is independent of the modulus (to the solver's tolerance) and
    scales with 1/(rho_1 + rho_2) and with kappa_s exactly."""
    a = xpersson.solve(scene(LOADS, {"electrical_contact": electrical()}))
    b = xpersson.solve(scene(np.multiply(LOADS, 7.0), {"electrical_contact": electrical(
        3 * CU_RHO, 3 * CU_RHO)}, E="70 MPa"))  # fmt: skip
    g_a = a["electrical_constriction_conductance"].values
    g_b = b["electrical_constriction_conductance"].values
    np.testing.assert_allclose(g_b, g_a / 3.0, rtol=1e-6)


def test_single_load_scene():
    sc = scene([2e5], {"electrical_contact": electrical(), "thermal_contact": thermal(**AIR)})
    sc["load"]["p0"] = "2e5 Pa"  # a scalar load: p0 is a scalar coordinate
    ds = xpersson.solve(sc)
    assert ds["thermal_contact_conductance"].dims == ()
    g = float(ds["electrical_constriction_conductance"])
    assert g == pytest.approx(float(ds["contact_stiffness"]) / (CU_RHO * E_STAR), rel=1e-14)


def test_film_in_series_on_the_finest_contact_area():
    film = {"film_resistivity": "1e3 ohm*m", "film_thickness": "2 nm", "nominal_area": "1 mm**2"}
    ds = xpersson.solve(scene(LOADS, {"electrical_contact": electrical(**film)}))
    A = ds["area_fraction"].isel(zeta=-1).values
    r_f = 1e3 * 2e-9 / (A * 1e-6)  # rho_f d / (A_c A0)
    np.testing.assert_allclose(ds["electrical_film_resistance"].values, r_f, rtol=1e-14)
    g_c = ds["electrical_constriction_conductance"].values
    np.testing.assert_allclose(ds["electrical_contact_resistance"].values,
                               1 / (g_c * 1e-6) + r_f, rtol=1e-14)  # fmt: skip
    g = ds["electrical_contact_conductance"].values
    np.testing.assert_allclose(1 / g, 1 / g_c + 1e3 * 2e-9 / A, rtol=1e-14)


def test_holm_spots_beside_barber(ds):
    """Holm's sum of the spots seen at zeta equals Barber's conductance at holm_magnification
    (or comes closest there); at the finest scale the non-interacting sum exceeds Barber (the
    spots interact)."""
    g_b = ds["electrical_constriction_conductance"].values
    g_h = ds["holm_conductance"].values
    zeta = ds["zeta"].values
    z_h, r_h = ds["holm_magnification"].values, ds["holm_ratio"].values
    for i in range(len(LOADS)):
        ratio = np.exp(np.interp(np.log(z_h[i]), np.log(zeta), np.log(g_h[i] / g_b[i])))
        assert ratio == pytest.approx(r_h[i], rel=1e-12)
        assert np.all(np.abs(np.log(g_h[i] / g_b[i])) >= abs(np.log(r_h[i])) - 1e-12)
    assert g_h[0, -1] > 100 * g_b[0] and g_h[1, -1] > 10 * g_b[1]
    q_L = 1e3
    np.testing.assert_allclose(ds["holm_spot_radius"].values, math.pi / 2 / (z_h * q_L),
                               rtol=1e-14)  # fmt: skip


def test_holm_agrees_with_barber_at_the_roll_off_for_sparse_contact():
    """Persson (2022): the stiffness, so the resistance, is set by the long-wavelength
    roughness. At low load Holm's spots come closest to Barber's value near the roll-off
    (zeta ~ q_r/q_L = 10) and there agree within a factor 1.6 with c_r = pi/2, for every
    load, while the spot sum at zeta_1 exceeds it by 1e2-1e3."""
    ana = {"electrical_contact": electrical(), "contact_stiffness": {"s_factor": "closure"}}
    ds = xpersson.solve(scene([3e2, 1e3, 3e3], ana, E="10 GPa"))  # Persson 2007's K
    z_h, r_h = ds["holm_magnification"].values, ds["holm_ratio"].values
    assert np.all((z_h > 5) & (z_h < 30)) and np.all((r_h > 1.0) & (r_h < 1.6))
    over = ds["holm_conductance"].isel(zeta=-1) / ds["electrical_constriction_conductance"]
    assert np.all(over.values > 100)


def test_thermal_parts_add_up(ds):
    g = ds["thermal_contact_conductance"].values
    parts = sum(ds[f"thermal_{n}_conductance"].values for n in ("solid", "gas", "radiation"))
    np.testing.assert_allclose(g, parts, rtol=1e-15)
    lam = float(ds["gas_jump_length"])
    assert lam == pytest.approx(ph.jump_length(68e-9), rel=1e-15)
    assert np.all(ds["thermal_gas_conductance"].values > 0)
    np.testing.assert_allclose(ds["thermal_contact_resistance"].values, 1 / (g * 1e-4), rtol=1e-15)


def test_gas_part_is_the_gap_distribution_of_gap_pdf():
    """The CDF route on a geometric grid equals the product integral of the Dataset's
    gap_pdf (same bins) once that is sampled finely (32768 points): within 0.3 %. gap_pdf's
    default 256 points would overestimate it (a factor 3 at p0 = 10 MPa on the heat sink)."""
    ana = {"thermal_contact": thermal(**AIR), "gap_pdf": {"u_points": 32768, "n_bins": 200}}
    ds = xpersson.solve(scene(LOADS, ana))
    lam = float(ds["gas_jump_length"])
    fine = ph.gas_gap_conductance(ds["u"].values, ds["gap_pdf"].values, 0.026, lam)
    np.testing.assert_allclose(ds["thermal_gas_conductance"].values, fine, rtol=3e-3)
    # the geometric grid is converged
    ana["thermal_contact"]["u_per_decade"] = 400
    ds4 = xpersson.solve(scene(LOADS, ana))
    np.testing.assert_allclose(ds4["thermal_gas_conductance"].values,
                               ds["thermal_gas_conductance"].values, rtol=1e-4)  # fmt: skip


def test_vacuum_gap_is_zero_and_gas_tends_to_the_log_continuum():
    loads = 1e5
    vac = xpersson.solve(scene(loads, {"thermal_contact": thermal()}))
    assert float(vac["thermal_gas_conductance"]) == 0.0
    assert float(vac["gas_jump_length"]) == 0.0
    g = []
    for mfp in ("1e-13 m", "1e-14 m", "1e-15 m"):
        air = dict(AIR, gas_mean_free_path=mfp)
        ana = {"thermal_contact": thermal(**air), "gap_pdf": {"u_points": 16, "n_bins": 200}}
        d = xpersson.solve(scene(loads, ana))
        g.append(float(d["thermal_gas_conductance"]))
    # continuum limit: the gap density at u = 0+ makes g grow like -kappa pdf(0) ln(Lambda)
    pdf0 = float(d["gap_pdf"].isel(u=0))
    slope = (g[2] - g[1]) / math.log(10.0)
    assert slope == pytest.approx(0.026 * pdf0, rel=2e-3)
    assert g[0] < g[1] < g[2]


def test_radiation_on_the_non_contact_area():
    black = thermal(emissivity_1=1.0, emissivity_2=1.0, temperature="300 K")
    ds = xpersson.solve(scene(1e4, {"thermal_contact": black}))
    A = float(ds["area_fraction"].isel(zeta=-1))
    rad = 4 * ph.SIGMA_SB * 300.0**3 * (1 - A)
    assert float(ds["thermal_radiation_conductance"]) == pytest.approx(rad, rel=1e-14)


def test_check_plugin_contract():
    from xpersson.testing import check_plugin

    for cls in (ElectricalContact, ThermalContact):
        check_plugin(cls, scene={"load": {"p0": ["20 kPa", "100 kPa"]}})


def test_material_parameters_sweep():
    """A swept resistivity becomes a Dataset dimension; g scales as 1/(rho_1 + rho_2)."""
    ana = {"electrical_contact": electrical(rho2=CU_RHO)}
    ana["electrical_contact"]["resistivity_1"] = ["1.7e-8 ohm*m", "5.1e-8 ohm*m"]
    ds = xpersson.solve(scene([1e4, 1e5], ana))
    g = ds["electrical_constriction_conductance"].transpose("resistivity_1", "p0").values
    np.testing.assert_array_equal(ds["resistivity_1"].values, [1.7e-8, 5.1e-8])
    np.testing.assert_allclose(g[1] / g[0], 2 * CU_RHO / (6.8e-8), rtol=1e-12)


def test_from_sparse_to_full_contact():
    """Loads from A = 1e-3 to A ~ 1 (physics.md §1.4 scene): every output finite and inside
    its range, the solid conductance grows with load; near full contact the gas part falls
    again (the non-contact area closes) and stays below kappa_g (1 - A) / Lambda."""
    loads = np.geomspace(1e3, 1e7, 9)
    ana = {"electrical_contact": electrical(), "thermal_contact": thermal(**AIR)}
    ds = xpersson.solve(scene(loads, ana))
    for name in list(ElectricalContact.outputs) + list(ThermalContact.outputs):
        v = ds[name].values
        assert np.all(np.isfinite(v)) and np.all(v >= 0), name
    assert np.all(np.diff(ds["thermal_solid_conductance"].values) > 0)
    A = ds["area_fraction"].isel(zeta=-1).values
    assert A[0] < 0.02 and A[-1] > 0.999
    open_area = ds["non_contact_fraction"].isel(zeta=-1).values  # 1 - A without cancellation
    bound = 0.026 * open_area / float(ds["gas_jump_length"])
    assert np.all(ds["thermal_gas_conductance"].values <= bound * (1 + 1e-9))
    assert np.argmax(ds["thermal_gas_conductance"].values) < loads.size - 1


def test_full_contact_has_no_constriction():
    """A soft flat with 1 nm roughness pressed into full contact (contact_stiffness NaN,
    contact_stiffness_status 1): no constriction. The constriction resistance is 0, the
    conductances per area are NaN with a meaning naming the status (never inf); with a film the
    contact conductance is the film's alone, A_c/(rho_f d), and its resistance the film's."""
    ana = {
        "electrical_contact": electrical(film_thickness=["0 m", "2 nm"],
                                         film_resistivity="1e-3 ohm*m"),
        "thermal_contact": thermal(**AIR, emissivity_1=0.5, emissivity_2=0.5,
                                   film_thickness="2 nm", film_conductivity="1 W/(m*K)"),
    }  # fmt: skip
    spectrum = {"q_L": "1e5 1/m", "q_r": "1e6 1/m", "q_1": "1e7 1/m", "h_rms": "1 nm"}
    ds = xpersson.solve(scene([1e3, 1e5, 3e5], ana, E="1 MPa", **spectrum))
    shape = ds["film_thickness"] * ds["p0"]

    def v(name):  # (film_thickness: no film, 2 nm; p0)
        da = ds[name].isel(zeta=-1) if "zeta" in ds[name].dims else ds[name]
        return da.broadcast_like(shape).transpose("film_thickness", "p0").values

    full = v("contact_stiffness_status")[0] == 1
    np.testing.assert_array_equal(full, [False, True, True])
    for name in ("electrical_contact_status", "thermal_contact_status"):
        np.testing.assert_array_equal(v(name) == 1, [full, full])
    g_c = v("electrical_constriction_conductance")
    assert np.all(np.isnan(g_c[:, full])) and np.all(np.isfinite(g_c[:, ~full]))
    comment = ds["electrical_constriction_conductance"].attrs["comment"]
    assert "contact_stiffness_status 1" in comment
    assert np.all(v("electrical_constriction_resistance")[:, full] == 0.0)
    g, r = v("electrical_contact_conductance"), v("electrical_contact_resistance")
    assert np.all(np.isnan(g[0, full])) and np.all(r[0, full] == 0.0)  # no film
    a_c = v("area_fraction")[0]
    np.testing.assert_allclose(g[1, full], a_c[full] / (1e-3 * 2e-9), rtol=1e-12)  # film alone
    np.testing.assert_allclose(r[1, full], v("electrical_film_resistance")[1, full])
    for name in ("holm_magnification", "holm_ratio", "holm_spot_radius"):
        assert np.all(np.isnan(v(name)[:, full])) and "status 1" in ds[name].attrs["comment"]
    assert np.all(np.isfinite(ds["holm_conductance"].values))
    # thermal, with a film: solid = film alone; total = film + gas + radiation, all finite
    solid = v("thermal_solid_conductance")[0]
    np.testing.assert_allclose(solid[full], a_c[full] * 1.0 / 2e-9, rtol=1e-12)
    assert np.all(np.isnan(v("thermal_constriction_conductance")[0, full]))
    parts = solid + v("thermal_gas_conductance")[0] + v("thermal_radiation_conductance")[0]
    np.testing.assert_allclose(v("thermal_contact_conductance")[0], parts, rtol=1e-14)
    np.testing.assert_allclose(v("thermal_contact_resistance")[0], 1 / (parts * 1e-4), rtol=1e-14)


def test_full_contact_thermal_without_film_is_unbounded():
    """Without a film the solid path has no resistance at full contact: the solid and total
    conductances are NaN (unbounded), the resistance 0; the gas and radiation parts stay finite."""
    spectrum = {"q_L": "1e5 1/m", "q_r": "1e6 1/m", "q_1": "1e7 1/m", "h_rms": "1 nm"}
    ana = {"thermal_contact": thermal(**AIR, emissivity_1=0.5, emissivity_2=0.5)}
    ds = xpersson.solve(scene([1e3, 3e5], ana, E="1 MPa", **spectrum))
    np.testing.assert_array_equal(ds["thermal_contact_status"].values, [0, 1])
    for name in ("thermal_solid_conductance", "thermal_contact_conductance"):
        v = ds[name].values
        assert np.isfinite(v[0]) and np.isnan(v[1]), name
        assert "contact_stiffness_status 1" in ds[name].attrs["comment"]
    np.testing.assert_array_equal(ds["thermal_contact_resistance"].values[1], 0.0)
    for name in ("thermal_gas_conductance", "thermal_radiation_conductance"):
        assert np.all(np.isfinite(ds[name].values) & (ds[name].values >= 0)), name
