"""End-to-end solves: elastic limits, exact zero friction, scaling, log-slopes, superposition."""

from __future__ import annotations

import numpy as np
import pytest
from visco_testlib import elastic_scene, scene

import xpersson
from xpersson.testing import material, pressures
from xpersson_viscoelastic import Friction, ViscoelasticCoefficient

SLS = {"modulus": "sls", "E_r": "3 MPa", "E_g": "3 GPa", "relaxation_time": "1 ms"}
FRICTION = {"friction": {"tau_f": "0.5 MPa"}}


def _solve(coef, **kw):
    return xpersson.solve(scene(coef, **kw))


@pytest.mark.parametrize("closure", ["persson01", "yp08"])
@pytest.mark.parametrize(
    ("v", "E"), [("0 m/s", "3 MPa"), ("1e-14 m/s", "3 MPa"), ("1e25 m/s", "3 GPa")]
)
def test_velocity_limits_reproduce_the_elastic_solve(v, E, closure):
    ve = _solve({**SLS, "velocity": v, "closure": closure})
    el = xpersson.solve(elastic_scene(E, coefficient={"closure": closure}))
    for name in ("area_fraction", "G", "diffusion_time"):
        np.testing.assert_allclose(ve[name].values, el[name].values, rtol=1e-8, atol=0)
    if E == "3 GPa":  # sanity: the glassy solid is in far smaller contact
        assert float(ve["area_fraction"][0, -1]) < 0.01


def test_prony_limits_reproduce_the_elastic_solve():
    ve0 = _solve({"velocity": "0 m/s"})  # synthetic tread default, E_r = 3 MPa
    veinf = _solve({"velocity": "1e30 m/s"})
    el0 = xpersson.solve(elastic_scene("3 MPa"))
    elg = xpersson.solve(elastic_scene("3 GPa"))
    np.testing.assert_allclose(
        ve0["area_fraction"].values, el0["area_fraction"].values, rtol=1e-8, atol=0
    )
    np.testing.assert_allclose(
        veinf["area_fraction"].values, elg["area_fraction"].values, rtol=1e-8, atol=0
    )


@pytest.mark.parametrize(
    "coef",
    [
        {**SLS, "E_g": "3 MPa"},
        {"modulus": "prony", "delta_E": ["0 Pa", "0 Pa"], "relaxation_times": ["1 ms", "1 s"]},
    ],
)
def test_no_loss_modulus_gives_exactly_zero_viscoelastic_friction(coef):
    ds = _solve({**coef, "velocity": "1 cm/s"}, analyses=FRICTION)
    assert np.all(ds["mu_visc"].values == 0.0)
    assert np.all(ds["mu_visc_cumulative"].values == 0.0)
    assert np.all(ds["mu"].values == ds["mu_contact"].values)


@pytest.mark.parametrize("lam", [1e-3, 7.0, 1e4])
def test_scaling_moduli_and_pressures_leaves_area_and_mu_unchanged(lam):
    def run(k):
        coef = {"velocity": "3 cm/s", "E_r": f"{3e6 * k!r} Pa", "E_g": f"{3e9 * k!r} Pa"}
        sc = scene(
            coef, analyses={"friction": {"tau_f": f"{5e5 * k!r} Pa", "correction": "s_factor"}}
        )
        sc["load"] = {"p0": pressures([1e5 * k, 4e5 * k])}
        sc["material"] = material(f"{3e6 * k!r} Pa")
        return xpersson.solve(sc)

    a, b = run(1.0), run(lam)
    for name in ("area_fraction", "mu_visc", "mu_contact", "mu"):
        np.testing.assert_allclose(b[name].values, a[name].values, rtol=1e-12, atol=1e-300)


def test_log_slopes_of_mu_are_plus_one_and_minus_one():
    # SLS, tau = 1 ms, q in [1e3, 1e7] 1/m: b = q v tau << 1 for v <= 1e-9 m/s, >> 1 for
    # v >= 1e3 m/s. Small v: mu ∝ v; large v: mu ∝ 1/v (physics.md §4.4).
    def mu(v):
        ds = _solve({**SLS, "velocity": f"{v!r} m/s"}, analyses=FRICTION)
        return ds["mu_visc"].values

    for v1, sign in ((1e-9, 1.0), (1e4, -1.0)):
        slope = np.log(mu(2 * v1) / mu(v1)) / np.log(2.0)
        np.testing.assert_allclose(slope, sign, atol=1e-3)


def test_time_temperature_superposition():
    wlf = {"shift": "wlf", "T_ref": "250 K"}
    hot = _solve({"velocity": "1 cm/s", "temperature": "300 K", **wlf}, analyses=FRICTION)
    aT = float(hot["shift_factor"])
    assert aT == pytest.approx(10 ** (-17.44 * 50 / (51.6 + 50)), rel=1e-12)
    ref = _solve(
        {"velocity": f"{0.01 * aT!r} m/s", "temperature": "250 K", **wlf}, analyses=FRICTION
    )
    for name in ("area_fraction", "mu_visc", "loss_integral"):
        np.testing.assert_allclose(hot[name].values, ref[name].values, rtol=1e-12)


