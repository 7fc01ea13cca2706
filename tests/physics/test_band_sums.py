"""The compiled window sums of gap_cdf's erf terms (:mod:`xpersson.physics._band_sums`): the
numpy path's bits, in plain Python and compiled, on padded and flat window layouts."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import xpersson
from xpersson.physics import _band_sums, _compiled, _gap_distribution
from xpersson.physics._gap_distribution import Detachment, gap_cdf


def _detachment(rng: np.random.Generator, n_load: int, n_bin: int, spread: float) -> Detachment:
    """Random bins: widths over ``spread`` decades (the windows' widths spread: flat layout;
    close: padded), centres near and far from the wall, some zero and NaN weights."""
    h = np.sort(10.0 ** rng.uniform(-8.0, -8.0 + spread, n_bin))[::-1]
    u1 = rng.uniform(0.0, 3.0, (n_load, n_bin)) * h * 10.0 ** rng.uniform(0, 2, (n_load, n_bin))
    w = rng.uniform(0.0, 0.1, (n_load, n_bin))
    w[rng.random(w.shape) < 0.1] = 0.0
    if n_load > 1:
        w[-1, rng.integers(n_bin)] = np.nan  # spoils its load only
    z = np.geomspace(1.0, 10.0, n_bin + 1)
    area = np.ones((n_load, z.size))
    return Detachment(np.ones(n_load), z, area, area, w, u1, h, 2e-6)


def _through(compiled: bool, name: str, args: tuple, scale: float):
    """``gap_cdf`` of a random draw (``args``: seed, loads, bins, spread, abscissae, per load;
    abscissae up to ``scale`` times the largest bin height and beyond) with only the compiled
    kernel ``name`` (compiled, or its plain Python twin) offered: ``(got, numpy's, asked)``."""
    seed, n_load, n_bin, spread, n_u, per_load = args
    if compiled:
        pytest.importorskip("numba")
        with xpersson.set_options(compiled=True):  # whatever XPERSSON_COMPILED says
            fn = _compiled.kernel(math.inf, name)
        assert fn is not None
    else:
        fn = getattr(_band_sums, name)
    rng = np.random.default_rng(seed)
    det = _detachment(rng, n_load, n_bin, spread)
    top = scale * float(np.max(det.h)) * rng.uniform(0.5, 5.0)
    u = np.linspace(0.0, top, n_u)
    if per_load:  # rows of their own (sorted)
        u = np.sort(rng.uniform(0.0, top, (n_load, n_u)), axis=1)
    with xpersson.set_options(compiled=False):
        want = gap_cdf(det, u)
    asked: list[str] = []

    def kernel(work: float, kname: str = "gap_rows"):
        asked.append(kname)
        return fn if kname == name else None

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(_gap_distribution, "_compiled_kernel", kernel)
        got = gap_cdf(det, u)
    return got, want, asked


_DRAWS = (
    st.integers(0, 2**32 - 1),
    st.integers(1, 6),
    st.integers(1, 12),
    st.floats(0.0, 3.0),
    st.integers(2, 300),
    st.booleans(),
)


@pytest.mark.parametrize("compiled", [False, True])
@settings(max_examples=12, deadline=None)
@given(st.tuples(*_DRAWS))
def test_kernel_gives_the_numpy_bits(compiled, args):
    got, want, asked = _through(compiled, "band_sums", args, 10.0)
    assert "band_sums" in asked
    np.testing.assert_array_equal(got, want)


@pytest.mark.parametrize("compiled", [False, True])
@settings(max_examples=12, deadline=None)
@given(st.tuples(*_DRAWS))
def test_series_kernel_gives_the_numpy_bits(compiled, args):
    """``_series_sum``'s running sums and Horner loop (``series_horner``): the numpy bits."""
    got, want, asked = _through(compiled, "series_horner", args, 1.0)  # many series columns
    assume("series_horner" in asked)  # (~7 % of draws have no pair in the series' range)
    assert got.tobytes() == want.tobytes()
