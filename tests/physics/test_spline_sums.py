"""The compiled sums of Phi's spline (:mod:`xpersson.physics._spline_sums`): the numpy path's
bits (``_sub_mean_gap``'s ``spline`` branch: ``separation_at``'s difference quotient)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import xpersson
from xpersson.physics import _compiled, _spline_sums, _subgap
from xpersson.physics._fastnum import _row_spline
from xpersson.physics._phi import _Phi


def _phi(rng: np.random.Generator, n_load: int, n_knot: int) -> _Phi:
    """A ``_Phi`` of ``n_load`` random increasing curves on ``n_knot`` knots in ``ln tau``
    (some loads 0 at the first knot: the linear first interval then 0)."""
    phi = object.__new__(_Phi)
    s = np.sort(rng.uniform(-5.0, 20.0, n_knot))
    inc = rng.exponential(1.0, (n_load, n_knot)) * (rng.random((n_load, n_knot)) < 0.8)
    phi.phi = np.concatenate((np.zeros((n_load, 1)), np.cumsum(inc, axis=1)), axis=1)
    phi.tau1, phi.s, phi.p0 = math.exp(s[0]), s, np.ones(n_load)
    phi._spl, phi._tab = _row_spline(s, phi.phi[:, 1:]), None
    return phi


def _numpy(phi: _Phi, log_tc, kern, log_a2) -> np.ndarray:
    """The numpy loop of ``_sub_mean_gap``'s spline branch (one block of every load)."""
    with np.errstate(invalid="ignore"):
        lt = log_tc + log_a2
    vals = phi.spline_at_log_tau_per_load(lt, slice(0, lt.shape[0]))
    vals *= kern
    return vals.sum(axis=-1)


@pytest.mark.parametrize("compiled", [False, True])
@settings(max_examples=30, deadline=None)
@given(
    st.integers(0, 2**32 - 1),
    st.integers(1, 5),
    st.integers(1, 3),
    st.integers(1, 140),
    st.integers(4, 30),
)
def test_kernel_gives_the_numpy_bits(compiled, seed, n_load, n_edge, m, n_knot):
    """Random curves and arguments below the first knot (the linear interval, its exp), beyond
    the last, at knots, -inf (zero area) and NaN: every sum bit for bit the numpy path's;
    more than 128 nodes per row left to numpy."""
    if compiled:
        pytest.importorskip("numba")
        fn = _compiled.kernel(math.inf, "spline_sub_sums")
        if fn is None:
            pytest.skip("compiled kernels are off (XPERSSON_COMPILED=off)")
    else:
        fn = _spline_sums.spline_sub_sums
    rng = np.random.default_rng(seed)
    phi = _phi(rng, n_load, n_knot)
    log_tc = rng.uniform(phi.s[0] - 3.0, phi.s[-1] + 3.0, (n_load, n_edge, m))
    log_tc[..., : m // 3] = rng.choice(phi.s, (n_load, n_edge, m // 3))
    log_a2 = 2.0 * np.log(rng.uniform(0.0, 1.0, (n_load, n_edge, 1)))
    log_a2[rng.random(log_a2.shape) < 0.1] = -np.inf
    log_a2[rng.random(log_a2.shape) < 0.05] = np.nan
    kern = rng.exponential(1.0, (n_load, n_edge, m)) * 10.0 ** rng.uniform(-5, 5)
    want = _numpy(phi, log_tc, kern, log_a2)
    got = np.full(want.shape, -1.0)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(_subgap, "kernel", lambda work, name: fn)
        done = _subgap._compiled_spline_sums(phi, log_tc, kern, log_a2, got)
    assert done == (m <= _compiled.PAIRWISE)
    if done:
        np.testing.assert_array_equal(got, want)


def test_off_switch_keeps_numpy():
    phi = _phi(np.random.default_rng(1), 2, 6)
    out = np.zeros((2, 1))
    with xpersson.set_options(compiled=False):
        assert not _subgap._compiled_spline_sums(
            phi, np.zeros((2, 1, 4)), np.ones((2, 1, 4)), np.zeros((2, 1, 1)), out
        )
