"""The compiled kernels of the leak analysis's direct call (:mod:`xpersson.physics._phi_sums`):
``df_logs`` and ``df_sums`` (the Stieltjes nodes' ``ln(1 - F)`` and the sums of ``-dF``) and
``table_sums`` (``Phi``'s shared sums without the CSR matrix) give the numpy path's bits,
compiled and as plain Python."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import xpersson
from xpersson.physics import _compiled, _curve, _fastnum, _phi, _phi_sums, _spline_sums
from xpersson.physics._fastnum import _row_spline

#: The kernels of the spline (:func:`~xpersson.physics._fastnum._row_spline`, ``_ppoly_at``).
SLOPES = ("spline_rhs", "spline_slopes", "spline_coefficients", "spline_values")


def _kernel(compiled: bool, name: str):
    if not compiled:
        return getattr(_phi_sums, name)
    pytest.importorskip("numba")
    with xpersson.set_options(compiled=True):  # (built even under XPERSSON_COMPILED=off)
        fn = _compiled.kernel(math.inf, name)
    if fn is None:
        pytest.skip("numba not importable")
    return fn


def _special(rng: np.random.Generator, a: np.ndarray, share: float = 0.05) -> None:
    """Put signed zeros, infinities and NaN into ``a`` (in place)."""
    for v in (0.0, -0.0, np.inf, -np.inf, np.nan):
        a[rng.random(a.shape) < share] = v


def _numpy_poly(c, jb, k0, d, off, stop, rows, n):
    """The numpy form of ``_Curve._dF_blocks`` (its polynomial passes) and ``_quiet_rows``."""
    ck = c[:, jb : jb + n, k0 : k0 + rows]
    cc = np.moveaxis(ck, -1, 0)[:, :, None, :]  # (rows, 4, 1, n)
    c0, c1, c2, c3 = (cc[:, j] for j in range(4))
    db = d[:, off : off + n]
    with np.errstate(all="ignore"):
        y = np.multiply(c0, db)
        y += c1
        y *= db
        y += c2
        y *= db
        y += c3
        np.minimum(y, 0.0, out=y)
        dy = np.multiply(3.0 * c0, db)
        dy += 2.0 * c1
        dy *= db
        dy += c2
        np.maximum(dy, 0.0, out=dy)
    _curve._quiet_rows(dy, stop)
    return y, dy


@pytest.mark.parametrize("compiled", [False, True])
@settings(max_examples=40, deadline=None)
@given(
    st.integers(0, 2**32 - 1),
    st.integers(1, 5),
    st.integers(1, 7),
    st.integers(0, 40),
    st.integers(0, 3),
    st.booleans(),
)
def test_df_kernels_give_the_numpy_bits(compiled, seed, rows, m, n, jb, special):
    """Random coefficients (with signed zeros, infinities and NaN), blocks from a later
    interval, load and abscissa column on, each row's quiet intervals (none, some, more than
    the block's): ``df_logs``' ``y`` and its minimum, and ``df_sums``' node sums of
    ``dy exp(y) w`` bit for bit the numpy passes' (``_Curve._dF_blocks`` and
    ``dF_weighted``), nothing else written."""
    logs, sums = _kernel(compiled, "df_logs"), _kernel(compiled, "df_sums")
    rng = np.random.default_rng(seed)
    k0, off, start = (int(v) for v in rng.integers(0, 3, 3))
    c = rng.normal(0.0, 1.0, (4, jb + n + 1, k0 + rows + 1)) * 10.0 ** rng.uniform(-3, 3)
    d = rng.uniform(0.0, 0.2, (m, off + n))
    w_t = rng.uniform(0.1, 2.0, (m, start + n + 1))
    if special:
        _special(rng, c)
        _special(rng, d, 0.02)
    stop = rng.integers(-2, n + 3, rows).astype(np.intp)
    want_y, want_dy = _numpy_poly(c, jb, k0, d, off, stop, rows, n)
    y = np.full((n, m, rows), -1.0)
    out = np.full((k0 + rows + 1, start + n + 1), 7.0)
    with np.errstate(all="ignore"):  # (the plain-Python form on numpy scalars)
        low = logs(c, jb, k0, d, off, y)
        want_dy *= np.exp(want_y)
        want_dy *= w_t[:, start : start + n]
        sums(c, jb, k0, d, off, stop, np.exp(y), w_t, start, out)
    np.testing.assert_array_equal(y, want_y.transpose(2, 1, 0))
    assert not np.signbit(y[y == 0.0]).any()
    want_low = want_y.min() if want_y.size else 0.0
    assert low == want_low or (math.isnan(low) and math.isnan(want_low))
    np.testing.assert_array_equal(out[k0 : k0 + rows, start : start + n], want_dy.sum(axis=1))
    out[k0 : k0 + rows, start : start + n] = 7.0
    assert np.all(out == 7.0)


def _phi_of(rng: np.random.Generator, n_load: int, n_knot: int, zero_rows: int) -> _phi._Phi:
    """A ``_Phi`` of ``n_load`` random increasing curves on ``n_knot`` knots in ``ln tau``, the
    first ``zero_rows`` knots 0 for every load (the table's leading zero nodes)."""
    phi = object.__new__(_phi._Phi)
    s = np.sort(rng.uniform(-5.0, 20.0, n_knot))
    inc = rng.exponential(1.0, (n_load, n_knot)) * (rng.random((n_load, n_knot)) < 0.8)
    inc[:, :zero_rows] = 0.0
    phi.phi = np.concatenate((np.zeros((n_load, 1)), np.cumsum(inc, axis=1)), axis=1)
    phi.tau1, phi.s, phi.p0 = math.exp(s[0]), s, np.ones(n_load)
    phi._spl, phi._tab = _row_spline(s, phi.phi[:, 1:]), None
    return phi


@pytest.mark.parametrize("compiled", [False, True])
@settings(max_examples=30, deadline=None)
@given(
    st.integers(0, 2**32 - 1),
    st.integers(1, 6),
    st.integers(1, 4),
    st.integers(1, 30),
    st.integers(4, 30),
    st.integers(0, 12),
)
def test_table_sums_give_the_sparse_product_bits(compiled, seed, n_load, n_row, m, n_knot, zeros):
    """Arguments below the first knot (the linear first interval: left out), beyond the last,
    on the table's nodes and in its leading zero nodes: the sums bit for bit those of the CSR
    product (``scipy``'s ``csr_matvecs``), and the whole ``sums_at_log_tau`` too; with some
    entries asked for (``need``), theirs."""
    fn = _kernel(compiled, "table_sums")
    rng = np.random.default_rng(seed)
    phi = _phi_of(rng, n_load, n_knot, min(zeros, n_knot - 2))
    grid, _ = phi._table()
    log_tau = rng.uniform(phi.s[0] - 3.0, phi.s[-1] + 3.0, (n_row, m))
    log_tau[:, : m // 3] = rng.choice(grid, (n_row, m // 3))
    kern = rng.exponential(1.0, (n_row, m)) * 10.0 ** rng.uniform(-5, 5)
    want_table = phi._sparse_sums(log_tau, kern)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(_phi, "kernel", lambda work, name: None)
        want = phi.sums_at_log_tau(log_tau, kern)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(_phi, "kernel", lambda work, name: fn)
        got_table = phi._kernel_sums(log_tau, kern)
        got = phi.sums_at_log_tau(log_tau, kern)
        need = rng.random(got.shape) < 0.5  # some entries only: theirs the same bits
        part = phi._kernel_sums(log_tau, kern, need)
        np.testing.assert_array_equal(part, np.where(need, want_table, 0.0))
        log_tau[0, 0] = np.nan  # not finite: the sparse product
        assert phi._kernel_sums(log_tau, kern) is None
    np.testing.assert_array_equal(got_table, want_table)
    np.testing.assert_array_equal(got, want)


@pytest.mark.parametrize("compiled", [False, True])
@settings(max_examples=30, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 20), st.integers(4, 40), st.integers(0, 30))
def test_table_values_give_the_numpy_table(compiled, seed, n_load, n_knot, zeros):
    """``Phi``'s look-up table with the loads' own leading zeros (each load's first non-zero
    knot its own, the batch's the earliest's; ringing between zeros set to 0): the compiled
    ``table_values`` (each load from its own columns on, in blocks of 8 loads) gives the
    numpy path's table bit for bit."""
    fn = _kernel(compiled, "table_values")
    rng = np.random.default_rng(seed)
    s = np.sort(rng.uniform(-5.0, 20.0, n_knot))
    inc = rng.exponential(1.0, (n_load, n_knot)) * (rng.random((n_load, n_knot)) < 0.8)
    for k, z in enumerate(rng.integers(0, min(zeros, n_knot - 1) + 1, n_load)):
        inc[k, :z] = 0.0
    vals = np.concatenate((np.zeros((n_load, 1)), np.cumsum(inc, axis=1)), axis=1)

    def table(kern):
        with pytest.MonkeyPatch.context() as mp:
            mp.setattr(_phi, "kernel", kern)
            mp.setattr(_fastnum, "kernel", kern)
            phi = object.__new__(_phi._Phi)
            phi.phi, phi.tau1, phi.s, phi.p0 = vals, math.exp(s[0]), s, np.ones(n_load)
            phi._spl, phi._tab = _row_spline(s, vals[:, 1:]), None
            return phi._spl.c, phi._table()[1]

    numpy_c, want = table(lambda work, name: None)
    plain = {"table_values": fn}  # (compiled: the spline's kernels alike)
    if compiled:
        plain |= {n: _kernel(True, n) for n in SLOPES}
    # (not compiled: the spline by numpy's path. The spline kernels' plain-Python forms run
    # dgtsv's operations but not always its bits: LAPACK as built here rounds one of ~1e3
    # drawn systems differently in the last digit (seed 16590666, 8 loads, 10 knots); their
    # forms are checked against LAPACK on fixed systems in test_compiled_physics)
    got_c, got = table(lambda work, name: plain.get(name))
    np.testing.assert_array_equal(got_c, numpy_c)
    np.testing.assert_array_equal(got, want)


@pytest.mark.parametrize("compiled", [False, True])
@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 6), st.integers(1, 40), st.booleans())
def test_phi_cumsum_is_numpys_division_and_cumsum(compiled, seed, n_load, n, special):
    """``Phi``'s node integrals by the kernel, in place on a strided view (as ``_Phi`` has
    them): numpy's ``inc / p0`` then ``cumsum`` bit for bit (signed zeros, infinities and NaN
    propagated alike), the column before the view untouched."""
    fn = _kernel(compiled, "phi_cumsum")
    rng = np.random.default_rng(seed)
    phi = np.full((n_load, n + 1), 7.0)
    inc = phi[:, 1:]
    inc[...] = rng.exponential(1.0, (n_load, n)) * 10.0 ** rng.uniform(-30, 30, (n_load, 1))
    if special:
        _special(rng, inc)
    p0 = 10.0 ** rng.uniform(2, 8, n_load)
    with np.errstate(all="ignore"):
        want = np.cumsum(inc / p0[:, None], axis=1)
        fn(inc, p0)
    np.testing.assert_array_equal(inc, want)
    num = ~np.isnan(want)  # (a NaN's sign is the platform's)
    assert np.array_equal(np.signbit(inc[num]), np.signbit(want[num]))
    assert np.all(phi[:, 0] == 7.0)


