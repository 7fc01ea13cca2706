"""Right at the edges (issue 22): near full contact and beyond E* no load is lost."""

from __future__ import annotations

import numpy as np
import pytest
from interface_testlib import E_STAR, scene

import xpersson


@pytest.fixture(scope="module")
def stiff():
    loads = [1e5, 1e6, 5e6, 2e7, 1e8]  # 1 - A(zeta_1) down to 0; the last two above E*
    with pytest.warns(xpersson.XperssonWarning, match="exceed the contact modulus"):
        return xpersson.solve(scene(loads, analyses={"contact_stiffness": {}, "mean_gap": {}}))


def test_stiffness_never_fails_the_solve(stiff):
    """A load whose K exceeds the float range is NaN with status 1; the others are kept."""
    K = stiff["contact_stiffness"].values
    status = stiff["contact_stiffness_status"].values
    assert np.all(np.isfinite(K[:-1])) and np.all(np.diff(K[:-1]) > 0)
    assert np.isnan(K[-1]) and status[-1] == 1
    assert status.tolist()[:-1] == [0, 0, 0, 2]  # 2e7 Pa > E* = 1.33e7 Pa: flagged, kept
    assert "NaN means: full contact" in stiff["contact_stiffness"].attrs["comment"]


def test_compliance_is_the_reciprocal_and_finite(stiff):
    c = stiff["contact_compliance"].values
    K = stiff["contact_stiffness"].values
    assert np.all(np.isfinite(c)) and np.all(c >= 0) and c[-1] == 0.0
    np.testing.assert_allclose(c[:-1] * K[:-1], 1.0, rtol=1e-12)
    # the mean gap falls with load at the rate the compliance gives (secant vs end slopes)
    u = stiff["mean_gap"].values
    p = stiff["p0"].values
    secant = -(u[1] - u[0]) / (p[1] - p[0])
    assert c[1] < secant < c[0]


def test_status_flag_is_cf(stiff):
    a = stiff["contact_stiffness_status"].attrs
    assert a["flag_meanings"].split() == ["valid", "rigid_full_contact", "above_contact_modulus"]
    assert E_STAR < 2e7
