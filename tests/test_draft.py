"""A run's Dataset made once (``pipeline._draft.Draft``, issue 36): the one-load Dataset is
the ``isel(p0=0)`` of the run's unsqueezed Dataset with the model-error ancillaries added, as
the step-by-step construction gave it; a draft changed the way only a Dataset can be changed
behaves as that Dataset."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import xarray as xr

from xpersson.pipeline import as_scene, model_error, run, squeeze_p0
from xpersson.pipeline._draft import Draft

SPECTRUM = {
    "model": "self_affine",
    "H": 0.8,
    "q_L": "1e4 1/m",
    "q_r": "3e4 1/m",
    "q_1": "1e7 1/m",
    "h_rms": "1 um",
}
ELASTIC = {
    "spectrum": SPECTRUM,
    "material": {"E": "10 MPa", "nu": 0.5},
    "load": {"p0": "100 kPa"},
    "output": {"zeta_per_decade": 6},
}
JKR = {**ELASTIC, "boundary": {"model": "jkr", "work_of_adhesion": "0.05 J/m**2"}}
TIMES = ("history", "date_created", "xpersson_solver")  # the clock and the solve's own time


def _quiet(fn, *args, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fn(*args, **kwargs)


def _without_times(ds: xr.Dataset) -> xr.Dataset:
    for key in TIMES:
        ds.attrs.pop(key, None)
    return ds


@pytest.mark.parametrize("scene", [ELASTIC, JKR], ids=["elastic", "jkr"])
def test_one_load_dataset_is_the_isel_of_the_unsqueezed_run(scene):
    rs = as_scene(scene).resolve()
    once = _quiet(run, rs, model_errors=True)
    ref = _quiet(run, rs, squeeze=False).isel(p0=0)
    added = model_error.attach(ref, rs)
    assert added and all(name in once.variables for name in added)
    _without_times(once)
    _without_times(ref)
    xr.testing.assert_identical(once, ref)
    assert list(once.variables) == list(ref.variables)  # the archive's order
    assert list(once.xindexes) == list(ref.xindexes) == ["zeta", "q_psd"]
    for name, var in once.variables.items():  # attrs with their own types (CF flag arrays)
        for key, value in var.attrs.items():
            assert type(value) is type(ref.variables[name].attrs[key]), (name, key)


def test_squeeze_p0_is_isel_and_leaves_its_input_as_it_was():
    ds = _quiet(run, as_scene(ELASTIC).resolve(), squeeze=False)
    out = squeeze_p0(ds)
    xr.testing.assert_identical(out, ds.isel(p0=0))
    out["area_fraction"].attrs["units"] = "changed"
    out.attrs["title"] = "changed"
    assert ds["area_fraction"].attrs["units"] == "1"
    assert ds.attrs["title"] != "changed"
    assert np.shares_memory(out["area_fraction"].values, ds["area_fraction"].values)  # a view


def test_a_draft_updated_as_only_a_dataset_can_be_is_that_dataset():
    ds = _quiet(run, as_scene(ELASTIC).resolve(), squeeze=False)
    draft = Draft.of(ds)
    draft = Draft(dict(draft.variables), set(ds.coords))
    draft.attrs.update(ds.attrs)
    # a variable over a new dimension with a non-index coordinate: needs Dataset.update
    extra = xr.DataArray(
        np.arange(3.0), dims="k", coords={"k": [1, 2, 3], "k_label": ("k", list("abc"))}
    )
    draft.update({"extra": extra})
    ref = ds.copy()
    ref.update({"extra": extra})
    xr.testing.assert_identical(draft.dataset(), ref)
    assert "k_label" in draft.variables and draft.sizes["k"] == 3
