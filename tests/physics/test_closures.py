"""Tests of xpersson.physics.closures (physics.md §1.5) and the Xu et al. Octave reference data."""

from __future__ import annotations

import math
from decimal import Decimal
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.special import erf

from xpersson.physics import closures
from xpersson.physics.closures import CLOSURES, closure_S, effective_ratio, effective_tau
from xpersson.physics.elastic import area_fraction, diffusion_time
from xpersson.physics.psd import SelfAffineRollOff

REFDATA = Path(__file__).parents[2] / ".." / "shared" / "refdata" / "xu2024-gfmd"


def assert_digits(value: float, quoted: str, slack: float = 1.1) -> None:
    """``value`` rounds to ``quoted`` (within ``slack`` half-units of its last digit)."""
    d = Decimal(quoted)
    digits = d.as_tuple()
    last = d.adjusted() - (len(digits.digits) - 1)
    assert abs(value - float(d)) <= slack * 0.5 * 10.0**last, (value, quoted)


def area_of(G, closure, gamma=None):
    """A(G) at p0 = 1: tau_c = G."""
    G = np.atleast_1d(np.asarray(G, dtype=float))
    tau = effective_tau(G, 1.0, closure, gamma)
    return area_fraction(1.0, tau)[0]


# physics.md §1.5 table: G, Persson01, YP08 0.45, YP08 0.42, WM17 5/9, Xu24 0.45
TABLE = [
    ("0.1", "0.9746527", "0.9750968", "0.9751207", "0.9755221", "0.9756276"),
    ("1", "0.5204999", "0.5795623", "0.5829677", "0.6048491", "0.5799632"),
    ("10", "0.1769367", "0.2390134", "0.2441442", "0.2356001", "0.2314669"),
    ("100", "0.05637198", "0.08240415", "0.08502018", "0.07575836", "0.08013053"),
    ("1e4", "0.005641849", "0.008407034", "0.008701455", "0.00756986", "0.008367608"),
]
COLUMNS = [("persson01", None), ("yp08", 0.45), ("yp08", 0.42), ("wm17", 5 / 9), ("xu24", 0.45)]


@pytest.mark.parametrize("col", range(5))
def test_section_1_5_table(col):
    closure, gamma = COLUMNS[col]
    G = np.array([float(row[0]) for row in TABLE])
    A = area_of(G, closure, gamma)
    for a, row in zip(A, TABLE, strict=True):
        assert_digits(a, row[col + 1])


def test_defaults_match_documented_values():
    G = np.array([1.0, 10.0])
    np.testing.assert_array_equal(area_of(G, "yp08"), area_of(G, "yp08", 0.42))
    np.testing.assert_array_equal(area_of(G, "wm17"), area_of(G, "wm17", 5 / 9))
    np.testing.assert_array_equal(area_of(G, "xu24"), area_of(G, "xu24", 0.42))
    # YP08(0.42) column of the table through the default
    assert_digits(area_of(1.0, "yp08")[0], "0.5829677")


def _read_octave():
    path = REFDATA / "persson_variants_area_octave.csv"
    if not path.exists():
        pytest.skip(f"reference data not available: {path}")
    return np.genfromtxt(path, delimiter=",", comments="#", skip_header=2)


def test_octave_reference_zhou_scene():
    data = _read_octave()
    p0 = data[:, 0]
    # Zhou scene: E* = 1 Pa, C = C0 q^-3.6 on [1e4, 1e6], h_rms = 6 um, no plateau
    psd = SelfAffineRollOff.from_h_rms(6e-6, 0.8, 1e4, 1e4, 1e6)
    assert psd.rms_slope() == pytest.approx(0.276597, abs=1e-6)
    zeta = np.geomspace(1.0, 100.0, 50)
    tau_c = diffusion_time(psd, 1.0, zeta)
    for col, closure, gamma, rtol in [
        (3, "persson01", None, 1e-6),
        (4, "yp08", 0.45, 1e-3),
        (5, "wm17", 5 / 9, 1e-3),
        (6, "xu24", 0.45, 1e-3),
    ]:
        tau_eff = effective_tau(tau_c, p0, closure, gamma)
        A = area_fraction(p0[:, None], tau_eff)[0][:, -1]
        np.testing.assert_allclose(A, data[:, col], rtol=rtol, err_msg=closure)


