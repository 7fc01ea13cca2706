"""The load table's stencils compiled (:mod:`xpersson_interface._stencil_sums`) and its
one-pass helpers (:func:`._stencils._window_max`, :func:`._stencils._errors`): bit for bit
the numpy path's arithmetic (the stencils, weights, Lebesgue sums, weighted sums, agreement
of values, unusable loads), on random nodes, segments, irregular values and loads beyond the
nodes."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import xpersson
from xpersson_interface import _by_load, _stencil_sums, _stencils


def _case(seed: int, m: int, own: bool):
    """Sorted nodes, segments (runs, some shorter than ``m``), loads (some beyond the nodes),
    per-output logarithms (0 where irregular) and values (runs of equal values and NaN)."""
    rng = np.random.default_rng(seed)
    n = int(rng.integers(max(m, 2), 60))
    xn = np.cumsum(rng.uniform(0.01, 1.0, n)) * 10.0 ** rng.uniform(-3, 3)
    seg = np.cumsum(rng.random(n) < rng.uniform(0.0, 0.3)).astype(np.intp)
    x = np.sort(rng.uniform(xn[0] - 0.5, xn[-1] + 0.5, int(rng.integers(1, 80))))
    seg_x = np.sort(rng.integers(0, seg[-1] + 2, x.size)).astype(np.intp) if own else None
    lz, vals = [], []
    for _ in range(int(rng.integers(0, 4))):
        v = rng.random(n) * 10.0 ** rng.uniform(-200, 200)
        v[rng.random(n) < 0.3] = 0.0
        v[rng.random(n) < 0.2] = np.nan
        for j in np.flatnonzero(rng.random(n) < 0.4)[1:]:  # runs of equal values
            v[j] = v[j - 1]
        with np.errstate(divide="ignore", invalid="ignore"):
            L = np.log(v)
        lz.append(np.where(np.isfinite(L), L, 0.0))
        vals.append(v)
    lz, vals = np.array(lz).reshape(len(lz), n), np.array(vals).reshape(len(vals), n)
    return xn, x, seg, seg_x, lz, vals


def _numpy(xn, x, seg, seg_x, m, lz, vals):
    with xpersson.set_options(compiled=False):
        idx, w, leb, ys, bad, below, alike = _stencils._stencil(xn, x, seg, m, seg_x, lz, vals)
    assert alike is None
    alike = np.array([_stencils._alike(v, idx[:, 0], m) for v in vals]).reshape(ys.shape)
    return idx, w, leb, ys, bad, below, alike


def _same_bits(a, b) -> None:
    for u, v in zip(a, b, strict=True):
        u, v = np.asarray(u), np.asarray(v)
        assert u.shape == v.shape
        assert u.tobytes() == v.astype(u.dtype).tobytes()


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(2, 12), st.booleans())
def test_plain_python_sums_are_numpys(seed, m, own):
    """The kernel's plain-Python form: numpy's stencils, weights, sums and flags, bit for bit."""
    xn, x, seg, seg_x, lz, vals = _case(seed, m, own)
    ref = _numpy(xn, x, seg, seg_x, m, lz, vals)
    idx, w = np.empty((x.size, m), dtype=np.intp), np.empty((x.size, m))
    leb, y = np.empty(x.size), np.empty((len(lz), x.size))
    alike = np.empty(y.shape, dtype=bool)
    bad, below = np.empty(x.size, dtype=bool), np.empty(x.size, dtype=np.intp)
    sx = seg_x if own else seg[:0]
    with np.errstate(divide="ignore", invalid="ignore"):  # (q_aa: unused, as numpy's)
        _stencil_sums.stencil_sums(
            xn, x, seg, sx, own, m, lz, vals, idx, w, leb, y, alike, bad, below
        )
    _same_bits(ref, (idx, w, leb, y, bad, below, alike))


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(2, 12), st.booleans())
def test_compiled_sums_are_numpys(seed, m, own):
    """Compiled: the same bits as the numpy path."""
    pytest.importorskip("numba")
    xn, x, seg, seg_x, lz, vals = _case(seed, m, own)
    ref = _numpy(xn, x, seg, seg_x, m, lz, vals)
    with xpersson.set_options(compiled=True):
        got = _stencil_sums.sums(xn, x, seg, seg_x, m, lz, vals)
    if got is None:
        pytest.skip("kernel not built")
    _same_bits(ref, got)


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 12))
def test_window_max_is_the_gathered_max(seed, m):
    """The largest check error over each stencil: ``np.max(c[idx], axis=1)`` (inf and NaN
    included, fewer nodes than points included)."""
    rng = np.random.default_rng(seed)
    c = rng.random(int(rng.integers(1, 40)))
    c[rng.random(c.size) < 0.1] = np.inf
    c[rng.random(c.size) < 0.05] = np.nan
    start = rng.integers(0, max(c.size - m, 0) + 1, 50)
    idx = start[:, None] + np.arange(m)
    if c.size < m:
        idx = np.clip(idx, 0, c.size - 1)
    want = np.max(c[idx], axis=1)
    assert want.tobytes() == _stencils._window_max(c, idx).tobytes()


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_errors_are_the_per_output_maximum(seed):
    """The check's errors of per-load outputs in one pass: the per-output ``_relative``'s
    maximum (irregular values, zeros and tiny values against ``DEPTH``, rows alongside)."""
    rng = np.random.default_rng(seed)
    n = int(rng.integers(2, 40))
    odd = np.arange(1, n, 2)
    at, vals = {}, {}
    for k in "abcd":
        v = rng.random(n) * 10.0 ** rng.uniform(-40, 40, n)
        v[rng.random(n) < 0.2] = 0.0
        v[rng.random(n) < 0.1] = np.nan
        y = v[odd] * (1.0 + rng.normal(0, 1e-3, odd.size))
        y[rng.random(odd.size) < 0.2] = rng.choice([0.0, np.nan, np.inf])
        at[k], vals[k] = v, y
    at["row"] = rng.random((n, 5))
    vals["row"] = at["row"][odd] * 1.01
    names = sorted(at)
    want = np.zeros(odd.size)
    for k in names:
        top = float(np.abs(np.where(np.isfinite(at[k]), at[k], 0.0)).max())
        want = np.maximum(want, _stencils._relative(vals[k], at[k][odd], top))
    assert want.tobytes() == _stencils._errors(vals, at, odd, names).tobytes()


def test_table_compiled_is_numpys():
    """A whole table (keys, sealed stretches, a transformed output), compiled and not: the
    same outputs and estimates, bit for bit."""
    pytest.importorskip("numba")
    p0 = np.geomspace(1e3, 1e6, 700)

    def exact(rows):
        p = p0[rows]
        sealed = (p > 2e5).astype(float)
        return {
            "area": np.where(sealed > 0, 0.0, (p / 2e5) ** 1.7),
            "flag": sealed,
            "piece": (p > 2e4).astype(float),
            "rate": np.where(sealed > 0, 0.0, np.exp(-p / 1e5) * (1 + 0.1 * np.sin(np.log(p)))),
        }

    def weight(o, x):
        return np.full(x.size, 2.0), np.zeros(x.size)

    args = dict(
        tol=1e-4, keys=frozenset({"flag", "piece"}), weights=((frozenset({"rate"}), weight),)
    )
    with xpersson.set_options(compiled=False):
        ref = _by_load.by_load(p0, exact, **args)
    with xpersson.set_options(compiled=True):
        assert _stencil_sums.kernel() is not None
        got = _by_load.by_load(p0, exact, **args)
    assert ref[1].tobytes() == got[1].tobytes()
    assert ref[0].keys() == got[0].keys()
    for k in ref[0]:
        assert ref[0][k].tobytes() == got[0][k].tobytes()
    assert np.any(ref[1] > 0)  # (interpolated loads)


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_node_chain_is_numpys(seed):
    """The table's nodes about ``h`` apart, plain Python and compiled: numpy's indices (ties,
    spacings below and above ``h``, a single value)."""
    rng = np.random.default_rng(seed)
    xs = np.sort(np.round(rng.uniform(0, 10, int(rng.integers(1, 300))), int(rng.integers(1, 4))))
    h = float(rng.choice([0.0, rng.uniform(0, 0.5), rng.uniform(0, 20)]))
    with xpersson.set_options(compiled=False):
        want = _by_load._nodes(xs, h)
    out = np.empty(xs.size, dtype=np.intp)
    assert np.array_equal(out[: _stencil_sums.node_chain(xs, h, out)], want)
    pytest.importorskip("numba")
    with xpersson.set_options(compiled=True):
        got = _stencil_sums.chain(xs, h)
    if got is None:
        pytest.skip("kernel not built")
    assert np.array_equal(got, want)


def _row_case(seed: int):
    """Node rows of logarithms (NaN, -inf, wide magnitudes, a row of NaN), loads' stencils
    sorted by their first node (runs, some of one load), weights of either sign."""
    rng = np.random.default_rng(seed)
    m = int(rng.integers(1, 10))
    nn, nc = int(rng.integers(m, 40)), int(rng.integers(1, 30))
    L = rng.normal(0, 10.0 ** rng.uniform(-2, 2), (nn, nc)) - rng.uniform(0, 50)
    L[rng.random(L.shape) < 0.05] = -np.inf
    L[rng.random(L.shape) < 0.03] = np.nan
    if rng.random() < 0.3:
        L[int(rng.integers(nn))] = np.nan
    first = np.sort(rng.integers(0, nn - m + 1, int(rng.integers(1, 200))))
    idx = (first[:, None] + np.arange(m)).astype(np.intp)
    w = rng.normal(0, 1, idx.shape) * 10.0 ** rng.uniform(-1, 1, idx.shape)
    return L, idx, w


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1), st.booleans())
def test_row_sums_are_numpys(seed, test):
    """The rows' weighted sums and spike flags (:func:`._stencils._rows`), plain Python and
    compiled: numpy's values and flags, bit for bit (NaN and -inf elements and limits; a
    NaN's sign aside)."""
    L, idx, w = _row_case(seed)
    with xpersson.set_options(compiled=False), np.errstate(all="ignore"):
        want, spikes = _stencils._rows(L, idx, w, test)
        limits = _stencils._spike_limits(L, idx, w) if test else (np.empty(0),) * 2 + (L[:0],)
    out, flag = np.empty(want.shape), np.zeros(idx.shape[0], dtype=bool)
    with np.errstate(all="ignore"):
        _stencil_sums.row_sums(L, idx, w, 0, idx.shape[0], test, *limits, out, flag)
        np.exp(out, out=out)
    _same_values(out, want)
    assert np.array_equal(flag, spikes)
    pytest.importorskip("numba")
    with xpersson.set_options(compiled=True), np.errstate(all="ignore"):
        if _stencil_sums.kernel("row_sums") is None:
            pytest.skip("kernel not built")
        got, got_spikes = _stencils._rows(L, idx, w, test)
    _same_values(got, want)
    assert np.array_equal(got_spikes, spikes)


def _same_values(a, b) -> None:
    """The same bits, NaN's sign aside (a NaN's sign bit is no value)."""
    nan = np.isnan(a)
    assert np.array_equal(nan, np.isnan(b))
    assert a[~nan].tobytes() == b[~nan].tobytes()
