"""Opt-in approximate flash temperature (physics.md §4.5, structure only)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import quad
from visco_testlib import scene

import xpersson
from xpersson_viscoelastic import NoShift, synthetic_tread
from xpersson_viscoelastic._flash import solve_flash

WLF = {"shift": "wlf", "T_ref": "293.15 K", "C1": 7.84, "C2": "114.75 K"}
FRICTION = {"friction": {}}


def _solve(**coef):
    return xpersson.solve(scene({"velocity": "1 m/s", **WLF, **coef}, analyses=FRICTION))


def test_off_by_default_and_no_heating_at_rest():
    ds = _solve()
    assert np.all(ds["flash_temperature"].values == 293.15)
    rest = _solve(velocity="0 m/s", flash_temperature=True)
    assert np.all(rest["flash_temperature"].values == 293.15)


def test_flash_heats_along_the_scales_and_lowers_friction_below_the_peak():
    off, on = _solve(), _solve(flash_temperature=True)
    T = on["flash_temperature"].values
    assert T[0] == 293.15 and np.all(np.diff(T) >= 0) and T[-1] > 293.15 + 1.0
    assert np.all(on["mu_visc"].values < off["mu_visc"].values)
    # a very good conductor does not heat up: back to the isothermal result
    cold = _solve(flash_temperature=True, thermal_conductivity="1e9 W/(m*K)")
    np.testing.assert_allclose(cold["mu_visc"].values, off["mu_visc"].values, rtol=1e-8)
    np.testing.assert_allclose(cold["area_fraction"].values, off["area_fraction"].values, rtol=1e-8)


def test_flash_integral_matches_quadrature_without_shift():
    # no shift: the loss does not depend on T, so T(q) - T0 = (1/k) int sqrt(D v/q) dL exactly
    from xpersson.physics import SelfAffineRollOff

    psd = SelfAffineRollOff.from_h_rms(1e-5, 0.8, 1e3, 1e4, 1e7)
    model, v, k, D, nu = synthetic_tread(), 0.1, 0.25, 1e-7, 0.5
    prof = solve_flash(psd, model, NoShift(), nu, v, 300.0, k, D)
    assert prof.converged and prof.iterations == 2

    def dens(s):
        q = np.exp(s)
        loss = model.angular(q * v)[1] / (1 - nu**2)
        return np.sqrt(D * v / q) / k * q**4 * float(psd.C(q)) * loss

    for q in (3e3, 1e5, 1e7):
        ref = sum(
            quad(dens, a, b, epsabs=0, epsrel=1e-12, limit=200)[0]
            for a, b in ((np.log(1e3), np.log(min(q, 1e4))), (np.log(1e4), np.log(max(q, 1e4))))
        )
        assert prof(q) - 300.0 == pytest.approx(ref, rel=1e-8)
    half = solve_flash(psd, model, NoShift(), nu, v, 300.0, 2 * k, D)
    np.testing.assert_allclose(prof.dens, 2 * half.dens, rtol=1e-12)  # Delta T ∝ 1/k