def test_small_load_asymptote():
    G = 1e12
    a01 = area_of(G, "persson01")[0]
    for closure, gamma in [("yp08", 0.45), ("yp08", 0.42), ("wm17", 5 / 9), ("xu24", 0.45)]:
        ratio = area_of(G, closure, gamma)[0] / a01
        assert ratio == pytest.approx(1 / math.sqrt(gamma), rel=1e-5, abs=0)
    # kappa values quoted in physics.md §1.5 (at G = 1e12, A ~ kappa p0/(E* h'))
    kap = math.sqrt(8 / math.pi)
    assert_digits(kap * area_of(G, "yp08", 0.45)[0] / a01, "2.379")
    assert_digits(kap * area_of(G, "wm17")[0] / a01, "2.141")


def test_universality_and_discretisation_independence():
    psd = SelfAffineRollOff.from_h_rms(1e-6, 0.8, 1e3, 1e4, 1e8)
    Es = 13.3e6
    zeta_fine = np.geomspace(1, 1e5, 501)
    zeta_coarse = zeta_fine[::100]
    p0 = np.array([1e4, 1e5, 1e6])
    for closure in CLOSURES:
        fine = effective_tau(diffusion_time(psd, Es, zeta_fine), p0, closure)
        coarse = effective_tau(diffusion_time(psd, Es, zeta_coarse), p0, closure)
        np.testing.assert_allclose(fine[:, ::100], coarse, rtol=1e-14)
        # same G at a different load and scale of tau_c gives the same A
        G = fine / p0[:, None] ** 2
        scaled = effective_tau(diffusion_time(psd, Es, zeta_fine) * 4.0, 2 * p0, closure)
        np.testing.assert_allclose(scaled / (2 * p0[:, None]) ** 2, G, rtol=1e-12, atol=0)


def test_ordering_and_monotonicity():
    tau_c = np.concatenate(([0.0], np.geomspace(1e-4, 1e8, 300)))
    p0 = np.array([0.3, 1.0, 7.0])
    a01 = area_fraction(p0[:, None], effective_tau(tau_c, p0, "persson01"))[0]
    for closure in ("yp08", "wm17", "xu24"):
        te = effective_tau(tau_c, p0, closure)
        assert te.shape == (3, 301)
        assert np.all(te[:, 0] == 0.0)
        assert np.all(te <= tau_c * (1 + 1e-12))
        assert np.all(np.diff(te, axis=1) > 0)
        A = area_fraction(p0[:, None], te)[0]
        assert np.all(A >= a01 - 1e-15)
        assert np.all(np.diff(A, axis=1) <= 0)


def test_ode_closure_against_independent_lsoda():
    # V-form of the ODE (physics.md §1.5), solved here independently in linear V_c
    gamma, p0 = 0.3, 1.0
    for closure, S in [
        ("yp08", lambda A: gamma + (1 - gamma) * A * A),
        ("wm17", lambda A: gamma - 2 / 9 * A**2 + (11 / 9 - gamma) * A**4),
    ]:
        Vc_end = 2 * np.array([0.5, 3.0, 40.0])

        def rhs(s, V, S=S):
            A = erf(p0 / np.sqrt(2 * V[0])) if V[0] > 0 else 1.0
            return [np.exp(s) * S(A)]

        sol = solve_ivp(
            rhs,
            [np.log(1e-8), np.log(Vc_end[-1])],
            [1e-8],
            method="LSODA",
            rtol=1e-11,
            atol=1e-14,
            t_eval=np.log(Vc_end),
        )
        ref = erf(p0 / np.sqrt(2 * sol.y[0]))
        got = area_fraction(p0, effective_tau(Vc_end / 2, p0, closure, gamma))[0]
        np.testing.assert_allclose(got, ref, rtol=1e-8)