def test_friction_outputs_and_consistency_with_the_kernel():
    from xpersson_viscoelastic import friction_curve, synthetic_tread

    sc = scene({"velocity": "1 cm/s"}, analyses=FRICTION, output={"zeta_per_decade": 40})
    ds = xpersson.solve(sc)
    for name, spec in {**Friction.outputs, **ViscoelasticCoefficient.outputs}.items():
        assert ds[name].attrs["units"] == spec.attrs()["units"], name
        assert ds[name].dims == spec.dims, name
        if spec.valid_min is not None:
            assert ds[name].attrs["valid_min"] == spec.valid_min
    assert ds["sliding_speed"].attrs["units"] == "m s^-1"
    # mu_contact = tau_f A(zeta_max) / p0
    np.testing.assert_allclose(
        ds["mu_contact"].values,
        5e5 * ds["area_fraction"].isel(zeta=-1).values / ds["p0"].values,
        rtol=1e-14,
    )
    # the analysis (cubic Stieltjes rule on the output grid) and the kernel (closed-form area
    # at the quadrature nodes) agree to the grid's accuracy (fourth order; 40 per decade)
    ref = friction_curve(
        xpersson.scene.Scene(sc).resolve().psd, synthetic_tread(), 0.5, ds["p0"].values, [0.01]
    )
    np.testing.assert_allclose(ds["mu_visc"].values, ref["mu_visc"][0, 0], rtol=1e-6)
    np.testing.assert_allclose(
        ds["area_fraction"].isel(zeta=-1).values, ref["area_fraction"][0, 0], rtol=1e-10
    )


def test_velocity_shear_law_and_contact_cutoff():
    law = {"tau_f": "1 MPa", "shear_law": "velocity", "c": 0.1, "v_star": "1 mm/s", "zeta_c": 100}
    ds = _solve({"velocity": "1 m/s"}, analyses={"friction": law})
    assert float(ds["frictional_shear_stress"]) == pytest.approx(1e6 * np.exp(-0.1 * 9.0))
    A_c = ds["area_fraction"].sel(zeta=100, method="nearest")
    np.testing.assert_allclose(ds["contact_area_cutoff"].values, A_c.values, rtol=1e-12)


def test_an_analysis_after_friction_leaves_its_outputs_writable():
    # with zeta_c, friction's mu_visc is a view of mu_visc_cumulative (its last column): the
    # guard that hands the next analysis read-only variables must make both writable again
    # (the fuzz campaign of 2026-12-01 stopped here: "cannot set WRITEABLE flag")
    law = {"zeta_c": 10.0}
    ds = _solve({"velocity": "1 cm/s"}, analyses={"friction": law, "contact_area": {}})
    cumulative = ds["mu_visc_cumulative"].transpose("p0", "zeta").values
    np.testing.assert_array_equal(ds["mu_visc"].values, cumulative[:, -1])
    assert np.all(ds["mu_visc"].values > 0)
    for name in ("mu_visc", "mu_visc_cumulative", "area_fraction"):
        ds[name].values[...] = 0.0  # the user's Dataset is writable


def test_bad_input_is_refused_before_work(monkeypatch):
    with pytest.raises(ValueError, match=r"coefficient\.velocity: -1 m/s .*\[0, inf\] m/s"):
        _solve({"velocity": "-1 m/s"})
    with pytest.raises(ValueError, match=r"coefficient\.velocity: required"):
        _solve({})
    with pytest.raises(ValueError, match=r"E_g: .* below E_r"):
        _solve({**SLS, "E_g": "1 MPa", "velocity": "1 m/s"})
    with pytest.raises(ValueError, match=r"analyses.*loss_integral"):
        xpersson.solve(elastic_scene("3 MPa", analyses=FRICTION))
    from xpersson import engine

    def no_work(*args, **kwargs):
        raise AssertionError("the engine ran before the analysis refused the scene")

    monkeypatch.setattr(engine, "solve_batch", no_work)
    with pytest.raises(
        ValueError,
        match=r"analyses\.friction: zeta_c: 100000 exceeds .*"
        r"allowed \[1, 10000\]",
    ):
        _solve({"velocity": "1 m/s"}, analyses={"friction": {"zeta_c": 1e5}})


@pytest.mark.parametrize("cls", [ViscoelasticCoefficient, Friction])
def test_check_plugin(cls):
    testing = pytest.importorskip("xpersson.testing")
    over = {"coefficient": {"model": "viscoelastic", "velocity": "1 cm/s"}}
    params = {"velocity": 0.01} if cls is ViscoelasticCoefficient else None
    report = testing.check_plugin(cls, params, scene=None if params else over)
    assert report["metadata"] == "ok" and report["pickle"] == "ok"


def test_model_files_end_to_end(tmp_path):
    from xpersson_viscoelastic import sls

    model = sls(3e6, 3e9, 1e-3)
    f = np.geomspace(1e-4, 1e10, 400) / (2 * np.pi * 1e-3)
    E = model.modulus(2 * np.pi * f)
    table = zip(f.tolist(), (E.real / 1e6).tolist(), (E.imag / 1e6).tolist(), strict=True)
    rows = "\n".join(f"{a!r}, {b!r}, {c!r}" for a, b, c in table)
    mc = tmp_path / "sls_curve.txt"
    mc.write_text("# SLS sampled\nf [Hz], E_storage [MPa], E_loss [MPa]\n" + rows + "\n")
    pf = tmp_path / "modes.txt"
    pf.write_text("tau [ms], delta_E [GPa]\n1, 2.997\n2, 0\n")
    ref = _solve({**SLS, "velocity": "1 cm/s"}, analyses=FRICTION)
    pr = _solve(
        {"modulus": "prony", "prony_file": str(pf), "velocity": "1 cm/s"}, analyses=FRICTION
    )
    cu = _solve(
        {"modulus": "master_curve", "master_curve": str(mc), "velocity": "1 cm/s"},
        analyses=FRICTION,
    )
    for name in ("area_fraction", "mu_visc"):
        np.testing.assert_allclose(pr[name].values, ref[name].values, rtol=1e-12)
        np.testing.assert_allclose(cu[name].values, ref[name].values, rtol=3e-3)
