"""``PowerSpectrum.running_moment`` takes ``_segment_integral``'s per-segment factors
(``Ca a^(k+1)``, ``k + e + 1``) once per segment: the same bits as the formula per element
(numpy's array ``pow`` gives a value the same bits wherever it sits in an array)."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from xpersson.physics._self_affine import SelfAffineRollOff
from xpersson.physics._spectrum import _segment_integral
from xpersson.physics._tabulated import Tabulated


def _per_element(psd, k: float, q) -> np.ndarray:
    """The formula element by element (the earlier form of ``running_moment``)."""
    q_arr = np.minimum(np.maximum(np.asarray(q, dtype=float), psd.q_L), psd.q_1)
    idx = psd._segment(q_arr)
    part = _segment_integral(psd._a[idx], q_arr, psd._Ca[idx], psd._e[idx], float(k))
    return psd._cumulative(k)[idx] + part


@settings(max_examples=40, deadline=None)
@given(
    st.integers(0, 2**32 - 1),
    st.sampled_from([1.0, 3.0, 5.0, -2.0, 0.5]),
    st.integers(0, 300),
    st.booleans(),
    st.booleans(),
)
def test_running_moment_is_the_per_element_formula_bit_for_bit(seed, k, n_q, table, square):
    rng = np.random.default_rng(seed)
    q_L = 10 ** rng.uniform(1, 4)
    if table:  # many segments, exponents of both signs (incl. s = k + e + 1 = 0 cases)
        q = np.sort(q_L * 10 ** rng.uniform(0, 5, rng.integers(2, 12)))
        q = np.unique(np.concatenate(([q_L], q)))
        psd = Tabulated(q, 10 ** rng.uniform(-40, -20, q.size))
    else:
        H = rng.uniform(0.1, 1.0)
        q_r = q_L * 10 ** rng.uniform(0, 1)
        psd = SelfAffineRollOff.from_h_rms(1e-6, H, q_L, q_r, q_r * 10 ** rng.uniform(1, 4))
    qs = psd.q_L * 10 ** rng.uniform(-0.5, np.log10(psd.q_1 / psd.q_L) + 0.5, n_q)
    qs[rng.random(n_q) < 0.1] = psd.q_L  # the ends and the breakpoints themselves
    if n_q:
        qs[rng.integers(n_q)] = psd.q_1
        nodes = psd.nodes()
        qs[rng.integers(n_q)] = nodes[rng.integers(nodes.size)]
    if square and n_q % 2 == 0:
        qs = qs.reshape(2, -1)
    got = psd.running_moment(k, qs)
    assert got.shape == qs.shape
    assert got.tobytes() == _per_element(psd, k, qs).tobytes()
    one = qs.flat[0] if n_q else psd.q_L  # a scalar: numpy's scalar pow, as before
    assert psd.running_moment(k, one) == float(_per_element(psd, k, one))
