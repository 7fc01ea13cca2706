"""``dmt``: traction-gap laws, the gap integral, the self-consistent repulsive pressure."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from adhesion_testlib import PSD, ZETA_1, with_
from hypothesis import example, given, settings
from hypothesis import strategies as st
from scipy.integrate import quad
from scipy.special import erf, erfc

from xpersson.physics import diffusion_time
from xpersson.physics.interface import detachment, gap_pdf
from xpersson.scene import SceneError
from xpersson.testing import material, scene, spectrum
from xpersson_adhesion import LAWS, AdhesionLimitWarning, DMTBoundary, traction
from xpersson_adhesion._curves import curve_grid
from xpersson_adhesion._traction import attraction, attraction_quadrature

E_STAR = 4.0e6 / 3.0
TINY = scene(material=material("1 MPa"), p0=["2 kPa", "20 kPa"], zeta_per_decade=4)


def _dmt(**kw):
    return {"model": "dmt", "work_of_adhesion": "0.005 J/m**2", "range": "2 nm", **kw}


def _det(p0=6.6e4, zeta_out=(1.0, 1e4)):
    zeta = curve_grid(np.asarray(zeta_out, float))
    tau = diffusion_time(PSD, E_STAR, zeta)
    with np.errstate(divide="ignore"):
        x = p0 / (2.0 * np.sqrt(tau))
    return detachment(PSD, E_STAR, p0, zeta, erf(x), non_area=erfc(x))


@pytest.mark.parametrize("law", LAWS)
def test_laws_integrate_to_the_work_of_adhesion(law):
    work, rng = 0.02, 3e-9
    # in units of the range: int_0^inf sigma(rng x) rng dx
    parts = [(0.0, 1.0), (1.0, np.inf)]
    val = sum(
        quad(
            lambda x: float(traction(law, rng * x, work, rng)) * rng,
            a,
            b,
            epsabs=0,
            epsrel=1e-11,
            limit=200,
        )[0]
        for a, b in parts
    )
    assert abs(val - work) < 1e-8 * work
    assert np.all(traction(law, np.geomspace(1e-12, 1e-6, 50), work, rng) >= 0)


@pytest.mark.parametrize("law", ["dugdale", "exponential"])
def test_closed_forms_match_the_quadrature(law):
    det = _det()
    for rng in (1e-10, 2e-9, 1e-7):
        exact = attraction(law, det, 0.05, rng)
        num, mass_err = attraction_quadrature(law, det, 0.05, rng)
        np.testing.assert_allclose(num, exact, rtol=1e-7)
        assert abs(mass_err[0]) < 1e-10


def test_vanishing_range():
    det = _det()
    rho0 = float(gap_pdf(det, [0.0])[0, 0])
    work = 0.01
    for law in LAWS:
        # fixed work: the law concentrates at u = 0 -> dgamma rho(0+)
        p_small = float(attraction_quadrature(law, det, work, 1e-14)[0][0])
        assert abs(p_small / (work * rho0) - 1) < 1e-3, law
        # fixed maximum traction (work ~ range): p_att -> 0
        vals = [
            float(attraction_quadrature(law, det, 1e7 * r, r)[0][0]) for r in (1e-9, 1e-11, 1e-13)
        ]
        assert vals[2] < 1e-3 * vals[0] and vals[1] < vals[0], law


def test_zero_work_of_adhesion_is_elastic(solve):
    elastic = solve(with_(TINY, boundary={"model": "elastic"}))
    for law in LAWS:
        ds = solve(with_(TINY, boundary=_dmt(law=law, work_of_adhesion="0 J/m**2")))
        np.testing.assert_allclose(ds["area_fraction"], elastic["area_fraction"], rtol=1e-8)
        assert np.all(ds["p_att"].values == 0.0)
        for name, spec in DMTBoundary.outputs.items():  # declared ranges hold in this limit
            if spec.valid_min is not None:
                assert float(ds[name].min()) >= spec.valid_min, name


@pytest.mark.parametrize("law", LAWS)
def test_self_consistent_repulsive_pressure(solve, law):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AdhesionLimitWarning)
        ds = solve(with_(TINY, boundary=_dmt(law=law), solver={"rtol": 1e-7}))
    p0, p_rep, p_att = (ds[v].values for v in ("p0", "p_rep", "p_att"))
    np.testing.assert_allclose(p_rep, p0 + p_att, rtol=1e-14)
    assert np.all(p_att > 0)
    assert np.all(ds["dmt_residual"].values <= 1e-7)
    assert np.all(ds["dmt_iterations"].values >= 2)
    # the core's area is the elastic area at p_rep: erf(p_rep / (2 sqrt(tau)))
    tau = ds["diffusion_time"].values
    with np.errstate(divide="ignore"):
        exact = erf(p_rep[:, None] / (2.0 * np.sqrt(tau[None, :])))
    np.testing.assert_allclose(ds["area_fraction"].values, exact, rtol=1e-10)
    # re-evaluation of the fixed-point map at p_rep (the same curve sampling)
    for i in range(p0.size):
        det = _det(p_rep[i], ds["zeta"].values)
        again = float(attraction_quadrature(law, det, 0.005, 2e-9)[0][0])
        assert abs(again - p_att[i]) < 1e-5 * p_att[i]
    assert np.all(ds["p_att_discretization_error"].values < 0.05)
    # attraction enlarges the contact; larger work, more contact
    elastic = solve(with_(TINY, boundary={"model": "elastic"}))
    assert np.all(ds["area_fraction"].values[:, -1] > elastic["area_fraction"].values[:, -1])
    assert np.all(ds["mean_gap"].values > 0)


def test_tensile_load_and_pull_off(solve):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AdhesionLimitWarning)
        ds = solve(with_(TINY, boundary=_dmt(law="dugdale"), load={"p0": ["-100 Pa", "2 kPa"]}))
        assert np.all(ds["p_rep"].values > 0)
        assert ds["area_fraction"].values[0, -1] > 0
        with pytest.raises(ValueError, match=r"load.p0 = -1e\+06 Pa.*pull-off"):
            solve(with_(TINY, boundary=_dmt(law="dugdale"), load={"p0": "-1 MPa"}))


@pytest.mark.parametrize(
    ("boundary", "words"),
    [
        (_dmt(range="0 nm"), ["boundary.range", "m", "(0, inf]"]),
        (_dmt(range="-1 nm"), ["boundary.range", "outside the allowed range"]),
        (_dmt(work_of_adhesion="-1 J/m**2"), ["boundary.work_of_adhesion", "J/m**2", "[0, inf]"]),
        (_dmt(law="morse"), ["boundary.law", "dugdale", "lj93", "exponential"]),
    ],
)
def test_bad_input(solve, boundary, words):
    with pytest.raises((SceneError, ValueError)) as info:
        solve(with_(TINY, boundary=boundary))
    for w in words:
        assert w in str(info.value)


def test_tabor_warning_and_contract(solve):
    with pytest.warns(AdhesionLimitWarning, match="'jkr' limit"):
        solve(
            with_(
                TINY,
                load={"p0": "20 kPa"},
                boundary=_dmt(work_of_adhesion="0.05 J/m**2", range="0.3 nm"),
            )
        )
    from xpersson.testing import check_plugin

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AdhesionLimitWarning)
        report = check_plugin(
            DMTBoundary, {"work_of_adhesion": 1e-3, "range": 5e-9, "law": "exponential"}
        )
    assert report["metadata"] == "ok" and report["pickle"] == "ok"
    assert math.isfinite(DMTBoundary.outputs["p_att"].valid_min)
    # an instance that has solved a scene still pickles (dask ships instances)
    import pickle

    from xpersson.physics import coefficient_f
    from xpersson.plugins import DiffusionClock, SceneContext

    inst = DMTBoundary(work_of_adhesion=1e-3, range=5e-9, law="dugdale")
    zeta = np.geomspace(1.0, 1e4, 9)
    ctx = SceneContext(psd=PSD, E=1e6, nu=0.5, E_star=E_STAR, p0=np.array([2e4]), zeta=zeta)
    clock = DiffusionClock(
        lambda z: diffusion_time(PSD, E_STAR, z), lambda z: coefficient_f(PSD, E_STAR, z), 1e4
    )
    inst.walls(ctx, 2e4, clock)
    assert pickle.loads(pickle.dumps(inst)) == inst


def test_large_work_of_adhesion_drives_full_contact(solve):
    areas = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AdhesionLimitWarning)
        for w in ("0.005 J/m**2", "0.05 J/m**2", "1 J/m**2"):
            ds = solve(with_(TINY, boundary=_dmt(law="dugdale", work_of_adhesion=w)))
            areas.append(ds["area_fraction"].values[:, -1])
    assert np.all(np.diff(np.array(areas), axis=0) > 0)
    assert np.all(areas[-1] > 0.999)


# -- robustness: the area curve's nodes (fuzz campaign, 16 of 3000 scenes) ----------------------
def _core_zeta(zeta_max: float, per_decade: int) -> np.ndarray:
    """The core's output magnifications (scene.py: log grid with exact end points)."""
    n = max(1, math.ceil(per_decade * math.log10(zeta_max) - 1e-9))
    z = np.geomspace(1.0, zeta_max, n + 1)
    z[0], z[-1] = 1.0, zeta_max
    return z


