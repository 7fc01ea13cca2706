"""Band-limited sums of the gap kernels (:mod:`xpersson.physics._gap_band`)."""

from __future__ import annotations

import numpy as np
import pytest

from xpersson.physics._gap_band import _add, dominant, stable_order, windowed_sum


@pytest.mark.parametrize("span", [50, 100_000])  # a slice of out, or the touched entries only
def test_add_is_bincount_bit_for_bit(span):
    """Each touched entry gets the block's sum in input order, as ``np.bincount`` forms it."""
    rng = np.random.default_rng(span)
    out = rng.normal(size=span + 7)
    ref = out.copy()
    slot = np.full(out.size, -7, dtype=np.intp)  # stale scratch: never read before written
    for _ in range(4):
        idx = rng.integers(3, span + 3, size=200)
        v = rng.normal(size=200) * 10.0 ** rng.integers(-8, 8, size=200)
        ref += np.bincount(idx, weights=v, minlength=ref.size)
        _add(out, idx, v, slot)
    assert out.tobytes() == ref.tobytes()


def test_windowed_sum_is_the_dense_sum_at_many_loads():
    """Sum over each term's window per load equals the dense (term, u) sum (many loads: the
    blocks span only some of them)."""
    rng = np.random.default_rng(1)
    n_load, n_u, n_term = 300, 40, 3000
    load = np.sort(rng.integers(0, n_load, n_term))
    j0 = rng.integers(0, n_u, n_term)
    j1 = np.minimum(j0 + rng.integers(0, 25, n_term), n_u)
    a = rng.normal(size=n_term)

    def values(t, cols):
        return np.cos(a[t] * cols)

    dense = np.zeros((n_load, n_u))
    for t in range(n_term):
        cols = np.arange(j0[t], j1[t])
        dense[load[t], cols] += np.cos(a[t] * cols)
    got = windowed_sum(load, j0, j1, (n_load, n_u), values)
    np.testing.assert_allclose(got, dense, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("top", [3, 130, 40_000, 1 << 40])  # 16-bit keys (radix) and wider
def test_stable_order_is_the_stable_argsort(top):
    """A stable order is unique: the radix sort of 16-bit keys gives numpy's merge sort's."""
    rng = np.random.default_rng(top % 1000)
    key = rng.integers(-top if top < 1000 else 0, top, size=5000).astype(np.intp)
    key[::7] = key[0]  # many ties
    got = stable_order(key)
    assert got.dtype == np.intp
    np.testing.assert_array_equal(got, np.argsort(key, kind="stable"))
    assert stable_order(key[:0]).size == 0


def test_the_minimum_of_a_decreasing_value_is_among_the_dominant_terms():
    """``min((c_n - r) / d_n - s)`` over the terms :func:`dominant` keeps is the minimum over
    every term, bit for bit (ties, ``-inf``), and every term is kept where one has a NaN."""
    rng = np.random.default_rng(5)
    c = np.log(1e-18) - np.log(rng.uniform(1.0, 100.0, 16))[:, None]
    d = (2 * np.arange(16) + 1)[:, None]
    for t in range(200):
        n = int(rng.integers(1, 3000))
        r = np.round(rng.normal(size=n) * 5.0, int(rng.integers(0, 4)))  # (ties)
        s = np.round(rng.normal(size=n), int(rng.integers(0, 3)))
        r[rng.integers(0, n, 3 * (t % 2))] = -np.inf
        kept_r, kept_s = dominant(r, s)
        assert kept_r.size <= n
        with np.errstate(invalid="ignore"):
            every = np.min((c - r) / d - s, axis=1)
            kept = np.min((c - kept_r) / d - kept_s, axis=1)
        assert np.exp(every).tobytes() == np.exp(kept).tobytes()
    s[0] = np.nan
    assert dominant(r, s)[0].size == n
