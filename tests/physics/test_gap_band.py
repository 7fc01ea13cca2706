"""Band-limited sums of the gap kernels (:mod:`xpersson.physics._gap_band`)."""

from __future__ import annotations

import numpy as np
import pytest

from xpersson.physics._gap_band import _add, windowed_sum


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
