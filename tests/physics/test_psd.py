"""Tests of xpersson.physics.psd against physics.md §8 closed forms and numerical quadrature."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.special import gamma as Gamma

from xpersson.physics.psd import SelfAffineRollOff, Tabulated, profile_factor

TWO_PI_SQ = (2 * np.pi) ** 2


def quad_moment(psd, k, qa=None, qb=None):
    """Independent reference: adaptive quadrature in ln q on every segment between nodes."""
    qa = psd.q_L if qa is None else qa
    qb = psd.q_1 if qb is None else qb
    pts = [qa] + [x for x in psd.nodes() if qa < x < qb] + [qb]
    total = 0.0
    for a, b in zip(pts[:-1], pts[1:], strict=True):
        # evaluate strictly inside the segment so that the integrand is smooth
        f = lambda s: np.exp(s) ** (k + 1) * psd.C(np.exp(s))  # noqa: E731
        val, _ = quad(f, np.log(a), np.log(b), epsabs=0, epsrel=1e-13, limit=200)
        total += val
    return total


def closed_forms(C_r, H, qL, qr, q1):
    """physics.md §8.2 moments <h^2>, <|grad h|^2>, <(lap h)^2> (H = 1 log form)."""
    hh = 2 * np.pi * C_r * ((qr**2 - qL**2) / 2 + qr**2 / (2 * H) * (1 - (q1 / qr) ** (-2 * H)))
    if H == 1.0:
        tail = qr**4 * np.log(q1 / qr)
    else:
        tail = qr**4 / (2 - 2 * H) * ((q1 / qr) ** (2 - 2 * H) - 1)
    gg = 2 * np.pi * C_r * ((qr**4 - qL**4) / 4 + tail)
    ll = (
        2
        * np.pi
        * C_r
        * ((qr**6 - qL**6) / 6 + qr**6 / (4 - 2 * H) * ((q1 / qr) ** (4 - 2 * H) - 1))
    )
    return hh, gg, ll


@pytest.mark.parametrize("H", [0.3, 0.8, 1.0])
def test_selfaffine_moments_closed_forms_and_quad(H):
    C_r, qL, qr, q1 = 2.5e-20, 1e3, 1e4, 1e8
    psd = SelfAffineRollOff(C_r, H, qL, qr, q1)
    hh, gg, ll = closed_forms(C_r, H, qL, qr, q1)
    assert psd.h_rms() ** 2 == pytest.approx(hh, rel=1e-13, abs=0)
    assert psd.rms_slope() ** 2 == pytest.approx(gg, rel=1e-13, abs=0)
    assert psd.rms_curvature() ** 2 == pytest.approx(ll, rel=1e-13, abs=0)
    for k in (1, 3, 5):
        assert psd.moment(k) == pytest.approx(quad_moment(psd, k), rel=1e-12, abs=0)


@pytest.mark.parametrize("k", [0.0, 2.0, 2.6, -1.0, 4.5])
def test_general_k_moments_including_log_case(k):
    # H = 0.8: tail exponent -3.6, so k = 2.6 is the logarithmic case k + e = -1
    psd = SelfAffineRollOff(1e-20, 0.8, 1e3, 1e4, 1e8)
    assert psd.moment(k) == pytest.approx(quad_moment(psd, k), rel=1e-12, abs=0)
    # partial ranges straddling the roll-off
    for qa, qb in [(2e3, 5e3), (5e3, 3e6), (1e5, 1e8), (5e2, 2e9)]:
        assert psd.moment(k, qa, qb) == pytest.approx(
            quad_moment(psd, k, max(qa, 1e3), min(qb, 1e8)), rel=1e-12, abs=0
        )
    assert psd.moment(k, 3e5, 2e4) == pytest.approx(-psd.moment(k, 2e4, 3e5), rel=1e-15, abs=0)


def test_log_case_explicit():
    # k = 2H + 1 on a pure power law: int q^k C0 q^{-2-2H} dq = C0 ln(q1/qL)
    H = 0.8
    psd = SelfAffineRollOff(3.0, H, 1e4, 1e4, 1e6)
    assert psd.moment(2 * H + 1) == pytest.approx(psd.C0 * np.log(100.0), rel=1e-14, abs=0)


def test_I3_exact_vectorised():
    H, qL, qr, q1 = 0.8, 1e3, 1e4, 1e8
    C_r = 1.3e-21
    psd = SelfAffineRollOff(C_r, H, qL, qr, q1)
    q = np.array([[1e3, 2e3, 9.9e3], [1e4, 3.3e6, 1e8]])
    got = psd.I3(q)
    assert got.shape == q.shape
    # physics.md §1.2 closed form
    ref = np.where(
        q <= qr,
        C_r * (q**4 - qL**4) / 4,
        C_r
        * (
            (qr**4 - qL**4) / 4
            + qr ** (2 + 2 * H) * (q ** (2 - 2 * H) - qr ** (2 - 2 * H)) / (2 - 2 * H)
        ),
    )
    np.testing.assert_allclose(got, ref, rtol=1e-13, atol=0)
    assert psd.I3(qL) == 0.0
    assert psd.I3(1e12) == pytest.approx(psd.moment(3), rel=1e-14, abs=0)
    assert psd.I3(10.0) == 0.0
    assert psd.I3(5e5) == pytest.approx(quad_moment(psd, 3, qL, 5e5), rel=1e-12, abs=0)


def test_I3_H1_log_form():
    qL, qr, q1, C_r = 1e3, 1e4, 1e7, 1.0
    psd = SelfAffineRollOff(C_r, 1.0, qL, qr, q1)
    q = 5e5
    ref = C_r * ((qr**4 - qL**4) / 4 + qr**4 * np.log(q / qr))
    assert psd.I3(q) == pytest.approx(ref, rel=1e-14, abs=0)


def test_reference_parameter_set_section_1_4():
    psd = SelfAffineRollOff.from_h_rms(1e-6, 0.8, 1e3, 1e4, 1e8)
    assert psd.C_r == pytest.approx(1.421027e-21, abs=0.5e-27)
    assert psd.rms_slope() == pytest.approx(0.0931956, abs=0.5e-7)
    assert psd.h_rms() == pytest.approx(1e-6, rel=1e-14, abs=0)
    psd2 = SelfAffineRollOff.from_rms_slope(psd.rms_slope(), 0.8, 1e3, 1e4, 1e8)
    assert psd2.C_r == pytest.approx(psd.C_r, rel=1e-14, abs=0)


def test_C_values_and_support():
    psd = SelfAffineRollOff(2.0, 0.5, 1.0, 10.0, 1000.0)
    q = np.array([0.5, 1.0, 5.0, 10.0, 100.0, 1000.0, 1001.0])
    ref = np.array([0.0, 2.0, 2.0, 2.0, 2.0 * 10.0**-3, 2.0 * 100.0**-3, 0.0])
    np.testing.assert_allclose(psd.C(q), ref, rtol=1e-15)
    assert isinstance(psd.C(3.0), float)
    assert psd.C0 == pytest.approx(2.0 * 10.0**3, rel=1e-15, abs=0)
    np.testing.assert_array_equal(psd.nodes(), [1.0, 10.0, 1000.0])


def test_no_plateau_and_pure_plateau():
    nop = SelfAffineRollOff(1.0, 0.8, 1e4, 1e4, 1e6)
    np.testing.assert_array_equal(nop.nodes(), [1e4, 1e6])
    assert nop.moment(1) == pytest.approx(quad_moment(nop, 1), rel=1e-12, abs=0)
    flat = SelfAffineRollOff(1.0, 0.8, 1.0, 2.0, 2.0)
    assert flat.moment(3) == pytest.approx((16 - 1) / 4, rel=1e-15, abs=0)


@pytest.mark.parametrize(
    "args",
    [
        (1.0, 0.0, 1.0, 2.0, 3.0),
        (1.0, 1.2, 1.0, 2.0, 3.0),
        (1.0, 0.5, 0.0, 2.0, 3.0),
        (1.0, 0.5, 2.0, 1.0, 3.0),
        (1.0, 0.5, 1.0, 4.0, 3.0),
        (1.0, 0.5, 3.0, 3.0, 3.0),
        (-1.0, 0.5, 1.0, 2.0, 3.0),
        (np.nan, 0.5, 1.0, 2.0, 3.0),
    ],
)
def test_selfaffine_validation(args):
    with pytest.raises(ValueError):
        SelfAffineRollOff(*args)


def test_profile_factor_values_and_quadrature():
    # physics.md §8.2: 1/K = 2.733, pi, 3.508, 3.679, 3.843, 4
    for H, inv in [(0.3, 2.733), (0.7, 3.508), (0.8, 3.679), (0.9, 3.843)]:
        assert 1 / profile_factor(H) == pytest.approx(inv, abs=5e-4)
    assert 1 / profile_factor(0.5) == pytest.approx(np.pi, rel=1e-14, abs=0)
    assert 1 / profile_factor(1.0) == pytest.approx(4.0, rel=1e-14, abs=0)
    for H in [0.3, 0.5, 0.8, 1.0]:
        ref = Gamma(H + 0.5) / (2 * np.sqrt(np.pi) * Gamma(H + 1))
        assert profile_factor(H) == pytest.approx(ref, rel=1e-14, abs=0)
        qx = 2.0
        num = (
            quad(
                lambda qy, H=H, qx=qx: (qx**2 + qy**2) ** (-1 - H),
                0,
                np.inf,
                epsabs=0,
                epsrel=1e-13,
            )[0]
            / np.pi
        )
        assert num / (qx ** (-1 - 2 * H) * profile_factor(H)) == pytest.approx(1.0, abs=1e-12)
    np.testing.assert_allclose(profile_factor(np.array([0.5, 1.0])), [1 / np.pi, 0.25])
    with pytest.raises(ValueError):
        profile_factor(-0.6)


def test_tabulated_reproduces_selfaffine_exactly():
    sa = SelfAffineRollOff.from_h_rms(1e-6, 0.8, 1e3, 1e4, 1e8)
    q = sa.nodes()
    tab = Tabulated(q, sa.C(q))
    for k in (1, 3, 5, 2.6):
        assert tab.moment(k) == pytest.approx(sa.moment(k), rel=1e-13, abs=0)
    qq = np.geomspace(1e3, 1e8, 37)
    np.testing.assert_allclose(tab.I3(qq), sa.I3(qq), rtol=1e-13)
    np.testing.assert_allclose(tab.C(qq), sa.C(qq), rtol=1e-13)


def test_tabulated_dense_power_law_and_loglog_interpolation():
    q = np.geomspace(1e2, 1e6, 9)
    C = 5.0 * q**-3.0
    tab = Tabulated(q, C)
    qq = np.geomspace(1e2, 1e6, 101)
    np.testing.assert_allclose(tab.C(qq), 5.0 * qq**-3.0, rtol=1e-12)
    # k = 2 makes every segment the log case (k + e = -1)
    assert tab.moment(2) == pytest.approx(5.0 * np.log(1e4), rel=1e-13, abs=0)


def test_tabulated_irregular_vs_quad():
    q = np.array([1e3, 1.7e3, 4e3, 1e4, 3.2e4, 2e5, 1e6])
    C = np.array([1e-18, 1.5e-18, 9e-19, 1e-19, 6e-21, 2e-23, 1e-25])
    tab = Tabulated(q, C)
    for k in (1, 3, 5, 0.5):
        assert tab.moment(k) == pytest.approx(quad_moment(tab, k), rel=1e-12, abs=0)
    assert tab.I3(2.5e4) == pytest.approx(quad_moment(tab, 3, 1e3, 2.5e4), rel=1e-12, abs=0)


def test_tabulated_truncation():
    q = np.geomspace(1e2, 1e6, 5)
    tab = Tabulated(q, 7.0 * q**-3.6, q_L=3e2, q_1=5e5)
    assert tab.q_L == 3e2 and tab.q_1 == 5e5
    assert tab.moment(3) == pytest.approx(7.0 * (5e5**0.4 - 3e2**0.4) / 0.4, rel=1e-13, abs=0)
    with pytest.raises(ValueError, match="q_L"):
        Tabulated(q, q**-3.0, q_L=10.0)


def test_convention_surface_topography_two_pi_squared():
    sa = SelfAffineRollOff.from_h_rms(1e-6, 0.8, 1e3, 1e4, 1e8)
    q = np.geomspace(1e3, 1e8, 60)
    p = Tabulated(q, sa.C(q), "persson")
    jjp = Tabulated(q, TWO_PI_SQ * sa.C(q), "surface_topography")
    qq = np.geomspace(1e3, 1e8, 11)
    np.testing.assert_allclose(jjp.I3(qq), p.I3(qq), rtol=1e-14)
    np.testing.assert_allclose(jjp.C(qq), p.C(qq), rtol=1e-14)
    # guard: reading JJP data as Persson would be (2 pi)^2 off
    wrong = Tabulated(q, TWO_PI_SQ * sa.C(q), "persson")
    assert wrong.I3(1e8) / p.I3(1e8) == pytest.approx(TWO_PI_SQ, rel=1e-13, abs=0)


@pytest.mark.parametrize("H", [0.3, 0.8])
def test_convention_profile_1d_pure_power_law(H):
    C0_jjp = 3.0e-3
    q = np.geomspace(1e3, 1e7, 13)
    C1d = profile_factor(H) * C0_jjp * q ** (-1 - 2 * H)
    tab = Tabulated(q, C1d, "profile_1d")
    np.testing.assert_allclose(tab.H_local, H, atol=1e-12)
    np.testing.assert_allclose(tab.C(q), C0_jjp * q ** (-2 - 2 * H) / TWO_PI_SQ, rtol=1e-11)
    # line scan synthesised from the isotropic JJP power law by the exact y-integral
    qx = 5e4
    # C1D(qx) = (1/pi) int_0^inf C_iso(sqrt(qx^2 + qy^2)) dqy, with qy = qx t
    integral = quad(lambda t: (1 + t * t) ** (-1 - H), 0, np.inf, epsabs=0, epsrel=1e-12)[0]
    num = C0_jjp * qx ** (-1 - 2 * H) * integral / np.pi
    # ... and the table converted back at qx gives the isotropic JJP value / (2 pi)^2
    tab_x = Tabulated(
        np.array([qx / 2, qx, 2 * qx]), num * np.array([2.0, 1.0, 0.5]) ** (1 + 2 * H), "profile_1d"
    )
    assert tab_x.C(qx) * TWO_PI_SQ == pytest.approx(C0_jjp * qx ** (-2 - 2 * H), rel=1e-10, abs=0)


def test_profile_1d_plateau_is_clipped():
    q = np.geomspace(1.0, 100.0, 5)
    tab = Tabulated(q, np.ones(5), "profile_1d")
    np.testing.assert_array_equal(tab.H_local, 0.0)
    np.testing.assert_allclose(tab.C(q), 1.0 / (profile_factor(0.0) * q) / TWO_PI_SQ, rtol=1e-13)
    with pytest.raises(ValueError, match="h_clip"):
        Tabulated(q, np.ones(5), "profile_1d", h_clip=(-0.6, 1.0))


@pytest.mark.parametrize(
    ("q", "C", "match"),
    [
        ([1.0], [1.0], "at least 2"),
        ([1.0, 2.0], [1.0], "differ in length"),
        ([1.0, 1.0, 2.0], [1.0, 1.0, 1.0], "strictly increasing"),
        ([2.0, 1.0], [1.0, 1.0], "strictly increasing"),
        ([0.0, 1.0], [1.0, 1.0], "q must be > 0"),
        ([1.0, 2.0], [1.0, 0.0], "C must be > 0"),
        ([1.0, np.inf], [1.0, 1.0], "q contains non-finite"),
        ([1.0, 2.0], [np.nan, 1.0], "C contains non-finite"),
        ([[1.0, 2.0]], [[1.0, 2.0]], "one-dimensional"),
    ],
)
def test_tabulated_validation(q, C, match):
    with pytest.raises(ValueError, match=match):
        Tabulated(q, C)


def test_tabulated_unknown_convention():
    with pytest.raises(ValueError, match="persson"):
        Tabulated([1.0, 2.0], [1.0, 1.0], "jjp")


def test_from_file(tmp_path):
    sa = SelfAffineRollOff(1e-20, 0.8, 1e3, 1e4, 1e8)
    q = np.unique(np.concatenate([np.geomspace(1e3, 1e8, 30), sa.nodes()]))
    f = tmp_path / "psd.csv"
    lines = [
        "# exported PSD, q in 1/um, C in um^4 (SurfaceTopography convention)",
        "q_per_um, C_um4",
        "",
    ]
    lines += [
        f"{x / 1e6:.17e}, {TWO_PI_SQ * c / 1e-24:.17e}  # row"
        for x, c in zip(q, sa.C(q), strict=True)
    ]
    f.write_text("\n".join(lines) + "\n")
    tab = Tabulated.from_file(f, 1e6, 1e-24, "surface_topography")
    assert tab.I3(1e8) == pytest.approx(sa.I3(1e8), rel=1e-12, abs=0)
    g = tmp_path / "ws.txt"
    g.write_text("1 2 1\n2 3 0.5\n4 5 0.25\n")
    tab2 = Tabulated.from_file(g, columns=(0, 2))
    np.testing.assert_allclose(tab2.C([1.0, 2.0, 4.0]), [1.0, 0.5, 0.25])


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("1, 1\n2, x\n", "line 2"),
        ("1, 1\n", "at least 2"),
        ("1, 1\n1, 2\n", "strictly increasing"),
        ("1, 1\n2, -1\n", "line 2: C = -1 must be > 0"),
        ("h1, h2\nh3, h4\n1, 1\n", "line 2"),
    ],
)
def test_from_file_errors(tmp_path, text, match):
    f = tmp_path / "bad.csv"
    f.write_text(text)
    with pytest.raises(ValueError, match=match):
        Tabulated.from_file(f)


def test_h_rms_from_rms_definitions_are_consistent():
    psd = SelfAffineRollOff(1e-20, 0.8, 1e3, 1e4, 1e8)
    assert psd.h_rms() == pytest.approx(
        math.sqrt(2 * np.pi * quad_moment(psd, 1)), rel=1e-12, abs=0
    )
    assert psd.rms_curvature() == pytest.approx(
        math.sqrt(2 * np.pi * quad_moment(psd, 5)), rel=1e-12, abs=0
    )
