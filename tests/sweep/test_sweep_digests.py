"""Per-point fingerprints of a block (issue 36): a variable that changes along every sweep
dimension of its block gets stand-ins instead of hashes; the sweep's constant dimensions are
those the hashes give."""

from __future__ import annotations

import numpy as np
import xarray as xr

from xpersson.sweep.stacking import Block, _digests, _row_hashes, digest_list


def _block(number: int, start: tuple[int, int], shape: tuple[int, int]) -> Block:
    stop = (start[0] + shape[0], start[1] + shape[1])
    return Block(number, (number, 0), start, stop, ("a", "b"), {})


def _ds(values: dict[str, np.ndarray]) -> xr.Dataset:
    return xr.Dataset({n: (("a", "b", "z"), v) for n, v in values.items()})


def test_a_variable_changing_along_every_dimension_gets_distinct_stand_ins():
    rng = np.random.default_rng(3)
    both = rng.random((3, 4, 5))  # changes along a and b
    along_a = np.repeat(rng.random((3, 1, 5)), 4, axis=1)  # constant along b
    const = np.broadcast_to(rng.random(5), (3, 4, 5)).copy()
    ds = _ds({"both": both, "along_a": along_a, "const": const})
    blocks = [_block(0, (0, 0), (3, 4)), _block(1, (3, 0), (3, 4))]
    got = [_digests([{"both", "along_a", "const"}] * 12, ds, b) for b in blocks]
    stand_ins = np.concatenate([g["both"] for g in got])
    assert len({tuple(r) for r in stand_ins.tolist()}) == 24  # distinct across both blocks
    hashes = _row_hashes(both.reshape(12, 5))
    assert not np.array_equal(got[0]["both"], hashes)  # stand-ins, not the hashes
    for name, arr in (("along_a", along_a), ("const", const)):  # hashed: equal rows, equal
        np.testing.assert_array_equal(got[0][name], _row_hashes(arr.reshape(12, 5)))
    rows = np.array(digest_list(got[0]["along_a"]), dtype=object).reshape(3, 4)
    assert all(len(set(r)) == 1 for r in rows) and len(set(rows[:, 0])) == 3


def test_a_block_of_one_point_along_a_dimension_is_hashed():
    rng = np.random.default_rng(4)
    values = rng.random((1, 4, 5))
    got = _digests([{"v"}] * 4, _ds({"v": values}), _block(0, (0, 0), (1, 4)))
    np.testing.assert_array_equal(got["v"], _row_hashes(values.reshape(4, 5)))
