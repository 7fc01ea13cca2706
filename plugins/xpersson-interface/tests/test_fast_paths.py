"""The batched fast paths equal the per-load and scipy forms they replace (issue 25)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from interface_testlib import E_STAR, detach, scene
from scipy.interpolate import CubicSpline

import xpersson
from xpersson.cache import cache
from xpersson.physics import gap_cdf, gap_pdf
from xpersson.physics._fastnum import _exp, _row_spline
from xpersson.plugins import solved
from xpersson_interface import bruggeman_gap

LOADS = np.geomspace(2e3, 3e6, 9)  # A/A0 about 1e-3 .. 0.9


def _one(det, i):
    k = slice(i, i + 1)
    return dataclasses.replace(
        det, p0=det.p0[k], area=det.area[k], ubar=det.ubar[k], weight=det.weight[k], u1=det.u1[k]
    )


def test_per_load_bruggeman_equals_each_load_solved_alone(psd):
    """per_load=True (one vectorised root-find) = the loop over loads, each with its own cells."""
    d = detach(psd, E_STAR, LOADS, n=150)
    for a_c in (None, 0.42):
        u3 = bruggeman_gap(d, a_c=a_c, per_load=True)
        alone = np.concatenate([bruggeman_gap(_one(d, i), a_c=a_c) for i in range(LOADS.size)])
        np.testing.assert_allclose(u3, alone, rtol=1e-12, atol=0.0)
    # the batch's shared cells give another (coarser) answer for the small gaps
    assert not np.allclose(bruggeman_gap(d), alone, rtol=1e-6, atol=0.0)


def test_gap_tensors_skip_only_bins_without_weight(psd):
    """gap_pdf/gap_cdf over the non-zero-weight bins = the dense sum over every bin."""
    d = detach(psd, E_STAR, LOADS, n=150)
    assert (d.weight == 0).any()
    u = np.linspace(0.0, float(d.mean_gap.max()) + 6 * d.h_rms, 64)
    a = d.u1[:, :, None] / d.h[None, :, None]
    b = u[None, None, :] / d.h[None, :, None]
    with np.errstate(over="ignore"):
        dense = np.exp(-0.5 * (b - a) ** 2) * (1 + np.exp(-2 * a * b))
    ref = np.einsum("lk,lku->lu", d.weight / d.h / np.sqrt(2 * np.pi), dense)
    np.testing.assert_allclose(gap_pdf(d, u), ref, rtol=1e-10, atol=1e-300)
    per_load = np.broadcast_to(u, (LOADS.size, u.size))
    np.testing.assert_array_equal(gap_cdf(d, per_load), gap_cdf(d, u))
    # the CDF's last value is the detached area inside u_max
    assert np.all(gap_cdf(d, u)[:, -1] <= 1.0 - d.contact + 1e-12)


@pytest.mark.parametrize("n", [3, 4, 5, 60, 600])
def test_row_spline_is_scipys_cubic_spline(n):
    rng = np.random.default_rng(n)
    x = np.sort(rng.uniform(0.0, 10.0, n))
    y = rng.normal(size=(7, n))
    ref, got = CubicSpline(x, y, axis=1), _row_spline(x, y)
    np.testing.assert_array_equal(got.c, ref.c)
    xs = np.linspace(x[0] - 0.5, x[-1] + 0.5, 101)
    np.testing.assert_array_equal(got(xs), ref(xs))
    np.testing.assert_array_equal(got(xs, 1), ref(xs, 1))


def test_exp_is_numpys_exp_bit_for_bit():
    y = np.concatenate([np.linspace(-800.0, -700.0, 20001), [-np.inf, np.nan, 0.0, 5.0]])
    np.testing.assert_array_equal(_exp(y), np.exp(y))
    assert _exp(np.zeros(0)).shape == (0,)


def test_analyses_of_one_solve_share_one_curve_and_free_it():
    """mean_gap, contact_stiffness and gap_pdf of one solve build one SolvedContact (the
    solve-scoped cache "plugins.solved"; with the caches on also in CI's caches-off run)."""
    made = []
    real = xpersson.physics.SolvedContact

    class Counting(real):
        def __init__(self, *a, **k):
            made.append(1)
            super().__init__(*a, **k)

    xpersson.physics.SolvedContact = Counting
    try:
        one = {"s_factor": "closure"}  # one form: one curve (auto would pick yang_persson)
        an = {"mean_gap": one, "contact_stiffness": one, "gap_pdf": {}}
        with xpersson.set_options(cache=True):
            ds = xpersson.solve(scene(LOADS, analyses=an))
            alone = xpersson.solve(scene(LOADS, analyses={"gap_pdf": {}}))
        with xpersson.set_options(cache=False):
            off = xpersson.solve(scene(LOADS, analyses=an))
    finally:
        xpersson.physics.SolvedContact = real
    assert len(made) == 2 + 3  # one per solve; with the caches off one per analysis
    np.testing.assert_array_equal(ds["gap_pdf"].values, alone["gap_pdf"].values)
    for name in an:
        np.testing.assert_array_equal(ds[name].values, off[name].values)
    assert len(cache("plugins.solved")) == 0  # nothing outlives the solve


def test_fast_erf_is_scipys_erf_within_its_bound():
    """The table erf of gap_cdf: within ERF_ERROR (2e-13) of scipy's, exact +-1, NaN and -0.0."""
    from scipy.special import erf

    from xpersson.physics._fasterf import ERF_ERROR, fast_erf

    x = np.concatenate([np.linspace(-40.0, 40.0, 160001), [-np.inf, np.inf, np.nan, -0.0]])
    got, ref = fast_erf(x), erf(x)
    np.testing.assert_allclose(got, ref, rtol=0.0, atol=ERF_ERROR)
    far = np.abs(x) >= 6.0
    np.testing.assert_array_equal(got[far], ref[far])  # exactly +-1 (scipy's too)
    assert np.isnan(got[-2]) and np.signbit(got[-1])


def test_gap_cdf_negligible_bins_change_values_by_their_weight_only(psd):
    d = detach(psd, E_STAR, LOADS, n=150)
    w = np.where(d.weight > 0, d.weight, 0.0)
    cut = 1e-12  # larger than the 1e-30 the leakage uses, so that bins are actually left out
    small = (w > 0) & (w < cut * w.max(axis=1, keepdims=True))
    assert small.any()
    u = np.linspace(0.0, float(d.mean_gap.max()) + 6 * d.h_rms, 64)
    full, part = gap_cdf(d, u), gap_cdf(d, u, negligible=cut)
    np.testing.assert_array_equal(gap_cdf(d, u, negligible=0.0), full)
    left_out = np.sum(np.where(small, w, 0.0), axis=1)[:, None]
    # + round-off: the windows are summed in another grouping once bins are left out, so a few
    # units of 1.1e-16 on values <= 1 (absolute, not relative to values that may be ~0)
    assert np.all(full - part <= left_out * (1 + 1e-12) + 1e-15)
    assert np.all(full - part >= -1e-15)
    # = the CDF of the bins kept (the left-out bins' share here is below round-off)
    kept = dataclasses.replace(d, weight=np.where(small, 0.0, d.weight))
    np.testing.assert_allclose(part, gap_cdf(kept, u), atol=1e-15, rtol=0)


def test_bruggeman_root_is_brents_root():
    """The batched Newton iteration's root = brentq's on the same equation (1e-12 in ln s)."""
    from scipy.optimize import brentq

    from xpersson_interface._leakage import _bruggeman_rows

    rng = np.random.default_rng(3)
    n, k = 12, 200
    sigma = np.exp(rng.uniform(-60.0, 5.0, (n, k)))  # conductances over 28 decades
    m = rng.uniform(0.0, 1.0, (n, k))
    m /= m.sum(axis=1, keepdims=True)
    c = rng.uniform(0.0, 0.9, n)
    got = _bruggeman_rows(c, m, sigma, np.zeros(n), per_row=True)
    for i in range(n):
        if c[i] >= 0.5 * (c[i] + 1.0):
            assert got[i] == 0.0
            continue

        def f(x, i=i):
            r = sigma[i] / (sigma[i] + np.exp(x))
            return -c[i] + np.sum(m[i] * (2.0 * r - 1.0))

        x = brentq(f, -200.0, 50.0, xtol=1e-14, rtol=1e-15)
        assert abs(np.log(got[i]) - x) <= 1e-11 * max(1.0, abs(x))


def test_bruggeman_start_and_bracket_hints_change_no_root():
    """``ln_sigma`` only seeds the Newton start and the bracket: a wrong hint (shifted by 7 or
    reversed) still gives brentq's root to 1e-12 in ln s (more steps only)."""
    from xpersson_interface._leakage import _bruggeman_rows

    rng = np.random.default_rng(5)
    n, k = 10, 240
    sigma = np.exp(np.sort(rng.uniform(-50.0, 0.0, (n, k)), axis=1))
    m = rng.uniform(0.0, 1.0, (n, k))
    m /= m.sum(axis=1, keepdims=True)
    c = rng.uniform(0.0, 0.95, n)
    plain = _bruggeman_rows(c, m, sigma, np.zeros(n), per_row=True)
    for hint in (np.log(sigma), np.log(sigma) + 7.0, np.log(sigma)[:, ::-1]):
        got = _bruggeman_rows(c, m, sigma, np.zeros(n), per_row=True, ln_sigma=hint)
        open_ = plain > 0
        np.testing.assert_array_equal(got > 0, open_)
        np.testing.assert_allclose(np.log(got[open_]), np.log(plain[open_]), rtol=0, atol=2e-12)


def test_full_contact_nodes_are_dropped_without_changing_results(monkeypatch):
    """The dense grid's nodes in exact full contact (every load) are dropped: same outputs
    (which nodes: tests/plugins/test_solved.py)."""
    from xpersson.plugins.solved import _past_full_contact

    an = {"gap_pdf": {}, "leakage": {}, "mean_gap": {}, "contact_stiffness": {}}
    p0 = np.geomspace(1e3, 3e6, 7)
    kept = []

    def spy(area, non, S):
        kept.append((_past_full_contact(area, non, S).size, area.shape[1]))
        return _past_full_contact(area, non, S)

    monkeypatch.setattr(solved, "_past_full_contact", spy)
    trimmed = xpersson.solve(scene(p0, analyses=an))
    assert kept and all(n < 0.8 * total for n, total in kept)  # nodes were dropped
    monkeypatch.setattr(solved, "PLATEAU_MARGIN", 10**9)  # keeps every node
    full = xpersson.solve(scene(p0, analyses=an))
    for name in ("gap_pdf", "gap_mean", "leak_u1", "leak_flow_factor_emt", "mean_gap",
                 "contact_stiffness"):  # fmt: skip
        a, b = trimmed[name].values, full[name].values
        np.testing.assert_allclose(a, b, rtol=1e-13, atol=1e-14 * np.nanmax(np.abs(b)))


@pytest.mark.fast_paths
def test_dense_resolve_of_a_shared_tau_is_the_plain_paths(monkeypatch):
    """``ctx.solve_at`` of a coefficient whose effective tau is tau(zeta) asks tau once and
    hands it to the engine 1-D (broadcast over the loads): the same bits as the plain path,
    where every load's effective tau is asked and checked."""
    from xpersson.pipeline import solve_at
    from xpersson.plugins import plain_paths

    an = {"gap_pdf": {}, "leakage": {}}
    p0 = np.geomspace(1e3, 3e6, 5)
    taus = []
    solve = solve_at._solve

    def spy(rs, ctx, walls, clock, z, idx, tau):
        out = solve(rs, ctx, walls, clock, z, idx, tau)
        taus.append(out["effective_diffusion_time"].strides[0])
        return out

    monkeypatch.setattr(solve_at, "_solve", spy)
    fast = xpersson.solve(scene(p0, analyses=an))
    n_fast = len(taus)  # 1 with the caches on (the analyses share it), one per call without
    with plain_paths():
        plain = xpersson.solve(scene(p0, analyses=an))
    assert n_fast >= 1 and len(taus) > n_fast
    assert all(t == 0 for t in taus[:n_fast])  # broadcast
    assert all(t > 0 for t in taus[n_fast:])  # per load
    for name in ("gap_pdf", "gap_mean", "leak_zeta_c", "leak_u1", "leak_flow_factor_emt"):
        np.testing.assert_array_equal(fast[name].values, plain[name].values, err_msg=name)