@pytest.mark.parametrize("compiled", [False, True])
@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 5), st.integers(1, 30), st.integers(2, 40))
def test_row_values_give_the_numpy_bits(compiled, seed, n_load, n_point, n_knot):
    """Each load's spline at its own points (below, between, on and beyond the knots,
    infinite): ``_curve._rows``' numpy passes bit for bit; NaN points left to them."""
    fn = _compiled.row_values if not compiled else _kernel(True, "row_values")
    rng = np.random.default_rng(seed)
    knots = np.sort(rng.uniform(-3.0, 8.0, n_knot))
    spl = type("Spl", (), {})()
    spl.c = rng.normal(0.0, 1.0, (4, n_knot - 1, n_load)) * 10.0 ** rng.uniform(-3, 3)
    x = rng.uniform(knots[0] - 1.0, knots[-1] + 1.0, (n_load, n_point))
    x[rng.random(x.shape) < 0.2] = rng.choice(knots)
    x[rng.random(x.shape) < 0.05] = np.inf
    x[rng.random(x.shape) < 0.05] = -np.inf
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(_curve, "kernel", lambda work, name: None)
        want = _curve._rows(spl, knots, x)
        want_nan = _curve._rows(spl, knots, np.where(x > knots[-1], np.nan, x))
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(_curve, "kernel", lambda work, name: fn)
        got = _curve._rows(spl, knots, x)
        got_nan = _curve._rows(spl, knots, np.where(x > knots[-1], np.nan, x))
    np.testing.assert_array_equal(got, want)
    np.testing.assert_array_equal(got_nan, want_nan)


