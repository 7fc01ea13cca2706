"""A plugin's contribution checked in one pass (``checks.check_contributions``, issue 36): the
same pairs as the variable-by-variable check when every value is clean, and the same first
failure (the same message, naming the same variable) when one is not."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from xpersson.checks import PluginFailure, check_contributions, checked_variable
from xpersson.pipeline._draft import Draft
from xpersson.plugins import VarSpec

SIZES = {"p0": 2, "zeta": 3}
BOUNDS = [(None, None), (0.0, None), (0.0, 1.0), (None, 5.0), (-1.0, 1.0)]
DIMS = [("p0", "zeta"), ("zeta",), ("p0",), ()]
SPECIAL = [np.nan, np.inf, -np.inf, -2.0, 0.0, 0.5, 1.0, 1.5, 7.0]


def _draft() -> Draft:
    from xpersson.pipeline._insert import new_variable

    return Draft(
        {
            "p0": new_variable(("p0",), np.array([1.0, 2.0])),
            "zeta": new_variable(("zeta",), np.array([1.0, 2.0, 3.0])),
        },
        {"p0", "zeta"},
    )


def _one_by_one(ds, values, specs, who):
    """The variable-by-variable check (what check_contributions did for every value)."""
    sizes = dict(ds.sizes)
    return {n: checked_variable(ds, n, v, specs[n], who, sizes) for n, v in values.items()}


@st.composite
def contributions(draw):
    n = draw(st.integers(1, 6))
    specs, values = {}, {}
    for i in range(n):
        dims = draw(st.sampled_from(DIMS))
        lo, hi = draw(st.sampled_from(BOUNDS))
        specs[f"v{i}"] = VarSpec(dims, "1", f"v{i}", valid_min=lo, valid_max=hi)
        shape = tuple(SIZES[d] for d in dims)
        size = int(np.prod(shape, dtype=int))
        pick = draw(st.lists(st.sampled_from(SPECIAL), min_size=size, max_size=size))
        clean = draw(st.booleans())  # mostly clean contributions: the one-pass case
        arr = np.array(pick, float).reshape(shape)
        if clean:
            arr = np.clip(np.nan_to_num(arr, nan=0.5), -1.0 if lo is None else lo, hi or 1.0)
        values[f"v{i}"] = (dims, arr)
    return specs, values


@settings(max_examples=80, deadline=None)
@given(contributions())
def test_one_pass_is_the_variable_by_variable_check(case):
    specs, values = case
    ds = _draft()
    try:
        want = _one_by_one(ds, values, specs, "plugin 'p'")
    except PluginFailure as exc:
        with pytest.raises(PluginFailure) as got:
            check_contributions(ds, values, specs, "plugin 'p'")
        assert str(got.value) == str(exc)  # the same first failure, named the same
        assert got.value.variable == exc.variable
        return
    got = check_contributions(ds, values, specs, "plugin 'p'")
    assert list(got) == list(want)
    for name, (dims, arr) in want.items():
        assert got[name][0] == dims
        assert got[name][1].dtype == arr.dtype and got[name][1].tobytes() == arr.tobytes()
        if isinstance(values[name][1], np.ndarray):
            assert got[name][1] is values[name][1]  # the plugin's array itself, no copy


def test_an_infinite_value_among_clean_ones_is_named():
    specs = {n: VarSpec(("zeta",), "1", n, valid_min=0.0) for n in ("a", "b", "c")}
    values = {n: (("zeta",), np.ones(3)) for n in specs}
    values["b"] = (("zeta",), np.array([1.0, np.inf, 2.0]))
    with pytest.raises(PluginFailure, match="variable 'b' has 1 non-finite"):
        check_contributions(_draft(), values, specs, "plugin 'p'")


def test_a_clean_contribution_is_checked_in_one_pass(monkeypatch):
    """Clean float pairs never reach the variable-by-variable check (a check_contributions
    that called it would fail here); one bad value does, for its message."""
    from xpersson.checks import _dataset

    calls = []
    one = _dataset.checked_variable
    monkeypatch.setattr(
        _dataset, "checked_variable", lambda *a, **k: calls.append(a) or one(*a, **k)
    )
    specs = {n: VarSpec(("p0", "zeta"), "1", n, valid_min=0.0, valid_max=1.0) for n in "abc"}
    values = {n: (("p0", "zeta"), np.full((2, 3), 0.5)) for n in specs}
    got = check_contributions(_draft(), values, specs, "plugin 'p'")
    assert calls == [] and all(got[n][1] is values[n][1] for n in specs)
    values["b"] = (("p0", "zeta"), np.full((2, 3), 1.5))
    with pytest.raises(PluginFailure, match="variable 'b'"):
        check_contributions(_draft(), values, specs, "plugin 'p'")
    assert [a[1] for a in calls] == ["a", "b"]  # in order, up to the first failure


def test_returned_dataarray_keeps_its_attrs_and_shares_its_values():
    """A plugin's DataArray is not copied (its values become the Dataset's, as a pair's array
    does), but its own attrs and coordinates are left as they were: the checked variable has
    a dict of its own, and a coordinate not indexed in the Dataset is dropped from the copy
    only."""
    import xarray as xr

    ds = _draft()
    vals = np.array([0.25, 0.5])
    value = xr.DataArray(vals, dims=("p0",), attrs={"units": "m", "note": "plugin's"})
    value = value.assign_coords(extra=("p0", np.array([7.0, 8.0])))
    spec = VarSpec(("p0",), "1", "v", valid_min=0.0, valid_max=1.0)
    out = checked_variable(ds, "v", value, spec, "who", dict(ds.sizes))
    assert np.shares_memory(np.asarray(out), vals)  # no copy of the values
    assert out.attrs == {}  # the spec's attrs go onto a dict of the result's own
    out.attrs["units"] = "Pa"
    assert value.attrs == {"units": "m", "note": "plugin's"}
    assert "extra" not in out.coords and "extra" in value.coords
    assert np.array_equal(value["extra"].values, [7.0, 8.0])
