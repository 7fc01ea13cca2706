"""friction_curve(zeta=...): the running integral at output magnifications (panel edges), its
end equal to the curve-only kernel, the closures and the S factor, and the refused grids."""

from __future__ import annotations

import numpy as np
import pytest

from xpersson.physics import SelfAffineRollOff
from xpersson_viscoelastic import WLF, friction_curve, sls, synthetic_tread

PSD = SelfAffineRollOff.from_h_rms(6e-5, 0.8, 600.0, 3000.0, 1e7)
ZETA = np.geomspace(1.0, 1e7 / 600.0, 86)  # 20 per decade up to q_1
NU = 0.5
P0 = np.array([1e5, 3e5])
V = np.geomspace(1e-8, 1e2, 9)
AT = WLF(7.84, 114.75, 293.15).aT(np.array([273.15, 313.15]))


@pytest.mark.parametrize("model", [synthetic_tread(), sls(3e6, 3e9, 1e-3)])
@pytest.mark.parametrize(("closure", "correction"), [("persson01", "none"), ("yp08", "s_factor")])
def test_the_end_of_the_cumulative_is_the_curve_kernel(model, closure, correction):
    kw = {"closure": closure, "correction": correction}
    got = friction_curve(PSD, model, NU, P0, V, AT, zeta=ZETA, **kw)
    ref = friction_curve(PSD, model, NU, P0, V, AT, **kw)
    cum = got["mu_visc_cumulative"]
    assert cum.shape == (AT.size, V.size, P0.size, ZETA.size)
    # two quadratures of the same integral (panels ending at every magnification or not)
    np.testing.assert_allclose(got["mu_visc"], ref["mu_visc"], rtol=1e-10)
    np.testing.assert_array_equal(cum[..., -1], got["mu_visc"])
    np.testing.assert_allclose(got["area_fraction"], ref["area_fraction"], rtol=1e-13)
    assert np.all(cum[..., 0] == 0.0) and np.all(np.diff(cum, axis=-1) >= 0.0)


def test_the_cumulative_at_an_inner_magnification_is_the_curve_up_to_there():
    model = synthetic_tread()
    got = friction_curve(PSD, model, NU, P0, V, AT, zeta=ZETA)["mu_visc_cumulative"]
    for k in (10, 40, 70):  # zeta = 3.2, 100, 3162
        ref = friction_curve(PSD, model, NU, P0, V, AT, zeta_max=ZETA[k])["mu_visc"]
        np.testing.assert_allclose(got[..., k], ref, rtol=1e-9)  # the kernel's accuracy


def test_a_grid_without_one_starts_at_q_L():
    model = synthetic_tread()
    z = ZETA[20:]
    got = friction_curve(PSD, model, NU, P0, V, AT, zeta=z)["mu_visc_cumulative"]
    full = friction_curve(PSD, model, NU, P0, V, AT, zeta=ZETA)["mu_visc_cumulative"]
    np.testing.assert_allclose(got, full[..., 20:], rtol=1e-10)


@pytest.mark.parametrize(
    ("zeta", "zeta_max", "match"),
    [
        ([0.5, 2.0], None, ">= 1"),
        ([1.0, 3.0, 2.0], None, "strictly increasing"),
        ([1.0, np.nan], None, "finite"),
        ([1.0, 10.0], 20.0, "zeta_max"),
    ],
)
def test_bad_grids_are_refused(zeta, zeta_max, match):
    with pytest.raises(ValueError, match=match):
        friction_curve(PSD, sls(3e6, 3e9, 1e-3), NU, P0, V, AT, zeta=zeta, zeta_max=zeta_max)
