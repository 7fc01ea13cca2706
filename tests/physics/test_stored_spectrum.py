"""A spectrum rebuilt from what a Dataset stores (nodes, values, exponents) is the original."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from xpersson.physics.psd import SelfAffineRollOff, StoredSpectrum, Tabulated, segment_exponents


def _stored(psd, exponents=True):
    q = psd.nodes()
    return StoredSpectrum(q, psd.C(q), segment_exponents(psd) if exponents else None)


def _same_numbers(a, b, q):
    """Every number an analysis asks of a spectrum, equal bit for bit."""
    assert a.q_L == b.q_L and a.q_1 == b.q_1
    np.testing.assert_array_equal(a.C(q), b.C(q))
    np.testing.assert_array_equal(a.I3(q), b.I3(q))
    np.testing.assert_array_equal(a.running_moment(1.0, q), b.running_moment(1.0, q))
    for k in (1.0, 3.0, 5.0, 2.5):
        assert a.moment(k) == b.moment(k)
        assert a.moment(k, a.q_L * 3.0, a.q_1 / 7.0) == b.moment(k, b.q_L * 3.0, b.q_1 / 7.0)
    assert a.cache_key() == b.cache_key()  # the same segments, so the same digest


@settings(max_examples=40, deadline=None)
@given(
    H=st.floats(0.05, 1.0),
    roll=st.floats(0.0, 2.0),
    span=st.floats(0.5, 6.0),
    h=st.floats(1e-9, 1e-4),
)
def test_self_affine_rebuilt_bit_for_bit(H, roll, span, h):
    q_L = 1e3
    q_r = q_L * 10**roll
    psd = SelfAffineRollOff.from_h_rms(h, H, q_L, min(q_r, q_L * 10**span), q_L * 10**span)
    q = np.geomspace(q_L * 0.5, psd.q_1 * 2.0, 257)
    _same_numbers(_stored(psd), psd, q)


def test_tabulated_rebuilt_bit_for_bit():
    q = np.geomspace(1e3, 1e8, 40)
    C = 1e-20 * (q / 1e3) ** -3.1 * (1 + 0.3 * np.sin(np.log(q)))
    for psd in (
        Tabulated(q, C),
        Tabulated(q, C * 1e-6, "profile_1d", q_L=2e3, q_1=5e7),
    ):
        _same_numbers(_stored(psd), psd, np.geomspace(1e3, 1e8, 301))


def test_without_exponents_the_table_to_round_off():
    """An archive without ``psd_exponent``: the log-log slopes of the stored table, the
    spectrum up to round-off in the exponents (|ln(q/q_i)| * a few 1e-16 relative)."""
    psd = SelfAffineRollOff.from_h_rms(1e-6, 0.8, 1e3, 1e4, 1e9)
    legacy = _stored(psd, exponents=False)
    q = np.geomspace(1e3, 1e9, 301)
    np.testing.assert_allclose(legacy.C(q), psd.C(q), rtol=1e-13, atol=0)
    np.testing.assert_allclose(legacy.I3(q), psd.I3(q), rtol=1e-13, atol=0)
    assert legacy.moment(1.0) == pytest.approx(psd.moment(1.0), rel=1e-13)


def test_exponents_as_the_dataset_stores_them():
    psd = SelfAffineRollOff.from_h_rms(1e-6, 0.8, 1e3, 1e4, 1e8)
    e = segment_exponents(psd)
    assert e.shape == psd.nodes().shape and np.isnan(e[-1])
    np.testing.assert_array_equal(e[:-1], [0.0, -3.6])


@pytest.mark.parametrize(
    ("q", "C", "e", "match"),
    [
        ([1e3], [1.0], None, "at least two breakpoints"),
        ([1e3, 1e3], [1.0, 1.0], None, "strictly increasing"),
        ([1e3, 1e4], [1.0, 0.0], None, r"C\(q\) \[m\^4\] must be finite and > 0"),
        ([1e3, 1e4], [1.0, np.nan], None, "finite and > 0"),
        ([1e3, 1e4], [1.0, 0.1], [np.nan, np.nan], "exponents .* must be finite"),
        ([1e3, 1e4], [1.0, 0.1], [1.0, 2.0, 3.0], "one exponent"),
    ],
)
def test_malformed_tables_are_named(q, C, e, match):
    with pytest.raises(ValueError, match=match):
        StoredSpectrum(q, C, e)


@pytest.mark.parametrize("n", [2, 3, 7])
def test_segment_is_the_clipped_search(n):
    """The segment of each ``q`` (one search over the inner breakpoints) is the clipped
    ``searchsorted(nodes, q, "right") - 1``, for arrays and scalars, outside the support,
    at the breakpoints and for NaN."""
    rng = np.random.default_rng(n)
    q = np.cumsum(rng.uniform(0.5, 2.0, n)) * 1e4
    psd = StoredSpectrum(q, rng.uniform(1e-30, 1e-28, n))
    x = np.concatenate((q, np.nextafter(q, 0.0), np.nextafter(q, np.inf), [0.0, np.nan]))
    x = np.concatenate((x, [-np.inf, np.inf], rng.uniform(0.0, 2.0 * q[-1], 200)))
    ref = np.clip(np.searchsorted(q, x, side="right") - 1, 0, n - 2)
    np.testing.assert_array_equal(psd._segment(x), ref)
    assert psd._segment(x).dtype == np.intp
    for v, r in zip(x[:20], ref[:20], strict=True):
        assert isinstance(psd._segment(np.float64(v)), np.intp) and psd._segment(v) == r
