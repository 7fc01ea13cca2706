"""The compiled passes of a ``cn`` solve's tail give the numpy steps' numbers bit for bit
(issue 36, the engine's fixed cost per solve): the error control's reported estimate
(:func:`xpersson.engine._cn_outputs.fitted_error`), the load identity's scale
(:func:`~xpersson.engine._cn_outputs.scale_kernel`) and the assembled fields
(:func:`~xpersson.engine._cn_outputs.assembled`), on drawn values with signed zeros, NaN,
infinities, probabilities outside [0, 1] and estimates near their bounds; where a pass
declines, the numpy steps answer (and the pass is taken on ordinary values)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from xpersson import set_options
from xpersson.engine import _compiled
from xpersson.engine._cn_assemble import _fields, _fields_of, _start_floor
from xpersson.engine._cn_control import EST_FLOOR, _Fit
from xpersson.engine._cn_outputs import fitted_of, load_scale
from xpersson.engine._level import Outputs

pytest.importorskip("numba")

_VALUES = st.one_of(
    st.floats(-0.1, 1.1),
    st.sampled_from([0.0, -0.0, 1.0, 0.5, 1e-300, -5e-324, 2.0, np.nan, np.inf, -np.inf]),
)
_SMALL = st.one_of(
    st.floats(0.0, 1e-5), st.sampled_from([0.0, -0.0, 1e-9, 3.0, np.nan, np.inf, 1e-300])
)


def _kernels() -> SimpleNamespace:
    """The compiled passes, built whatever ``XPERSSON_COMPILED`` says."""
    with set_options(compiled=True):
        assert _compiled.build()
        return SimpleNamespace(
            fitted=_compiled.built("fitted"),
            scale=_compiled.built("scale"),
            assembled=_compiled.built("assembled"),
        )


def _bits(a) -> bytes:
    return np.ascontiguousarray(a, dtype=float).tobytes()


def _field(data, values, shape):
    n = shape[0] * shape[1]
    return np.array(data.draw(st.lists(values, min_size=n, max_size=n))).reshape(shape)


def _fitted_numpy(err, area, c, rtol, atol):
    """``_cn_control._control``'s steps for a successful fit: the reported estimate, or None
    where an estimate exceeds its tolerance (the fit then fails)."""
    e = np.minimum(err, 1.0)
    a = np.abs(area)
    e = e + c * a
    tol = rtol * a + atol
    if np.count_nonzero(e > tol):
        return None
    return tol * np.maximum((e / tol).max(axis=-1, keepdims=True), EST_FLOOR)


@settings(max_examples=60, deadline=None)
@given(
    shape=st.tuples(st.integers(1, 3), st.integers(1, 6)),
    data=st.data(),
    c=st.sampled_from([0.0, 3.6e-15, 1e-9]),
    rtol=st.sampled_from([1e-8, 1e-6, 1e-3]),
)
def test_compiled_reported_estimate_is_the_numpy_one(shape, data, c, rtol):
    fast = _kernels().fitted
    err, area = _field(data, _SMALL, shape), _field(data, _VALUES, shape)
    with np.errstate(all="ignore"):
        want = _fitted_numpy(err, area, c, rtol, 1e-7 * rtol)
    got = fitted_of(fast, err, area, c, rtol, 1e-7 * rtol, EST_FLOOR)
    if got is not None:  # (where it declines the numpy steps answer)
        assert want is not None and _bits(got) == _bits(want)
    ok = np.full(shape, 1e-12)
    assert fitted_of(fast, ok, np.full(shape, 0.5), c, rtol, 1e-7 * rtol, EST_FLOOR) is not None


@settings(max_examples=50, deadline=None)
@given(
    loads=st.lists(st.floats(-2.0, 2.0), min_size=1, max_size=3),
    data=st.data(),
)
def test_compiled_load_scale_is_the_numpy_one(loads, data):
    fast = _kernels().scale
    wall = st.one_of(st.floats(-3.0, 3.0), st.sampled_from([0.0, -0.0, np.nan, -np.inf]))
    lo = np.array(data.draw(st.lists(wall, min_size=1, max_size=6)))
    tau = np.arange(1.0, lo.size + 1.0)
    pbs = [SimpleNamespace(p0=p, lower=None, upper=None) for p in loads]
    want = load_scale(pbs, tau, lo)
    got = load_scale(pbs, tau, lo, fast)
    assert _bits(got) == _bits(want)


@settings(max_examples=60, deadline=None)
@given(
    loads=st.integers(1, 3),
    n_a=st.integers(0, 3),
    n_m=st.integers(1, 4),
    zero_first=st.booleans(),
    status=st.sampled_from(["success", "tolerance_not_met"]),
    data=st.data(),
)
def test_compiled_fields_are_the_numpy_ones(loads, n_a, n_m, zero_first, status, data):
    fast = _kernels().assembled
    shape = (loads, n_m)
    tau = np.arange(float(n_a + n_m)) + (0.0 if zero_first else 0.5)
    pbs = [SimpleNamespace(p0=900.0 + q, tau=tau) for q in range(loads)]
    fields = [_field(data, _VALUES, shape) for _ in range(3)]
    moments = [_field(data, st.floats(-1e3, 1e3), shape) for _ in range(3)]
    best = Outputs(fields[0], fields[1], fields[2], *moments, None)
    fit = _Fit(_field(data, _SMALL, shape), best, 48, status)
    lv = SimpleNamespace(image=None)
    analytic = np.arange(tau.size) < n_a
    trunc, roundoff = 2e-14, 4e-13
    rtol, atol = data.draw(st.sampled_from([(1e-6, 1e-13), (1e-3, 1e-10), (1e-12, 1e-16)]))
    with np.errstate(all="ignore"):
        *want, w_status, _ = _fields(pbs, analytic, fit, lv, n_a, trunc, roundoff)
        _start_floor(want[5], want[0], tau, n_a, rtol, atol)
    got = _fields_of(fast, pbs, fit, tau, trunc, roundoff, rtol, atol)
    if got is not None:  # (where it declines the numpy steps answer)
        assert w_status == status  # (no distance moved beyond the estimate)
        for have, ref in zip(got, want, strict=True):
            assert _bits(have) == _bits(ref)
    plain = Outputs(*(np.full(shape, 0.25) for _ in range(6)), None)
    ok = _Fit(np.full(shape, 1e-9), plain, 48, status)
    assert _fields_of(fast, pbs, ok, tau, trunc, roundoff, rtol, atol) is not None
