"""The coefficient contract: ``f``/``tau`` accept any ``zeta`` shape and keep it.

A boundary's :class:`~xpersson.plugins.DiffusionClock` calls them with scalars and with 2-D
arrays (``zeta_of_tau`` on per-load tables, e.g. ``plastic_scale_dependent``); the q-panel
edges used to be built from a 2-D array and crashed the scene (fuzz campaign, 36 of 3000).
"""

from __future__ import annotations

import numpy as np
import pytest
from visco_testlib import elastic_scene, scene

import xpersson
from xpersson.physics import SelfAffineRollOff
from xpersson.plugins import DiffusionClock, SceneContext
from xpersson_viscoelastic import ViscoelasticCoefficient, kernel

PSD = SelfAffineRollOff.from_h_rms(1e-5, 0.8, 1e3, 1e4, 1e7)
CTX = SceneContext(
    psd=PSD, E=3e6, nu=0.5, E_star=4e6, p0=np.array([1e5]), zeta=np.geomspace(1.0, 1e4, 9)
)
COEFS = {
    "prony": {"velocity": 0.01},
    "sls": {"velocity": 0.01, "modulus": "sls", "E_r": 3e6, "E_g": 3e9, "relaxation_time": 1e-3},
    "flash": {"velocity": 0.01, "flash_temperature": True},  # a_T(q): the callable path
}
Z2 = np.array([[1.0, 3.7, 41.0, 1e4], [2.0, 17.0, 900.0, 5e3], [1.5, 1.5, 8e3, 1e4]])


@pytest.mark.parametrize("name", sorted(COEFS))
@pytest.mark.parametrize("method", ["f", "tau"])
def test_any_zeta_shape_gives_the_same_shape_and_values(name, method):
    coef = ViscoelasticCoefficient(**COEFS[name])
    fn = getattr(coef, method)
    flat = np.asarray(fn(CTX, Z2.ravel()))
    two_d = np.asarray(fn(CTX, Z2))
    assert two_d.shape == Z2.shape
    np.testing.assert_allclose(two_d, flat.reshape(Z2.shape), rtol=1e-13, atol=0)
    one = np.asarray(fn(CTX, 41.0))
    assert one.shape == ()
    np.testing.assert_allclose(one, flat[2], rtol=1e-13)
    assert np.all(flat[Z2.ravel() > 1.0] > 0)


def test_kernel_entry_points_keep_the_zeta_shape():
    model = ViscoelasticCoefficient(**COEFS["sls"]).model
    v = np.array([1e-3, 1e-1])
    for fn in (kernel.diffusion_time, kernel.coefficient_f, kernel.loss_integral):
        out = fn(PSD, model, 0.5, Z2, v)
        assert out.shape == v.shape + Z2.shape
        flat = fn(PSD, model, 0.5, Z2.ravel(), v)
        np.testing.assert_allclose(out, flat.reshape(out.shape), rtol=1e-13, atol=0)
    rms, loss = kernel.angular_averages(PSD, model, 0.5, Z2, v)
    assert rms.shape == loss.shape == v.shape + Z2.shape
    edges = kernel.panel_edges(PSD, Z2 * PSD.q_L)
    assert edges.ndim == 1 and np.all(np.diff(edges) > 0)
    assert np.isin(np.unique(Z2) * PSD.q_L, edges).all()


def test_clock_inverse_round_trips_on_2d_diffusion_times():
    coef = ViscoelasticCoefficient(**COEFS["prony"])
    clock = DiffusionClock(lambda z: coef.tau(CTX, z), lambda z: coef.f(CTX, z), 1e4)
    t = np.asarray(coef.tau(CTX, Z2))
    z = clock.zeta_of_tau(t)
    assert z.shape == Z2.shape
    np.testing.assert_allclose(clock.tau_of_zeta(z), t, rtol=1e-9)


def test_zero_speed_with_scale_dependent_plasticity_is_the_elastic_solve():
    """v = 0: the rubbery solid, so the plastic scene equals the elastic one with E = E_r."""
    small = {
        "boundary": {"model": "plastic_scale_dependent", "Y1": "1 MPa", "n": 0.5},
        "load": {"p0": ["0.1 MPa", "0.4 MPa"]},
        "output": {"zeta_per_decade": 3},
    }
    ve = xpersson.solve(
        scene(
            {
                "modulus": "sls",
                "E_r": "3 MPa",
                "E_g": "3 GPa",
                "relaxation_time": "1 ms",
                "velocity": "0 m/s",
            },
            **small,
        )
    )
    el = xpersson.solve(elastic_scene("3 MPa", **small))
    assert float(el["area_fraction"][0, -1]) > 0
    for name in ("area_fraction", "diffusion_time"):
        np.testing.assert_allclose(ve[name].values, el[name].values, rtol=1e-8, atol=0)
