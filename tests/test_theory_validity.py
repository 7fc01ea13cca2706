"""The per-load validity flag of the core result (``theory_validity``, issue 22 item 4)."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.special import erfc

import xpersson
from xpersson.pipeline.diagnostics import SLOPE_LIMIT, VALIDITY_FLAGS

E, NU = 10e6, 0.5
E_STAR = E / (1 - NU**2)


def _solve(p0, *, h_rms: str = "1 um", output: dict | None = None) -> object:
    scene = {
        "spectrum": {
            "model": "self_affine",
            "H": 0.8,
            "q_L": "1e3 1/m",
            "q_r": "1e4 1/m",
            "q_1": "1e8 1/m",
            "h_rms": h_rms,
        },
        "material": {"E": f"{E} Pa", "nu": NU},
        "load": {"p0": [f"{p!r} Pa" for p in p0] if isinstance(p0, list) else f"{p0!r} Pa"},
    }
    if output:
        scene["output"] = output
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return xpersson.solve(scene)


def test_each_bit_is_set_exactly_where_its_condition_holds():
    loads = [1e-303, 1e4, 1e6, 2e7]
    ds = _solve(loads)
    flags = ds["theory_validity"].values
    assert flags.dtype == np.int8
    tau1 = float(ds["diffusion_time"].values[-1])
    # closed forms: 1 - A = erfc(p0 / 2 sqrt(tau_1)), A = erf(...) ~ p0 / sqrt(pi tau_1)
    open_ = np.array([erfc(p / (2 * math.sqrt(tau1))) for p in loads])
    area = np.array([p / math.sqrt(math.pi * tau1) for p in loads])
    want = (
        (np.array(loads) > E_STAR) * 1 + (open_ < 2.0**-53) * 4 + (area < np.finfo(float).tiny) * 8
    )
    np.testing.assert_array_equal(flags, want)
    assert flags[1] == 0 and flags[2] == 0  # ordinary loads: inside the regime
    assert flags[3] == 1 | 4  # above E* and at full contact
    assert flags[0] == 8  # the area underflows


def test_steep_surface_flags_every_load():
    ds = _solve([1e4, 1e6], h_rms="100 um")  # rms slope ~ 100 x that of the 1 um surface
    assert float(ds["rms_slope"].values) > SLOPE_LIMIT
    assert np.all(ds["theory_validity"].values & 2)


def test_cf_flag_attributes():
    ds = _solve(1e4)
    v = ds["theory_validity"]
    assert v.dims == ()  # a scalar load squeezes like every per-load output
    a = v.attrs
    masks, values = a["flag_masks"], a["flag_values"]
    meanings = a["flag_meanings"].split()
    assert list(masks) == list(VALIDITY_FLAGS) == list(values)
    assert len(meanings) == len(masks)
    assert all(m.replace("_", "").isalnum() for m in meanings)  # CF: blank-separated words
    assert masks.dtype == v.dtype and a["valid_max"] == sum(VALIDITY_FLAGS)
    assert int(v) == 0


@pytest.mark.parametrize("bit", list(VALIDITY_FLAGS))
def test_bits_are_distinct_powers_of_two(bit):
    assert bit & (bit - 1) == 0


def test_cf_flag_attributes_keep_the_variable_type_with_a_pressure_grid():
    """The P diagnostics (added after the flag) leave its CF attributes as they are: the valid
    range has the flag's own type (int8) with or without a stored P."""
    ds = _solve([1e4, 1e5], output={"zeta_per_decade": 2, "pressure_pdf": True, "p_points": 200})
    for name in ("theory_validity", "P_resolved"):
        attrs = ds[name].attrs
        assert attrs["valid_min"].dtype == attrs["valid_max"].dtype == ds[name].dtype == np.int8
    assert ds["P_integral"].attrs["units"] == "1" and "flag_meanings" in ds["P_resolved"].attrs


@settings(max_examples=40, deadline=None)
@given(
    st.tuples(st.integers(1, 3), st.integers(1, 40), st.integers(2, 3000)),
    st.integers(0, 2**32 - 1),
)
def test_blocked_trapezoid_is_numpys_bit_for_bit(shape, seed):
    from xpersson.pipeline.diagnostics import _trapezoid

    rng = np.random.default_rng(seed)
    y = rng.random(shape) * np.exp(5 * rng.normal(size=shape))
    x = np.sort(rng.random(shape[-1])) * 1e6
    np.testing.assert_array_equal(_trapezoid(y, x), np.trapezoid(y, x, axis=-1))


def test_diagnostics_run_again_replace_their_variables():
    """Inserted directly when new; a second call replaces them through xarray (same values)."""
    from xpersson.pipeline.diagnostics import pdf_resolution, theory_validity

    ds = _solve([1e4, 1e6])
    flags = ds["theory_validity"].values.copy()
    ds["theory_validity"] = ds["theory_validity"] * 0  # replaced by the caller
    theory_validity(ds)
    np.testing.assert_array_equal(ds["theory_validity"].values, flags)
    assert ds["theory_validity"].attrs["valid_max"] == sum(VALIDITY_FLAGS)
    assert pdf_resolution(ds) is None and "P_integral" not in ds  # no P stored: nothing added


_EDGES = st.sampled_from(
    [0.0, 1e-310, 2.0**-54, 2.0**-53, 0.3, 1.0, SLOPE_LIMIT, 3.1, E_STAR, 2 * E_STAR, math.nan]
)


@settings(max_examples=200, deadline=None)
@given(p0=_EDGES, slope=_EDGES, non=_EDGES, area=_EDGES)
def test_one_load_flags_equal_the_array_path(p0, slope, non, area):
    """The one-load path (Python floats) gives the bits and dtype of the array path (the same
    load twice), also at each condition's edge and for NaN."""
    from xpersson.pipeline.diagnostics import validity_flags

    one = validity_flags(np.array([p0]), E_STAR, slope, np.array([area]), np.array([non]))
    two = validity_flags(np.full(2, p0), E_STAR, slope, np.full(2, area), np.full(2, non))
    assert one.dtype == two.dtype == np.int8
    assert one.shape == (1,)
    assert one[0] == two[0] == two[1]
