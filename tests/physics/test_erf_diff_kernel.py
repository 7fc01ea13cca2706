"""The compiled Hermite recurrence of the gap CDF's series (issue 36): the numpy coefficients'
bits, from its plain-Python form and, with numba, compiled."""

from __future__ import annotations

import math

import numpy as np
import pytest

import xpersson
from xpersson.physics import _compiled, _gap_distribution
from xpersson.physics._fasterf import erf_diff_coefficients


@pytest.mark.parametrize("compiled", [False, True])
def test_erf_diff_series_gives_the_numpy_coefficients_bit_for_bit(monkeypatch, compiled):
    """``_erf_diff`` through the kernel: every row of ``erf_diff_coefficients(a, factor, q2)``
    bit for bit, ``a`` across the clip at 6 and the Hermite polynomials' sign changes."""
    if compiled:
        pytest.importorskip("numba")
        fn = _compiled.kernel(math.inf, "erf_diff_series")
        if fn is None:
            pytest.skip("compiled kernels are off (XPERSSON_COMPILED=off)")
    else:
        fn = _compiled.erf_diff_series
    monkeypatch.setattr(_gap_distribution, "_compiled_kernel", lambda work, name: fn)
    rng = np.random.default_rng(36)
    for n in (1, 3, 40):
        a = np.concatenate((rng.uniform(0.0, 8.0, n), [0.0, 6.0, 7.5]))
        factor, q2 = rng.uniform(-1.0, 1.0, a.size), rng.uniform(1e-9, 1.0, a.size)
        got = _gap_distribution._erf_diff(a, factor, q2)
        with xpersson.set_options(compiled=False):
            want = erf_diff_coefficients(a, factor, q2)
        assert got.shape == want.shape == (16, a.size)
        np.testing.assert_array_equal(got, want)
