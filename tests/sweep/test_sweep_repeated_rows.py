"""A variable every point of a block holds as one repeated row (a view: the engine's exact
zeros of the balances, a coordinate the run shares) stays one row through the sweep's fill,
until a block brings other values; the sweep's values are those of the rows written out."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
import xarray as xr
from xpersson_sweep_testlib import scene

import xpersson
from xpersson.sweep import filling as filling_mod
from xpersson.sweep.filling import Filling
from xpersson.sweep.parts import finalize
from xpersson.sweep.stacking import Block, BlockResult

PLAN = SimpleNamespace(dims=("a", "b"), shape=(4, 3))


def _block(number: int, start: int, stop: int) -> Block:
    return Block(number, (number, 0), (start, 0), (stop, 3), PLAN.dims, {})


def _result(number: int, start: int, stop: int, values: np.ndarray) -> BlockResult:
    ds = xr.Dataset({"v": (("a", "b", "z"), values)})
    block = _block(number, start, stop)
    return BlockResult(block, ds, None, np.zeros(block.shape, np.int8), {})


def _repeat(row: list[float], n: int) -> np.ndarray:
    return np.broadcast_to(np.array(row), (n, 3, len(row)))


@pytest.mark.parametrize(
    "second",
    [
        _repeat([0.0, 1.0], 2),  # the same row again: kept a view
        _repeat([0.0, -0.0], 2),  # another row (-0.0: other bits)
        np.arange(12.0).reshape(2, 3, 2),  # values of its own (written in place or copied)
    ],
)
def test_repeated_rows_fill_as_the_values_would(second):
    first = _repeat([0.0, 1.0], 2)
    fill = Filling(PLAN)
    fill.add(_result(0, 0, 2, first))
    fill.add(_result(1, 2, 4, second))
    got = fill.dataset()["v"]
    np.testing.assert_array_equal(got.values[:2], first)
    assert np.concatenate([first, second]).tobytes() == np.ascontiguousarray(got.values).tobytes()
    kept = second.strides[0] == 0 and np.array_equal(second, first, equal_nan=True)
    kept &= np.signbit(second).tolist() == np.signbit(first).tolist()
    assert (got.values.strides[:2] == (0, 0)) == bool(kept)  # no array written: still a view


def test_reduced_repeated_row_equals_the_reduction_of_its_values():
    row = np.array([np.nan, -0.0, 2.5])
    view = xr.Dataset({"v": (("a", "b", "z"), np.broadcast_to(row, (4, 3, 3)))})
    written = view.copy(deep=True)
    constant = {"v": ["a", "b"]}
    a, b = finalize(view, constant, {}), finalize(written, constant, {})
    xr.testing.assert_identical(a, b)
    assert a["v"].values.tobytes() == b["v"].values.tobytes() and a["v"].values.flags.writeable


@pytest.mark.fast_paths
def test_batched_sweep_keeps_the_exact_balances_as_one_row(monkeypatch):
    """An E x H sweep of one load (closed-form): its balances are exact zeros at every point;
    the fill never writes their rows out, and the result equals the threads' copied blocks."""
    written = []
    out = Filling._write_out
    monkeypatch.setattr(
        Filling,
        "_write_out",
        lambda self, n: (n in self._repeat and written.append(n)) or out(self, n),
    )
    repeated = filling_mod.repeated
    kept = []
    monkeypatch.setattr(
        filling_mod, "repeated", lambda var, k: kept.append(r := repeated(var, k)) or r
    )
    data = scene(
        spectrum={"H": [0.6, 0.75, 0.9]},
        material={"E": ["2 MPa", "5 MPa", "40 MPa"], "nu": 0.5},
        load={"p0": "3e4 Pa"},
    )
    direct = xpersson.solve(data, chunk=6)  # blocks of 2 and 1 spectra
    assert any(r is not None for r in kept) and written == []
    copied = xpersson.solve(data, chunk=6, scheduler="threads")
    xr.testing.assert_identical(direct.drop_attrs(), copied.drop_attrs())
    assert direct["load_balance"].dims == ("zeta",) and not direct["load_balance"].any()


def test_sweep_arrays_made_together_are_disjoint_aligned_arrays():
    """:func:`~xpersson.sweep.filling.empty_arrays`: the numeric arrays share one buffer
    without overlapping; each is aligned, C-ordered and writable; text arrays are their own."""
    specs = {
        "a": ((3, 5), np.float64),
        "s": ((2,), np.int8),
        "b": ((4, 1, 2), np.float64),
        "o": ((3,), object),
        "z": ((0, 7), np.float32),
    }
    got = filling_mod.empty_arrays(specs)
    assert {n: (a.shape, a.dtype) for n, a in got.items()} == {
        n: (s, np.dtype(d)) for n, (s, d) in specs.items()
    }
    numeric = [got[n] for n in ("a", "s", "b", "z")]
    assert all(a.flags.c_contiguous and a.flags.writeable and a.flags.aligned for a in numeric)
    assert np.shares_memory(got["a"].base, got["b"].base) and got["o"].base is None
    for k, arr in enumerate(numeric):
        arr[...] = k + 1
    assert [np.unique(a).tolist() for a in numeric] == [[1], [2], [3], []]


@pytest.mark.parametrize("texts", [["success"] * 6, ["success", "failed"] * 3])
def test_text_rows_fingerprints_are_the_arrays_of_their_digests(texts):
    """A block's text variable (every point's solver status) gets the ``(points, 2)`` array of
    fingerprints the numeric ones get: the same 128-bit ints as its per-point digests, equal
    texts equal, so the sweep compares it as an array (no Python loop per point)."""
    from xpersson.sweep.stacking import _digests, _row_digests, digest_list

    block = Block(0, (0, 0), (0, 0), (2, 3), ("a", "b"), {})
    rows = np.array(texts, dtype=object)
    ds = xr.Dataset({"s": (("a", "b"), rows.reshape(2, 3))})
    got = _digests([{"s"}] * 6, ds, block)["s"]
    assert isinstance(got, np.ndarray) and got.shape == (6, 2)
    assert digest_list(got) == _row_digests(rows)
    assert (len(set(digest_list(got))) == 1) == (len(set(texts)) == 1)
