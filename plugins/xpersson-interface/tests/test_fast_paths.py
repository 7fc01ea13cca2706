"""The batched fast paths equal the per-load and scipy forms they replace (issue 25)."""

from __future__ import annotations

import dataclasses
import gc

import numpy as np
import pytest
from interface_testlib import E_STAR, detach, scene
from scipy.interpolate import CubicSpline

import xpersson
from xpersson.physics import gap_cdf, gap_pdf
from xpersson.physics._fastnum import _exp, _row_spline
from xpersson_interface import _solved, bruggeman_gap

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
    """mean_gap, contact_stiffness and gap_pdf of one solve build one SolvedContact."""
    gc.collect()
    before = len(_solved.SOLVES)
    made = []
    real = xpersson.physics.SolvedContact

    class Counting(real):
        def __init__(self, *a, **k):
            made.append(1)
            super().__init__(*a, **k)

    xpersson.physics.SolvedContact = Counting
    try:
        an = {"mean_gap": {}, "contact_stiffness": {}, "gap_pdf": {}}
        ds = xpersson.solve(scene(LOADS, analyses=an))
        alone = xpersson.solve(scene(LOADS, analyses={"gap_pdf": {}}))
    finally:
        xpersson.physics.SolvedContact = real
    assert len(made) == 2  # one per solve
    np.testing.assert_array_equal(ds["gap_pdf"].values, alone["gap_pdf"].values)
    gc.collect()
    assert len(_solved.SOLVES) == before  # nothing outlives the solve
