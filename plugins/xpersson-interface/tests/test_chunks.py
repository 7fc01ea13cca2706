"""Loads in chunks (:mod:`xpersson_interface._chunks`): the same bits as all loads at once."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from interface_testlib import scene

import xpersson
import xpersson_interface.plugins as plugins_mod
from xpersson_interface._chunks import chunk_rows, joined, on_gap_grid

LOADS = list(np.geomspace(1e3, 3e6, 7))
ANALYSES = {"mean_gap": {}, "gap_pdf": {"u_points": 40},
            "leakage": {"viscosity": "1 mPa*s", "n_bins": 60}}  # fmt: skip


def test_chunk_rows_cover_the_loads_once():
    rows = chunk_rows(11, 4)
    assert [(r.start, r.stop) for r in rows] == [(0, 4), (4, 8), (8, 11)]
    assert joined([np.arange(3), np.arange(3, 5)], lambda a: (a, 2 * a))[1].tolist() == [
        0, 2, 4, 6, 8,
    ]  # fmt: skip


@pytest.fixture(scope="module")
def both():
    """The scene solved with all 7 loads at once and in chunks of 3 (3 + 3 + 1 loads)."""
    whole = xpersson.solve(scene(LOADS, analyses=ANALYSES))
    mp = pytest.MonkeyPatch()
    mp.setattr(plugins_mod, "CHUNK", 3)
    try:
        chunked = xpersson.solve(scene(LOADS, analyses=ANALYSES))
    finally:
        mp.undo()
    return whole, chunked


@pytest.mark.parametrize(
    "name",
    ["mean_gap", "gap_pdf", "gap_mean", "gap_contact_weight", "leak_zeta_c", "leak_u1",
     "leak_rate", "leak_rate_emt", "leak_flow_factor_emt", "leak_sealed_emt"],
)  # fmt: skip
def test_chunked_equals_whole(both, name):
    """A load's values do not depend on the chunk it is in: equal bit for bit (each load's
    curve, crossing, tables and row sums are its own)."""
    whole, chunked = (np.asarray(d[name].values, dtype=float) for d in both)
    assert whole.shape == chunked.shape and np.isfinite(whole).any()
    np.testing.assert_array_equal(chunked, whole)


def test_on_gap_grid_is_the_plain_dataarray():
    # the template's shallow copy: the DataArray built afresh, with rho's own memory, and
    # neither the template nor a later call sees the values of an earlier one
    rng = np.random.default_rng(5)
    u = np.linspace(0.0, 3e-6, 57)
    coord = xr.Variable(("u",), u, {"units": "m", "long_name": "interfacial separation"})
    for _ in range(2):
        rho = rng.random((4, u.size))
        got = on_gap_grid(rho, u)
        want = xr.DataArray(rho.copy(), dims=("p0", "u"), coords={"u": coord})
        assert got.identical(want)
        assert np.shares_memory(got.values, rho)
        rho[0, 0] = -1.0  # the caller's array is the data, not the template's
        assert got.values[0, 0] == -1.0
        assert on_gap_grid(np.zeros((4, u.size)), u).values[0, 0] == 0.0
    other = on_gap_grid(np.ones((3, 9)), np.linspace(0.0, 1.0, 9))
    assert other.sizes == {"p0": 3, "u": 9} and other["u"].values[-1] == 1.0
