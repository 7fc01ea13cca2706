"""The fast gap kernels against plain references over every element (issue 25).

``gap_cdf`` uses a table erf (``fast_erf``, within 2e-13 of scipy's), a Taylor series of
``erf(a + b) - erf(a - b)`` for ``u/(sqrt2 h) <= 0.5`` and evaluates each bin only where its
terms vary; ``gap_pdf`` evaluates each bin only within 39 of its widths. The references below
are the defining sums written plainly (scipy's ``erf`` / numpy's ``exp`` on the whole tensor).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from interface_testlib import E_STAR, detach
from scipy.special import erf

from xpersson.physics import gap_cdf, gap_pdf
from xpersson.physics._fasterf import (
    ERF_DIFF_B,
    ERF_DIFF_ERROR,
    ERF_ERROR,
    erf_diff_coefficients,
    erf_nonneg,
    fast_erf,
)
from xpersson_interface import _leakage, bruggeman_gap

LOADS = np.geomspace(2e3, 3e6, 9)  # A/A0 about 1e-3 .. 0.9


def cdf_reference(det, u):
    """``0.5 sum_k w [erf((u - u1)/(sqrt2 h)) + erf((u + u1)/(sqrt2 h))]`` on every element."""
    u = np.asarray(u, dtype=float)
    uu = u[:, None, :] if u.ndim == 2 else u[None, None, :]
    s = np.sqrt(2.0) * det.h[None, :, None]
    t = erf((uu - det.u1[:, :, None]) / s) + erf((uu + det.u1[:, :, None]) / s)
    return 0.5 * np.einsum("lk,lku->lu", det.weight, t)


def pdf_reference(det, u):
    """``sum_k w [N(u; u1, h^2) + N(u; -u1, h^2)]`` on every element, each element formed as
    gap_pdf forms it (``b = u/h``, ``a = u1/h``, ``exp(-(b - a)^2/2) (1 + exp(-2ab))``): the
    far tails' relative round-off (``~ eps |b| |b - a|``, 2e-12 at 1e-258 here) is then shared
    and only the order of the sum differs."""
    inv = 1.0 / det.h
    b = u[None, None, :] * inv[None, :, None]
    a = det.u1[:, :, None] * inv[None, :, None]
    with np.errstate(over="ignore", under="ignore"):  # bins of h = 0: exp(-inf) = 0
        g = np.exp(-0.5 * (b - a) ** 2) * (1.0 + np.exp(-2.0 * a * b))
    return np.einsum("lk,lku->lu", det.weight * inv / np.sqrt(2 * np.pi), g)


@pytest.fixture(scope="module")
def det(psd):
    return detach(psd, E_STAR, LOADS, n=150)


def test_fast_erf_within_its_bound_on_a_fine_grid():
    x = np.linspace(-7.0, 7.0, 1_400_001)
    err = np.abs(fast_erf(x) - erf(x))
    assert err.max() <= ERF_ERROR  # 1.67e-13 measured: the interpolation bound h^4/384 max|erf''''|
    assert err.max() > 1e-14  # (the bound is tight: this is not scipy's erf)
    np.testing.assert_array_equal(fast_erf(-x), -fast_erf(x))  # exactly odd


@settings(max_examples=300, deadline=None)
@given(st.floats(-1e300, 1e300, allow_nan=False))
def test_fast_erf_property(x):
    got = fast_erf(np.array([x]))[0]
    assert abs(got - erf(x)) <= ERF_ERROR
    if abs(x) >= 6.0:
        assert got == np.sign(x)


def test_erf_nonneg_is_fast_erf_bit_for_bit():
    x = np.concatenate((np.linspace(0.0, 7.0, 200_001), [5.999999999, 6.0, 1e300, np.inf, 0.0]))
    np.testing.assert_array_equal(erf_nonneg(x.copy()), fast_erf(x))


def test_fast_erf_is_non_decreasing_across_every_node():
    """Consecutive doubles around every table node (and zero) never step down."""
    nodes = np.arange(0, 6 * 512 + 1) / 512.0
    steps = np.arange(-300, 301)
    x = nodes[:, None] + steps[None, :] * np.spacing(np.maximum(nodes, 1e-300))[:, None]
    x[0] = steps * 5e-324
    x = np.unique(np.concatenate((-x.ravel(), x.ravel())))  # sorted
    assert np.all(np.diff(fast_erf(x)) >= 0.0)
    assert np.all(np.diff(fast_erf(np.linspace(-8.0, 8.0, 2_000_001))) >= 0.0)


def test_erf_difference_series_within_its_bound():
    a = np.linspace(0.0, 6.0, 601)
    b = np.linspace(0.0, ERF_DIFF_B, 201)
    c = erf_diff_coefficients(a)
    b2 = b[None, :] ** 2
    s = np.zeros((a.size, b.size))
    for n in range(c.shape[0] - 1, -1, -1):
        s = s * b2 + c[n][:, None]
    ref = erf(a[:, None] + b[None, :]) - erf(a[:, None] - b[None, :])
    # the truncation bound plus scipy's and the sum's round-off (a few 1.1e-16)
    np.testing.assert_allclose(s * b[None, :], ref, rtol=0.0, atol=ERF_DIFF_ERROR + 1e-15)


def _grids(det):
    top = float(det.mean_gap.max()) + 10.0 * det.h_rms
    shared = np.concatenate(([0.0], np.geomspace(1e-6 * det.h_rms, top, 240)))
    per = np.geomspace(1e-6 * det.h_rms, det.mean_gap + 10.0 * det.h_rms, 240, axis=1)
    per = np.concatenate((np.zeros((det.p0.size, 1)), per), axis=1)
    lin = np.linspace(0.0, top, 97)
    return {"shared": shared, "per_load": per, "linear": lin}


@pytest.mark.parametrize("grid", ["shared", "per_load", "linear"])
def test_gap_cdf_within_1e_12_of_the_exact_sum_and_non_decreasing(det, grid):
    u = _grids(det)[grid]
    got, ref = gap_cdf(det, u), cdf_reference(det, u)
    total = det.weight.sum(axis=1, keepdims=True)
    # fast_erf / series error times the detached area, plus round-off
    assert np.all(np.abs(got - ref) <= ERF_ERROR * total + 1e-15)
    assert np.all(np.diff(got, axis=1) >= 0.0)  # masses of the Bruggeman cells >= 0
    np.testing.assert_array_equal(got[:, 0], 0.0)  # int_0^0


def test_gap_cdf_unsorted_or_negative_u_take_the_dense_path(det):
    u = _grids(det)["linear"]
    total = det.weight.sum(axis=1, keepdims=True)
    perm = np.random.default_rng(0).permutation(u.size)
    for v in (u[perm], np.concatenate((-u[::-1], u))):
        assert np.all(np.abs(gap_cdf(det, v) - cdf_reference(det, v)) <= ERF_ERROR * total + 1e-15)


@pytest.mark.parametrize("grid", ["linear", "shuffled"])
def test_gap_pdf_within_rtol_1e_12_of_the_exact_sum(det, grid):
    u = np.linspace(0.0, float(det.mean_gap.max()) + 6 * det.h_rms, 256)
    if grid == "shuffled":
        u = u[np.random.default_rng(1).permutation(u.size)]
    np.testing.assert_allclose(gap_pdf(det, u), pdf_reference(det, u), rtol=1e-12, atol=1e-300)


def test_nan_weight_spoils_its_load_only(det):
    w = det.weight.copy()
    w[3, np.flatnonzero(w[3])[0]] = np.nan
    bad = dataclasses.replace(det, weight=w)
    u = _grids(det)["linear"]
    for f in (gap_cdf, gap_pdf):
        got, good = f(bad, u), f(det, u)
        assert np.isnan(got[3]).all()
        np.testing.assert_allclose(np.delete(got, 3, 0), np.delete(good, 3, 0), rtol=1e-14)


@pytest.mark.parametrize("per_load", [False, True])
def test_bruggeman_gap_equals_the_exact_cdfs(det, per_load, monkeypatch):
    """The leakage's effective medium on the fast CDF = on the plain scipy-erf CDF (1e-9)."""
    fast = bruggeman_gap(det, a_c=0.42, per_load=per_load)

    def exact(d, u, negligible=0.0):
        w = np.where(np.abs(d.weight) < negligible * d.weight.max(axis=1, keepdims=True), 0, 1)
        return cdf_reference(dataclasses.replace(d, weight=d.weight * w), u)

    monkeypatch.setattr(_leakage, "gap_cdf", exact)
    ref = bruggeman_gap(det, a_c=0.42, per_load=per_load)
    np.testing.assert_allclose(fast, ref, rtol=1e-9, atol=0.0)
    assert np.all(np.isfinite(fast))