# q_1/q_L of a fuzz scene whose output grid met the curve grid one ulp apart at zeta = 1.842
FUZZ_ZMAX = 5541.683342273044 / 2002.0669273387969


@settings(max_examples=40, deadline=None)
@example(zeta_max=FUZZ_ZMAX, per_decade=11)
@given(zeta_max=st.floats(1.01, ZETA_1), per_decade=st.integers(1, 40))
def test_curve_grid_nodes_are_separated(zeta_max, per_decade):
    zeta = _core_zeta(zeta_max, per_decade)
    for dense in (16, 32):
        z = curve_grid(zeta, per_decade=dense)
        assert z[0] == 1.0 and z[-1] == zeta[-1]
        assert np.all(np.diff(np.log(z)) > 1e-9)
        tau = diffusion_time(PSD, E_STAR, z)
        assert np.all(np.diff(tau) > 0)


def test_scene_with_near_duplicate_curve_nodes_solves(solve):
    """The fuzz scene that failed with "`x` must be strictly increasing sequence"."""
    sc = scene(
        spectrum(
            H=0.08770701236623936,
            q_L="2002.0669273387969 1/m",
            q_r="2002.0669273387969 1/m",
            q_1="5541.683342273044 1/m",
            h_rms="6.318420262971771e-09 m",
        ),
        material("2398213099.2847214 Pa", 0.39554770728104216),
        p0=[0.05381634121038694, 148290.75137277704],
        zeta_per_decade=11,
        boundary=_dmt(
            work_of_adhesion="0.005043522597706408 J/m**2",
            range="2.386381796964268e-09 m",
            law="exponential",
        ),
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = solve(sc)
    p0, p_rep, p_att = (ds[n].values for n in ("p0", "p_rep", "p_att"))
    np.testing.assert_allclose(p_rep, p0 + p_att, rtol=1e-9)
    assert np.all(ds["dmt_residual"].values < 1e-5)
    assert np.all(np.diff(ds["area_fraction"].values[:, -1]) > 0)


def test_flat_diffusion_time_keeps_the_first_node_of_the_stretch():
    from xpersson_adhesion._curves import increasing

    z = np.geomspace(1.0, 2e4, 40)  # beyond q_1/q_L = 1e4 the spectrum is zero: tau is flat
    tau = diffusion_time(PSD, E_STAR, z)
    zz, tt = increasing(z, tau)
    assert np.all(np.diff(tt) > 0) and zz[0] == 1.0
    assert zz[-1] == z[np.argmax(tau)] and zz.size < z.size
    assert tt[-1] == tau.max()