@pytest.mark.parametrize("compiled", [False, True])
@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(2, 6), st.integers(1, 30), st.integers(2, 40))
def test_shared_points_give_the_numpy_bits(compiled, seed, n_load, n_point, n_knot):
    """Points shared by every load (a broadcast row, as the detachment's bin edges): each
    point's interval found once (``shared_row_values``), ``_curve._rows``' numpy passes bit
    for bit, also with a NaN point (left to them)."""
    fns = {"row_values": _compiled.row_values, "shared_row_values": _spline_sums.shared_row_values}
    if compiled:
        fns = {k: _kernel(True, k) for k in fns}
    rng = np.random.default_rng(seed)
    knots = np.sort(rng.uniform(-3.0, 8.0, n_knot))
    spl = type("Spl", (), {})()
    spl.c = rng.normal(0.0, 1.0, (4, n_knot - 1, n_load)) * 10.0 ** rng.uniform(-3, 3)
    x = rng.uniform(knots[0] - 1.0, knots[-1] + 1.0, n_point)
    x[rng.random(x.shape) < 0.2] = rng.choice(knots)
    x[rng.random(x.shape) < 0.05] = np.inf
    for pts in (x, np.where(x > knots[-1], np.nan, x)):
        shared = np.broadcast_to(pts, (n_load, n_point))
        with pytest.MonkeyPatch.context() as mp:
            mp.setattr(_curve, "kernel", lambda work, name: None)
            want = _curve._rows(spl, knots, shared)
        with pytest.MonkeyPatch.context() as mp:
            mp.setattr(_curve, "kernel", lambda work, name: fns[name])
            got = _curve._rows(spl, knots, shared)
        np.testing.assert_array_equal(got, want)


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 6), st.integers(2, 30), st.floats(0.0, 1.0))
def test_first_open_interval_of_rows_together_is_the_smallest(seed, n_row, n_node, share):
    """The first open interval of several rows together (every row's nodes clamped around
    it: the former ``_first_open``) is the smallest of the rows' own."""
    rng = np.random.default_rng(seed)
    dead = rng.random((n_row, n_node)) < share
    dead[:, : int(rng.integers(0, n_node + 1))] = True  # the usual clamped prefix
    pad = np.concatenate(([True], np.all(dead, axis=0), [False]))
    together = int(np.argmin(pad[:-3] & pad[1:-2] & pad[2:-1] & pad[3:]))
    assert int(_curve._first_open_rows(dead).min()) == together