def test_gap_cdf_leaves_u_unchanged_in_either_memory_order(det):
    """Rows laid out column-major (``np.geomspace(..., axis=1)`` gives such) are read, never
    written, and give the row-major result bit for bit."""
    per = _grids(det)["per_load"]
    f_order, c_order = np.asfortranarray(per), np.ascontiguousarray(per)
    keep = f_order.copy()
    got = gap_cdf(det, f_order, negligible=_leakage.NEGLIGIBLE)
    np.testing.assert_array_equal(f_order, keep)
    np.testing.assert_array_equal(got, gap_cdf(det, c_order, negligible=_leakage.NEGLIGIBLE))


def test_rank_is_searchsorted_per_row():
    """The geometric guess (kept only where confirmed) + bisection = numpy's per-row count."""
    from xpersson.physics._gap_band import rank

    rng = np.random.default_rng(7)
    for kind in range(4):
        n, m = 6, 40
        if kind == 0:  # the leakage cells: 0, then geometric per row
            u = np.geomspace(1e-12, rng.uniform(1e-6, 1e-4, n), m - 1, axis=1)
            u = np.concatenate((np.zeros((n, 1)), u), axis=1)
        elif kind == 1:
            u = np.sort(rng.uniform(0.0, 1.0, (n, m)), axis=1)
        elif kind == 2:  # ties
            u = np.sort(rng.integers(0, 6, (n, m)).astype(float), axis=1)
        else:  # geometric with a repeated first entry and an infinite last one
            u = np.concatenate(
                (np.zeros((n, 2)), np.geomspace(1e-3, 1.0, m - 2)[None].repeat(n, 0)), 1
            )
            u[:, -1] = np.inf
        row = rng.integers(0, n, 400)
        x = np.concatenate(
            (
                u[row[:150], rng.integers(0, m, 150)],  # the entries themselves
                rng.uniform(-0.5, 1.5, 150) * np.nanmax(u[np.isfinite(u)]),
                [np.nan, np.inf, -np.inf, 0.0, -0.0] * 10,
                np.geomspace(1e-14, 10.0, 50),
            )
        )
        ref = np.array(
            [
                np.searchsorted(u[r], v) if not np.isnan(v) else 0
                for r, v in zip(row, x, strict=True)
            ]
        )
        np.testing.assert_array_equal(rank(u, row, x), ref)


def test_windowed_sum_without_padding_is_the_plain_sum():
    """Windows of widely spread widths (laid along one row, unpadded) = a plain loop."""
    from xpersson.physics._gap_band import windowed_sum

    rng = np.random.default_rng(11)
    n_load, n_u, n_term = 5, 300, 400
    width = np.where(
        rng.random(n_term) < 0.9, rng.integers(0, 3, n_term), rng.integers(50, 300, n_term)
    )
    j0 = rng.integers(0, n_u - width + 1)
    load, scale = rng.integers(0, n_load, n_term), rng.normal(size=n_term)

    def values(t, cols):
        return np.sin(0.01 * cols * (1.0 + t % 7)) * scale[t]

    ref = np.zeros((n_load, n_u))
    for t in range(n_term):
        cols = np.arange(j0[t], j0[t] + width[t])
        ref[load[t], cols] += values(np.array([t]), cols)
    got = windowed_sum(load, j0, j0 + width, (n_load, n_u), values)
    np.testing.assert_allclose(got, ref, rtol=1e-13, atol=1e-13)
