"""The compiled step of the Bruggeman Newton (:mod:`xpersson_interface._newton`): its
reductions in numpy's orders, and the whole root bit for bit the numpy path's."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from xpersson_interface import _newton


def _compiled_or_skip():
    pytest.importorskip("numba")
    import xpersson

    with xpersson.set_options(compiled=True):
        fn = _newton.kernel()
    if fn is None:
        pytest.skip("numba not importable")
    return fn


def _row(rng: np.random.Generator, n: int) -> np.ndarray:
    """Non-negative values over many decades, with zeros (the products of the cells)."""
    a = rng.random(n) * 10.0 ** rng.uniform(-30, 5, n)
    a[rng.random(n) < 0.1] = 0.0
    return a


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(0, _newton.MAX_CELLS))
def test_reductions_take_numpys_orders(seed, n):
    """The pairwise row sum and the einsum row dot, plain Python: numpy's bits (rows of 0 to
    MAX_CELLS elements, several rows: each row's as numpy reduces a 2-D array)."""
    rng = np.random.default_rng(seed)
    a, b = np.stack([_row(rng, n) for _ in range(3)]), np.stack([_row(rng, n) for _ in range(3)])
    sums, dots = a.sum(axis=1), np.einsum("ij,ij->i", a, b)
    for i in range(3):
        assert 0.0 + _newton._pairwise_sum(a[i], n) == sums[i]
        assert 0.0 + _newton._einsum_dot(a[i], b[i], n) == dots[i]


def test_numpy_orders_are_checked(monkeypatch):
    """This numpy takes the reproduced orders; a step whose dot were summed in another order
    (sequentially) is refused: the numpy path would run."""
    assert _newton.numpy_orders()

    def sequential(a, b, n):
        t = 0.0
        for i in range(n):
            t += a[i] * b[i]
        return t

    monkeypatch.setattr(_newton, "_einsum_dot", sequential)
    assert not _newton.numpy_orders()


def _problem(rng: np.random.Generator, n: int, k: int):
    """Random Bruggeman rows as ``_bruggeman_rows`` hands them to ``newton``: the start, the
    brackets, masses and conductances over many decades, the constant term."""
    m = rng.random((n, k)) * (rng.random((n, k)) < 0.9)
    s_k = 10.0 ** rng.uniform(-12, 3, (n, k))
    c, m_inf = rng.random(n) * 0.3 * m.sum(axis=1), rng.random(n) * 0.1
    ln_s = np.log(s_k)
    lo, hi = ln_s.min(axis=1) - 60.0, ln_s.max(axis=1) + 60.0
    x = np.einsum("ij,ij->i", m, ln_s) / np.maximum(m.sum(axis=1), 1e-300)
    x = np.where((x > lo) & (x < hi), x, 0.5 * (lo + hi))
    x[rng.random(n) < 0.2] = lo[0] + 1.0  # far starts: bisection steps
    return x, lo, hi, m, s_k, m_inf - c - m.sum(axis=1)


@pytest.mark.parametrize("compiled", [False, True])
@settings(max_examples=25, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 6), st.integers(1, 300))
def test_compiled_newton_is_the_numpy_newton(compiled, seed, n, k):
    """Roots, brackets and the number of steps of each row: bit for bit the numpy loop's."""
    fn = _compiled_or_skip() if compiled else _newton.newton_step
    rng = np.random.default_rng(seed)
    args = _problem(rng, n, k)
    want = [a.copy() for a in args[:3]]
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(_newton, "kernel", lambda: None)
        _newton.newton(*want, *args[3:], 1e-12)
    got = [a.copy() for a in args[:3]]
    with pytest.MonkeyPatch.context() as mp, np.errstate(all="ignore"):
        mp.setattr(_newton, "kernel", lambda: fn)
        _newton.newton(*got, *args[3:], 1e-12)
    for g, w in zip(got, want, strict=True):
        np.testing.assert_array_equal(g, w)
    assert np.all(np.isfinite(got[0]))
    assert math.isfinite(float(np.exp(got[0]).sum()))
