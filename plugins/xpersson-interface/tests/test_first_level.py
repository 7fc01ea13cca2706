"""The leakage load table's first level (:mod:`xpersson_interface._first_level`): loads predicted
to be computed directly are computed in the table's first call, exactly, and the table stays
within its stated error around them."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from interface_testlib import scene
from test_by_load import _KINKED, Direct, _relative

import xpersson
from xpersson import physics
from xpersson_interface import _by_load as by_load_mod
from xpersson_interface import _first_level as first_mod
from xpersson_interface._by_load import LEAK_TOL, by_load
from xpersson_interface._leakage import NEAR_SEALING


def _kinked(p0: np.ndarray) -> dict[str, np.ndarray]:
    """A smooth output with a slope jump at 2e4 Pa (a key marks its side), as ``u1`` at a
    breakpoint of the spectrum."""
    x = np.log(p0 / 2e4)
    return {"v": np.exp(np.where(x < 0, -0.4 * x, -0.7 * x) + 0.1 * x * x), "k": (x >= 0) * 1.0}


@settings(max_examples=25, deadline=None)
@given(
    n=st.integers(500, 1500),
    lo=st.floats(2.5, 3.5),
    spans=st.lists(st.tuples(st.floats(0.0, 1.0), st.floats(0.0, 0.3)), max_size=3),
)
def test_first_level_loads_are_computed_in_the_first_call_and_the_rest_within_its_error(
    n, lo, spans
):
    """Whatever loads are given as the first level's (``free``): each is computed in the first
    call and carries its direct value (error 0); every other load stays within its stated
    error of the direct path, and that error within the tolerance."""
    p0 = np.geomspace(10**lo, 10 ** (lo + 3.0), n)
    t = np.linspace(0.0, 1.0, n)
    free = np.zeros(n, dtype=bool)
    for a, w in spans:
        free |= (t >= a) & (t <= a + w)
    direct = Direct(p0, _kinked)
    out, err = by_load(p0, direct, LEAK_TOL, frozenset({"k"}), free=free)
    assert set(np.flatnonzero(free)) <= set(direct.asked[0].tolist())
    exact = _kinked(p0)
    assert not err[free].any()
    np.testing.assert_array_equal(out["v"][free], exact["v"][free])
    np.testing.assert_array_equal(out["k"], exact["k"])
    rel = _relative({"v": out["v"]}, {"v": exact["v"]})
    assert np.all(rel <= err + 1e-15) and err.max() <= LEAK_TOL


def _curves(zc: np.ndarray, z_max: float = 1e3) -> tuple[np.ndarray, np.ndarray]:
    """Contact area curves ``A = a_c (zc/zeta)^0.3`` (NaN ``zc``: above ``a_c`` everywhere)
    on 50 magnifications: each crosses ``a_c = 0.42`` at its ``zc``."""
    zeta = np.geomspace(1.0, z_max, 50)
    top = np.where(np.isfinite(zc), zc, 2.0 * z_max)
    return zeta, np.minimum(0.42 * (top[:, None] / zeta) ** 0.3, 1.0)


@settings(max_examples=40, deadline=None)
@given(
    frac=st.lists(st.floats(0.01, 0.99), min_size=1, max_size=60),
    n_shut=st.integers(0, 2 * first_mod.SHORT),
    n_sealed=st.integers(0, 5),
)
def test_predicted_loads(frac, n_shut, n_sealed):
    """Predicted: the loads whose crossing lies above ``(1 - MARGIN) NEAR_SEALING zeta_max``
    (the stored curve's crossing within 1e-3 of the threshold left out) and, when fewer than
    ``SHORT``, those the junction seals; never a load sealed by both."""
    rel = np.sort(frac)
    zc = np.concatenate((rel * 1e3, np.full(n_shut + n_sealed, np.nan)))
    zeta, area = _curves(zc)
    sealed = np.zeros(zc.size, dtype=bool)
    sealed[zc.size - n_sealed :] = True
    got = first_mod.predicted(zeta, area, 0.42, sealed)
    limit = (1.0 - first_mod.MARGIN) * NEAR_SEALING
    opened, shut = got[: rel.size], got[rel.size : rel.size + n_shut]
    assert not got[sealed].any()
    assert opened[rel > limit * 1.001].all() and not opened[rel < limit * 0.999].any()
    assert np.all(shut == (n_shut < first_mod.SHORT))


@settings(max_examples=60, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 80), st.floats(0.0, 1.05))
def test_beyond_is_the_crossings_side_of_every_load(seed, n, where):
    """``_beyond`` (the crossings computed only where their interval holds the threshold) is
    ``critical_magnification``'s verdict for every load: random rough curves, thresholds on
    and between the magnifications, curves that never cross, that start below ``a_c``, and
    rows with a NaN (whose crossing can be NaN too)."""
    rng = np.random.default_rng(seed)
    zeta = np.concatenate(([1.0], np.sort(rng.uniform(1.0, 1e3, 49))))
    zeta = np.unique(zeta)
    steps = rng.uniform(0.0, 0.1, (n, zeta.size)) * (rng.random((n, zeta.size)) < 0.7)
    area = np.clip(rng.uniform(0.3, 1.0, (n, 1)) - np.cumsum(steps, axis=1), 0.0, 1.0)
    area[rng.random(n) < 0.1, :] = 1.0  # never below a_c
    area[rng.random(n) < 0.1, 0] = 0.1  # below a_c from the first node on
    nan = rng.random(n) < 0.1
    area[nan, rng.integers(zeta.size)] = np.nan
    limit = zeta[rng.integers(zeta.size)] if rng.random() < 0.3 else where * zeta[-1]
    zc = physics.critical_magnification(zeta, area, 0.42)
    near, crossed = first_mod._beyond(zeta, area, 0.42, limit)
    with np.errstate(invalid="ignore"):
        np.testing.assert_array_equal(near, zc > limit)
    np.testing.assert_array_equal(crossed, np.isfinite(zc))


@pytest.fixture(scope="module")
def calls():
    """leakage at 600 loads (the table from 100 on; a roll-off spectrum: a table per group of
    outputs, :mod:`xpersson_interface._by_group`): per direct call, the rows computed for each
    group (junction, effective medium), and the outputs."""
    sc = scene([1.0], analyses={"leakage": {}})
    sc["load"] = {"p0": {"start": "1 kPa", "stop": "3 MPa", "num": 600}}
    rows: list[list[np.ndarray]] = []
    run = by_load_mod._Direct.run

    def recording(self):
        rows.append([np.flatnonzero(p & ~d) for p, d in zip(self.pending, self.done, strict=True)])
        run(self)

    mp = pytest.MonkeyPatch()
    try:
        mp.setattr(by_load_mod, "TABLE_MIN", 100)
        mp.setattr(first_mod, "LEAK_MIN", 100)
        mp.setattr(by_load_mod._Direct, "run", recording)
        ds = xpersson.solve(sc)
    finally:
        mp.undo()
    return rows, ds


def test_near_sealing_loads_are_computed_in_the_first_call(calls):
    """The loads the direct path finds near the junction's sealing (``zeta_c`` above
    ``NEAR_SEALING zeta_max``: computed directly, each a key of its own) have their junction
    computed in the table's first call (their effective medium tabled, within the tolerance);
    those the junction alone seals (fewer than ``SHORT`` here) are computed there for both."""
    rows, ds = calls
    zc = ds["leak_zeta_c"].values
    near = np.flatnonzero(zc > NEAR_SEALING * ds["zeta"].values[-1])
    shut = np.flatnonzero((ds["leak_sealed"].values == 1) & (ds["leak_sealed_emt"].values == 0))
    assert near.size and shut.size < first_mod.SHORT
    junction, medium = (set(r.tolist()) for r in rows[0])
    assert set(near) | set(shut) <= junction and set(shut) <= medium
    err = ds["leak_load_error"].values
    assert not err[shut].any() and np.all(err[near] <= LEAK_TOL)


def test_loads_near_a_roll_off_are_computed_directly_and_the_rest_within_their_error(leak_1000):
    """A roll-off spectrum at 1000 loads: every load whose ``zeta_c`` lies within ``KINK`` of
    the breakpoint ``q_r/q_L`` has its junction computed directly (equal to the direct path's),
    and every interpolated output is within its load's stated error of the direct path (the
    effective medium tabled in its own group, with nodes of its own, across the window)."""
    table, direct = leak_1000(_KINKED["ringing"])  # a roll-off at q_r / q_L = 4.34
    err = table["leak_load_error"].values
    zb = 10447.226407941289 / 2405.2229074205247  # (spec: q_r / q_L)
    with np.errstate(invalid="ignore"):
        window = np.abs(np.log(direct["leak_zeta_c"].values / zb)) < 0.999 * np.log1p(
            first_mod.KINK
        )
    assert window.sum() >= 10 and np.all(err[window] <= LEAK_TOL)
    for k in ("leak_u1", "leak_flow_factor", "leak_rate_emt", "leak_flow_factor_emt"):
        got, want = table[k].values, direct[k].values
        if "emt" not in k:  # the junction: direct (batch round-off)
            np.testing.assert_allclose(got[window], want[window], rtol=1e-12)
        ok = np.isfinite(want) & (want > 0) & (err > 0)
        assert np.all(np.abs(got[ok] / want[ok] - 1.0) <= err[ok]), k