def test_xu24_fixed_point_residual():
    gamma = 0.42
    G = np.concatenate(([0.0], np.geomspace(1e-6, 1e14, 2001)))
    r = effective_ratio(G, "xu24", gamma)
    with np.errstate(divide="ignore"):
        A = erf(0.5 / np.sqrt(r * G))
    res = r - (gamma + (1 - gamma) * A)
    assert np.max(np.abs(res)) < 1e-12
    assert np.all((r >= gamma) & (r <= 1))
    assert r[0] == 1.0


def test_full_contact_is_exact():
    G = np.array([0.0, 1e-6, 1e-3])
    for closure in CLOSURES:
        np.testing.assert_array_equal(effective_tau(G, 1.0, closure), G)


def test_closure_S():
    A = np.array([0.0, 0.3, 1.0])
    np.testing.assert_array_equal(closure_S("persson01", A), 1.0)
    np.testing.assert_allclose(closure_S("yp08", A), 0.42 + 0.58 * A**2, rtol=1e-15)
    np.testing.assert_allclose(
        closure_S("wm17", A), 5 / 9 - 2 / 9 * A**2 + (11 / 9 - 5 / 9) * A**4, rtol=1e-15
    )
    np.testing.assert_allclose(closure_S("xu24", A, 0.45), 0.45 + 0.55 * A, rtol=1e-15)
    for closure in CLOSURES:
        assert closure_S(closure, 1.0, 0.3) == pytest.approx(1.0, rel=1e-15, abs=0)
    assert closure_S("wm17", 0.0) == pytest.approx(5 / 9, rel=1e-15, abs=0)


def test_validation():
    with pytest.raises(ValueError, match="persson01, yp08, wm17, xu24"):
        effective_tau([0.0, 1.0], 1.0, "yp09")
    with pytest.raises(ValueError, match="allowed"):
        closure_S("YP08", 0.5)
    for g in (0.0, -0.1, 1.5, float("nan")):
        with pytest.raises(ValueError, match="gamma"):
            effective_tau([0.0, 1.0], 1.0, "yp08", g)
    with pytest.raises(ValueError, match="gamma"):
        effective_tau([0.0, 1.0], 1.0, "wm17", 0.005)
    with pytest.raises(ValueError, match="non-decreasing"):
        effective_tau([0.0, 2.0, 1.0], 1.0, "xu24")
    with pytest.raises(ValueError, match="tau_c"):
        effective_tau([-1.0, 2.0], 1.0, "xu24")
    with pytest.raises(ValueError, match="p0"):
        effective_tau([0.0, 2.0], [1.0, 0.0], "yp08")


def test_shapes():
    tau_c = np.linspace(0, 3, 7)
    assert effective_tau(tau_c, 2.0, "yp08").shape == (7,)
    assert effective_tau(tau_c, np.array([1.0, 2.0]), "wm17").shape == (2, 7)
    assert effective_tau(tau_c, np.array([1.0, 2.0]), "persson01").shape == (2, 7)


def test_500_loads_200_zeta_batch_equals_each_load():
    """A (500 loads x 200 zeta) batch is finite and its rows equal the loads solved one by one
    (the batch shares one ODE solution per closure; speed is measured in benchmarks/)."""
    closures._ode_solution.cache.clear()
    p0 = np.geomspace(1e-4, 0.5, 500)
    tau_c = np.concatenate(([0.0], np.geomspace(1e-8, 0.02, 199)))
    for closure in CLOSURES:
        out = effective_tau(tau_c, p0, closure)
        assert out.shape == (500, 200)
        assert np.all(np.isfinite(out))
        for k in (0, 137, 499):
            np.testing.assert_allclose(out[k], effective_tau(tau_c, p0[k], closure), rtol=1e-12)
