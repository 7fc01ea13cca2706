"""Sweeps with several loads per point solved as batches of equivalent loads (issue 36), the
in-memory fill of the sweep's arrays and the per-point fingerprints as arrays."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from xpersson_sweep_testlib import scene

import xpersson
from xpersson.sweep import batched, plain_paths
from xpersson.sweep.stacking import _row_digests, _row_hashes, digest_list

LOADS_SCENE = scene(
    spectrum={"H": [0.6, 0.9]},
    material={"E": ["2 MPa", "5 MPa", "40 MPa"], "nu": [0.2, 0.45]},
    load={"p0": ["1e4 Pa", "3e4 Pa", "1e5 Pa"]},
    analyses={"contact_area": {}},
)


def _equal_to_rounding(fast, plain):
    assert list(fast.variables) == list(plain.variables)
    for name, var in plain.variables.items():
        got = fast[name]
        assert got.dims == var.dims, name
        if var.dtype.kind == "f":
            np.testing.assert_allclose(got.values, var.values, rtol=1e-12, atol=1e-300)
        else:
            np.testing.assert_array_equal(got.values, var.values)


@pytest.mark.fast_paths
@pytest.mark.parametrize("chunk", [None, 4])
def test_several_loads_per_point_batched_equal_point_by_point(monkeypatch, chunk):
    """Every block takes the batched path (the point-by-point ``run`` is never called) and
    equals the plain path to the contract's 1e-12."""
    from xpersson.sweep import blocks

    with plain_paths():
        plain = xpersson.solve(LOADS_SCENE, chunk=chunk)

    def no_fallback(*a, **k):
        raise AssertionError("a block fell back to point by point")

    monkeypatch.setattr(blocks, "run", no_fallback)
    fast = xpersson.solve(LOADS_SCENE, chunk=chunk)
    assert fast.area_fraction.dims == ("H", "E", "nu", "p0", "zeta")
    _equal_to_rounding(fast, plain)


@pytest.mark.fast_paths
def test_shared_equivalent_loads_are_solved_once(monkeypatch):
    """Log-spaced E and p0 with one ratio: p0_j E*_ref / E*_k repeat; each distinct load is
    solved once and every point gets its own back."""
    data = scene(
        material={"E": ["1 MPa", "10 MPa", "100 MPa"], "nu": 0.0},  # E* = E: exact ratios
        load={"p0": ["1e3 Pa", "1e4 Pa", "1e5 Pa"]},
    )
    seen = []
    original = batched._similar_loads

    def spy(rs, estar):
        out = original(rs, estar)
        seen.append(out[0].p0.size)
        return out

    monkeypatch.setattr(batched, "_similar_loads", spy)
    fast = xpersson.solve(data)
    assert seen == [5]  # 9 (point, load) pairs, 5 distinct equivalent loads
    with plain_paths():
        plain = xpersson.solve(data)
    _equal_to_rounding(fast, plain)


@pytest.mark.fast_paths
def test_estar_of_a_block_equals_the_points_own():
    """E* of every point of a block by array operations: the float E / (1 - nu^2) of each."""
    from xpersson.pipeline import as_scene
    from xpersson.sweep import expand
    from xpersson.sweep.blocks import block_points, blocks_of
    from xpersson.sweep.execute import resolve_points

    data = scene(material={"E": ["2 MPa", "5 MPa", "7 MPa"], "nu": [0.1, 0.3, 0.49]})
    plan = expand(as_scene(data))
    points = resolve_points(plan, None)
    block = blocks_of(plan, plan.size)[0]
    region = block_points(plan, points, block)
    for where, _, estar in batched._sub_points(block, region):
        for k, e in zip(where, estar, strict=True):
            rs = region[int(k)]
            assert e == rs.E / (1.0 - rs.nu**2)


@settings(max_examples=30, deadline=None)
@given(
    st.lists(st.integers(0, 2**20), min_size=1, max_size=12),
    st.integers(1, 6),
)
def test_row_hashes_as_arrays_equal_the_listed_fingerprints(seed_values, width):
    """The (points, 2) uint64 hashes name the same rows equal as the per-point ints."""
    rows = np.array(seed_values, float)[:, None] * np.arange(1, width + 1)[None, :]
    rows[::2] = rows[0]  # some equal rows
    hashes = _row_hashes(rows)
    assert digest_list(hashes) == _row_digests(rows)
    same = [bool(np.array_equal(r, rows[0])) for r in rows]
    assert [h == digest_list(hashes)[0] for h in digest_list(hashes)] == same
