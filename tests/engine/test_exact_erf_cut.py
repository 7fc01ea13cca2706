"""The one-wall closed form's ``erf``/``erfc`` skip the leading columns where every value is
exactly 1 / +0 (:func:`xpersson.engine.exact._erf_erfc`): the bits of evaluating every one."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.special import erf, erfc

from xpersson.engine import exact
from xpersson.engine.exact import _erf_erfc

_SPECIAL = np.array([np.nan, np.inf, -np.inf, 0.0, -0.0, 6.5, 28.0, 5.9, 26.7, 1e308, -30.0])


@settings(max_examples=60, deadline=None)
@given(
    st.integers(0, 2**32 - 1),
    st.lists(st.integers(1, 40), min_size=1, max_size=3),
    st.floats(0.0, 1.0),
    st.floats(0.0, 1.0),
)
def test_erf_erfc_are_the_full_evaluation_bit_for_bit(seed, shape, lead, special):
    rng = np.random.default_rng(seed)
    x = 10 ** rng.uniform(-3, 3, shape) * rng.choice([1.0, -1.0], shape, p=[0.9, 0.1])
    cols = int(lead * shape[-1])  # leading columns beyond both cuts (as near tau = 0)
    x[..., :cols] = rng.choice([6.5, 7.0, 27.9, 28.0, 29.0, 1e3, np.inf], x[..., :cols].shape)
    pick = rng.random(shape) < 0.2 * special
    x[pick] = rng.choice(_SPECIAL, int(pick.sum()))
    want_area, want_non = erf(x), erfc(x)
    area, non = _erf_erfc(x.copy())
    assert area.tobytes() == want_area.tobytes()
    assert non.tobytes() == want_non.tobytes()


def test_the_cuts_are_where_erf_and_erfc_are_exact():
    x = np.concatenate((np.linspace(exact._ERF_ONE, 40.0, 200_001), [np.inf, 1e300]))
    assert np.all(erf(x) == 1.0)
    y = np.concatenate((np.linspace(exact._ERFC_ZERO, 40.0, 200_001), [np.inf, 1e300]))
    assert erfc(y).tobytes() == np.zeros(y.size).tobytes()


def test_one_wall_batch_keeps_its_bits():
    rng = np.random.default_rng(3)
    tau = np.concatenate(([0.0], np.geomspace(1e-12, 1.0, 300)))[None, :]
    p0 = rng.uniform(0.05, 2.0, (40, 1))
    area, non = exact.one_wall_area_non(np.broadcast_to(tau, (40, tau.size)), p0)
    with np.errstate(divide="ignore"):
        x = p0 / (2.0 * np.sqrt(tau))
    assert area.tobytes() == erf(x).tobytes()
    assert non.tobytes() == erfc(x).tobytes()


def test_erf_above_one_is_one_minus_erfc_bit_for_bit():
    # _erf_erfc takes erf from erfc where x > 1 (scipy's own erf there): around 1, across
    # the erfc branches (x < 8, >= 8) and where erf rounds to 1
    rng = np.random.default_rng(7)
    one = np.nextafter(1.0, 2.0)
    x = np.concatenate(
        ([one, 1.0, np.nextafter(1.0, 0.0)], 1.0 + 10 ** rng.uniform(-16, 1.5, 200_000))
    )
    big = x > 1.0
    assert (1.0 - erfc(x[big])).tobytes() == erf(x[big]).tobytes()
    rows = np.sort(x[:5000])[::-1].reshape(50, 100)  # the cut path (> _SMALL), around 1
    area, non = _erf_erfc(rows.copy())
    assert area.tobytes() == erf(rows).tobytes()
    assert non.tobytes() == erfc(rows).tobytes()
