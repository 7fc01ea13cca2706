"""The cuts of one solve's fixed cost (issue 36, "one curve at kernel speed"): each is the
plain computation's result, bit for bit, or keys exactly what it replaces."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from hypothesis import given, settings
from hypothesis import strategies as st

import xpersson
from xpersson import cache as xc
from xpersson.builtin.elastic import ElasticCoefficient
from xpersson.physics import elastic
from xpersson.physics.psd import SelfAffineRollOff
from xpersson.pipeline._insert import new_variable
from xpersson.pipeline.assemble import _spectrum_variables
from xpersson.pipeline.frontend import diffusion_clock, scene_context
from xpersson.pipeline.stages import coefficient_arrays

SCENE = {
    "spectrum": {"model": "self_affine", "H": 0.7, "q_L": "1e3 1/m", "q_1": "1e7 1/m",
                 "h_rms": "1 um"},
    "material": {"E": "10 MPa", "nu": 0.5},
    "load": {"p0": "0.1 MPa"},
}  # fmt: skip


@pytest.mark.parametrize(
    ("dims", "data", "attrs", "encoding"),
    [
        (("p0", "zeta"), np.arange(6.0).reshape(2, 3), {"units": "1"}, None),
        ((), np.asarray(2.5), {"units": "Pa"}, {"dtype": "float32"}),
        (("p0",), np.array(["success"], dtype=object), None, None),
        (("zeta",), np.arange(3, dtype=np.int8)[::-1], {}, {}),
        ((), np.float64(1e5), {"units": "Pa"}, None),  # a numpy scalar: kept as it is
    ],
)
def test_new_variable_is_the_constructors_variable(dims, data, attrs, encoding):
    got = new_variable(dims, data, None if attrs is None else dict(attrs), encoding)
    want = xr.Variable(dims, data, attrs, encoding, fastpath=True)
    assert type(got) is type(want)
    assert got.identical(want)
    assert got.encoding == want.encoding
    assert got._data is want._data  # noqa: SLF001 - the same array, not a copy
    assert got.dims == want.dims and got.attrs == want.attrs


def test_new_variable_refuses_dims_of_another_length():
    with pytest.raises(ValueError, match="same length"):
        new_variable(("p0",), np.zeros((2, 2)))


@given(st.integers(0, 700), st.sampled_from(["f8", "f4", "i8", "u1"]), st.booleans())
@settings(max_examples=60, deadline=None)
def test_content_key_of_arrays_either_side_of_the_byte_limit(n, dtype, strided):
    """Arrays key by their bytes up to 2 KiB and by a digest above: equal content, equal key;
    one bit, the dtype or the shape changed, another key; a view keys as its copy."""
    base = np.arange(2 * n + 1).astype(dtype)
    a = base[::2] if strided else base[:n]
    key = xc.content_key(a)
    assert key == xc.content_key(np.ascontiguousarray(a))
    assert (key[0] == "b") == (a.nbytes <= xc._SMALL)  # noqa: SLF001 - the limit itself
    if a.size:
        b = a.copy()
        b.view(np.uint8)[0] ^= 1
        assert xc.content_key(b) != key
        assert xc.content_key(a.reshape(1, -1)) != key
    assert xc.content_key(a.astype("i2")) != key


class _Sub(np.ndarray):
    pass


@pytest.mark.parametrize("n", [5, 1000])
def test_content_key_of_an_array_subclass_is_its_arrays(n):
    a = np.arange(float(n))
    assert xc.content_key(a.view(_Sub)) == xc.content_key(a)


def _clock_parts():
    rs = xpersson.Scene(SCENE).resolve()
    return rs, scene_context(rs)


def test_elastic_clock_key_names_its_spectrum_and_modulus():
    rs, ctx = _clock_parts()
    clock = diffusion_clock(ctx, rs.coefficient)
    assert clock.key == xc.content_key(("elastic", rs.psd, float(rs.E_star)))

    class Scaled(ElasticCoefficient):  # redefines tau: its clock has no key
        def tau(self, ctx, zeta):
            return 2.0 * super().tau(ctx, zeta)

    assert Scaled().clock_key(ctx) is None
    assert diffusion_clock(ctx, Scaled()).key is None


def test_keyed_clock_tables_are_the_unkeyed_ones():
    rs, ctx = _clock_parts()
    xc.clear_caches()
    keyed = diffusion_clock(ctx, rs.coefficient)
    plain = diffusion_clock(ctx, rs.coefficient)
    object.__setattr__(plain, "key", None)
    t = np.geomspace(1e-3, 1.0, 40) * float(keyed.tau_of_zeta(ctx.zeta_max))
    np.testing.assert_array_equal(keyed.zeta_of_tau(t), plain.zeta_of_tau(t))
    for a, b in zip(keyed._nodes()[:5], plain._nodes()[:5], strict=True):  # noqa: SLF001
        np.testing.assert_array_equal(a, b)


def test_coefficient_arrays_by_clock_key_are_the_asked_ones_and_writable():
    rs, ctx = _clock_parts()
    key = diffusion_clock(ctx, rs.coefficient).key
    for _ in range(2):  # computed, then (caches on) kept
        tau, f, tau_eff, shared = coefficient_arrays(rs.coefficient, ctx, "c", key)
        np.testing.assert_array_equal(tau, elastic.diffusion_time(rs.psd, rs.E_star, rs.zeta))
        np.testing.assert_array_equal(f, elastic.coefficient_f(rs.psd, rs.E_star, rs.zeta))
        assert shared and tau.flags.writeable and f.flags.writeable
        tau[0] = -1.0  # the caller's copy: what is kept does not change


def test_spectrum_variables_are_the_spectrums_and_writable():
    psd = SelfAffineRollOff.from_h_rms(1e-6, 0.6, 1e3, 1e4, 1e8)
    for _ in range(2):
        q, c, e, h, s = _spectrum_variables(psd)
        np.testing.assert_array_equal(q, psd.nodes())
        np.testing.assert_array_equal(c, psd.C(np.asarray(psd.nodes())))
        assert (h, s) == (float(psd.h_rms()), float(psd.rms_slope()))
        assert np.isnan(e[-1]) and q.flags.writeable and c.flags.writeable
        c[0] = 0.0
