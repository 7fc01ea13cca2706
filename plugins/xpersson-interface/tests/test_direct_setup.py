"""The direct path's per-call set-up (issue 36): the loads' variables selected without xarray,
the Dataset's spectrum rebuilt once per content. Both give what they replace, bit for bit."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

import xpersson
from xpersson.plugins import solved
from xpersson.plugins.stored import spectrum_of
from xpersson.testing import TINY_SCENE
from xpersson_interface._chunks import _Rows


@pytest.fixture(scope="module")
def four():
    """A core-only solve of four loads and a bare context."""
    scene = {**TINY_SCENE, "load": {"p0": ["20 kPa", "50 kPa", "0.1 MPa", "0.3 MPa"]}}
    ds = xpersson.solve(scene)
    ctx = SimpleNamespace(p0=ds["p0"].values, boundary=None, coefficient=None, solve_at=None)
    return ctx, ds


@pytest.mark.parametrize("rows", [[0], [1, 3], [3, 0, 2], [0, 1, 2, 3]])
def test_selected_rows_hold_what_isel_holds(four, rows):
    """``_Rows``: each of ``names`` the Dataset has, with the values, dimensions and attributes
    of ``ds[names].isel(p0=rows)`` (the p0 axis wherever it lies; isel adds the coordinates)."""
    ctx, ds = four
    rows = np.array(rows)
    names = solved.curve_variables(ctx)
    want = ds[[k for k in names if k in ds.variables]].isel(p0=rows).variables
    got = _Rows(ds, names, rows).variables
    assert set(got) == {k for k in names if k in ds.variables}
    for k in got:
        var = want[k]
        assert got[k].dims == var.dims, k
        assert got[k].attrs == var.attrs, k
        np.testing.assert_array_equal(got[k].values, var.values, err_msg=k)
        assert got[k].values.dtype == var.values.dtype, k


@pytest.mark.parametrize("form", ["closure", "yang_persson"])
def test_solved_curve_of_selected_rows_is_that_of_the_isel_dataset(four, form):
    ctx, ds = four
    rows = np.array([2, 0])
    names = solved.curve_variables(ctx)
    sub = SimpleNamespace(p0=ctx.p0[rows], boundary=None, coefficient=None, solve_at=None)
    a = solved.solved_curve(sub, ds[[k for k in names if k in ds.variables]].isel(p0=rows), form)
    b = solved.solved_curve(sub, _Rows(ds, names, rows), form)
    for f in ("p0", "zeta", "area", "non_area", "contact", "s_factor"):
        np.testing.assert_array_equal(getattr(b, f), getattr(a, f), err_msg=f)
    assert b.E_star == a.E_star
    assert b.psd.cache_key() == a.psd.cache_key()


def test_the_solved_curves_spectrum_is_the_datasets(four):
    """The curve's spectrum (built once per content) is ``spectrum_of(ds)``: the same content
    key and values, whichever loads were selected."""
    ctx, ds = four
    names = solved.curve_variables(ctx)
    ref = spectrum_of(ds)
    for rows in ([0], [1, 2]):
        rows = np.array(rows)
        sub = SimpleNamespace(p0=ctx.p0[rows], boundary=None, coefficient=None, solve_at=None)
        psd = solved.solved_curve(sub, _Rows(ds, names, rows)).psd
        assert psd.cache_key() == ref.cache_key()
        q = np.geomspace(float(ref.q_L), float(ref.q_1), 7)
        np.testing.assert_array_equal(psd.C(q), ref.C(q))
