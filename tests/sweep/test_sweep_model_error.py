"""A sweep carries the model error (issue 34): every point's ancillary variables equal its own
solve's, on the plain and the fast paths, in memory and in a folder; ``[output] model_error =
false`` leaves them out."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

import xpersson
from xpersson.pipeline import model_error
from xpersson.sweep import plain_paths

LOADS = ["300 Pa", "600 Pa", "0.2 MPa"]


def base(H, E, **output):
    """A campaign-like scene (roll-off at 2 q_L, q_1 = 16 q_L): the packaged table verifies
    H = 0.8 at the light loads, not H = 0.2 (outside its Hurst range) nor the heaviest load."""
    return {
        "spectrum": {
            "model": "self_affine",
            "H": H,
            "q_L": "1e4 1/m",
            "q_r": "2e4 1/m",
            "q_1": "1.6e5 1/m",
            "rms_slope": 0.1,
        },
        "material": {"E": E, "nu": 0.5},
        "load": {"p0": LOADS},
        "analyses": {"contact_stiffness": {}},
        "output": {"zeta_per_decade": 4, **output},
    }


def ancillary(ds):
    return sorted(n for n in ds.data_vars if n.endswith(model_error.SUFFIXES))


def swept(path, analyses=None, **kw):
    data = base([0.2, 0.8], ["0.5 MPa", "0.75 MPa"])
    if analyses is not None:
        data["analyses"] = analyses
    if path == "plain":
        with plain_paths():
            return xpersson.solve(data, **kw)
    return xpersson.solve(data, **kw)


@pytest.mark.fast_paths
@pytest.mark.parametrize(
    ("path", "analyses"),
    [
        ("batched", {}),  # contact_area: batched by contact similarity
        ("plain", {}),
        ("default", {"contact_stiffness": {}}),  # no contact similarity: point by point
    ],
)
def test_sweep_ancillary_variables_equal_each_points_own_solve(path, analyses, monkeypatch):
    from xpersson.sweep import fast

    runs = []
    batched_block = fast.batched_block
    monkeypatch.setattr(
        fast, "batched_block", lambda *a, **k: runs.append(1) or batched_block(*a, **k)
    )
    ds = swept(path, analyses)
    assert bool(runs) == (path == "batched")
    outputs = ["area_fraction"] + list(analyses)
    names = ancillary(ds)
    assert set(names) == {v + s for v in outputs for s in model_error.SUFFIXES}
    statuses = set()
    for H in (0.2, 0.8):
        for E in ("0.5 MPa", "0.75 MPa"):
            one = xpersson.solve({**base(H, E), "analyses": analyses})
            assert ancillary(one) == names
            got = ds.sel(H=H, E=float(E.split()[0]) * 1e6)
            for name in names + outputs:
                have = got[name].drop_vars(["E", "H"], errors="ignore")
                if have.dtype.kind == "f":  # batched: contact similarity, equal to 1e-13
                    xr.testing.assert_allclose(have, one[name], rtol=1e-13, atol=0)
                else:
                    xr.testing.assert_identical(have, one[name])
                assert have.attrs == one[name].attrs, name
            statuses.add(tuple(one["area_fraction_model_error_status"].values))
    assert statuses == {(0, 0, 0), (1, 1, 0)}  # H = 0.2 never, H = 0.8 at the light loads


@pytest.mark.fast_paths
def test_stacked_sweep_equals_the_plain_one(monkeypatch):
    """A sweep over H alone runs stacked (one run for the block's points)."""
    from xpersson.pipeline import stacked

    data = {**base([0.2, 0.5, 0.8], "0.75 MPa"), "analyses": {}}  # contact_stiffness: unstacked
    runs = []
    run_stacked = stacked.run_stacked
    monkeypatch.setattr(stacked, "run_stacked", lambda pts: runs.append(1) or run_stacked(pts))
    fast = xpersson.solve(data)
    assert runs  # the stacked path solved it
    with plain_paths():
        plain = xpersson.solve(data)
    names = ancillary(plain)
    assert names and ancillary(fast) == names
    for name in names:
        xr.testing.assert_allclose(fast[name], plain[name], rtol=1e-12, atol=0)
        assert fast[name].attrs == plain[name].attrs
    np.testing.assert_array_equal(
        fast["area_fraction_model_error_status"].values,
        plain["area_fraction_model_error_status"].values,
    )


def test_folder_sweep_round_trips_the_model_error(tmp_path):
    memory = swept("batched", {})
    folder = tmp_path / "run"
    swept("batched", {}, output=folder, chunk=2)  # two parts, batched
    back = xpersson.open_dataset(folder)
    assert ancillary(back) == ancillary(memory)
    for name in ancillary(memory):
        xr.testing.assert_identical(back[name].load(), memory[name])
    attrs = back["area_fraction"].attrs["ancillary_variables"]
    assert attrs == memory["area_fraction"].attrs["ancillary_variables"]


def test_switch_leaves_the_model_error_out_of_a_sweep():
    ds = xpersson.solve(base([0.2, 0.8], ["0.5 MPa", "0.75 MPa"], model_error=False))
    assert ancillary(ds) == []
    assert "ancillary_variables" not in ds["area_fraction"].attrs
