"""Kinks a few ulps apart (loads that differ in their last bits) merge before the time plan:
no zero-length step, no NaN (a batch of loads 1 ulp apart used to end in NaN areas with
"balance_violated" while each load alone succeeded)."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from test_cn_lean import TAU, _wall

from xpersson.engine import solve_batch
from xpersson.engine._cn_kinks import (
    KINK_GAP,
    _kinks_apart_array,
    _kinks_apart_few,
    kinks_apart,
)


@settings(max_examples=60, deadline=None)
@given(
    times=st.lists(st.floats(1e-4, 10.0), min_size=0, max_size=12),
    twins=st.lists(st.integers(0, 11), max_size=4),
    ulps=st.integers(0, 40),
)
def test_kinks_apart_keeps_one_of_each_near_pair_and_every_distinct_one(times, twins, ulps):
    kinks = list(times)
    for i in twins:  # near copies of drawn kinks
        if i < len(times):
            kinks.append(float(np.nextafter(times[i], np.inf) + ulps * np.spacing(times[i])))
    outs = np.sort(np.asarray(times[:2], dtype=float))  # outputs that coincide with kinks
    kept = np.sort(np.asarray(kinks_apart(kinks, outs), dtype=float))
    # no kept kink within the gap of another kept one or of an output
    assert np.all(np.diff(kept) > KINK_GAP * kept[1:])
    for o in outs:
        assert not np.any(np.abs(kept - o) <= KINK_GAP * kept)
    # every drawn kink is within the gap of a kept kink or an output, and kept values are drawn
    anchors = np.concatenate([kept, outs])
    for t in kinks:
        assert np.any(np.abs(anchors - t) <= 2 * KINK_GAP * t)
    assert set(kept.tolist()) <= set(kinks)


@settings(max_examples=80, deadline=None)
@given(
    times=st.lists(st.floats(1e-4, 10.0), min_size=0, max_size=20),
    twins=st.lists(st.integers(0, 19), max_size=6),
    ulps=st.integers(0, 40),
    n_outs=st.integers(0, 6),
)
def test_the_float_path_equals_the_array_path(times, twins, ulps, n_outs):
    # few kinks run on floats: the same list as numpy's path on the same doubles
    kinks = list(times)
    for i in twins:
        if i < len(times):
            kinks.append(float(np.nextafter(times[i], np.inf) + ulps * np.spacing(times[i])))
    outs = np.sort(np.asarray(times[:n_outs] + [5.0, 0.5][: max(0, 2 - n_outs)], dtype=float))
    few, many = _kinks_apart_few(kinks, outs), _kinks_apart_array(kinks, outs)
    assert few == many
    assert (few is kinks) == (many is kinks)


def test_kinks_far_apart_are_returned_as_given():
    kinks = [3.0, 1.0, 2.0]
    assert kinks_apart(kinks, np.array([0.5, 4.0])) is kinks


def test_loads_one_ulp_apart_solve_as_each_alone():
    wall = _wall(0.0, None)
    p0 = np.array([0.2, np.nextafter(0.2, 1.0)])
    both = solve_batch(TAU, p0, (wall, None), rtol=1e-6, method="cn")
    assert list(both.status) == ["success", "success"]
    assert np.all(np.isfinite(both.area))
    for i in range(2):
        alone = solve_batch(TAU, p0[i : i + 1], (wall, None), rtol=1e-6, method="cn")
        np.testing.assert_allclose(both.area[i], alone.area[0], rtol=1e-6)
