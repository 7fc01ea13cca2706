"""Many loads through a table in the load (:mod:`xpersson_interface._by_load`): the nodes exact,
every other load within its stated error of the direct path, which the output carries."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from interface_testlib import scene

import xpersson
from xpersson_interface import _by_load as by_load_mod
from xpersson_interface import _first_level as first_mod
from xpersson_interface import _stencils as stencils_mod
from xpersson_interface._by_load import TOL, by_load

U = np.linspace(0.0, 5.0, 64)


def _smooth(p0: np.ndarray) -> dict[str, np.ndarray]:
    """Outputs of the shape of the gap distribution: a density row moving and narrowing with
    ln p0, a falling mean, a rising weight (all positive, smooth in ln p0)."""
    x = np.log(p0)[:, None]
    centre, width = 3.0 - 0.2 * x, 1.0 / (1.0 + 0.05 * x)
    rows = np.exp(-0.5 * ((U - centre) / width) ** 2) / width
    return {"rho": rows, "mean": np.exp(-0.3 * x[:, 0]), "weight": 1.0 - np.exp(-p0 / 1e4)}


class Direct:
    """An ``exact`` callback that records the loads it is asked for."""

    def __init__(self, p0: np.ndarray, fn=_smooth) -> None:
        self.p0, self.fn, self.asked = p0, fn, []

    def __call__(self, rows: np.ndarray) -> dict[str, np.ndarray]:
        self.asked.append(np.asarray(rows))
        return self.fn(self.p0[rows])


def _relative(got: dict, want: dict) -> np.ndarray:
    """The largest relative error per load over the outputs (rows: of the row's largest)."""
    out = np.zeros(next(iter(want.values())).shape[0])
    for k, w in want.items():
        d = np.abs(got[k] - w)
        if w.ndim > 1:
            out = np.maximum(out, d.max(axis=1) / np.abs(w).max(axis=1))
        else:
            out = np.maximum(out, d / np.abs(w))
    return out


def test_few_loads_are_computed_directly_in_one_call():
    p0 = np.geomspace(1e3, 1e6, by_load_mod.TABLE_MIN - 1)
    direct = Direct(p0)
    out, err = by_load(p0, direct)
    assert len(direct.asked) == 1 and np.array_equal(direct.asked[0], np.arange(p0.size))
    assert not err.any()
    np.testing.assert_array_equal(out["rho"], _smooth(p0)["rho"])


@settings(max_examples=40, deadline=None)
@given(decades=st.floats(0.05, 8.0), extra=st.integers(-3, 3))
def test_the_table_starts_at_three_loads_per_node(decades, extra):
    """From DENSITY times the first level's nodes (16 per decade, at least 4 ORDER) and
    TABLE_MIN loads on, the table; one load fewer: every load directly, in one call."""
    top = 1e3 * 10.0**decades
    span = np.log10(top / 1e3)  # (as the range's endpoints give it, whatever the loads between)
    nodes = max(by_load_mod.PER_DECADE * span, 4 * by_load_mod.ORDER) + 1
    least = max(by_load_mod.TABLE_MIN, int(np.ceil(by_load_mod.DENSITY * nodes)))
    n = least + extra
    p0 = np.geomspace(1e3, top, n)
    assert by_load_mod.tabled(p0, 0) == (n >= least)
    direct = Direct(p0)
    out, err = by_load(p0, direct)
    asked = np.unique(np.concatenate(direct.asked))
    if n < least:
        assert len(direct.asked) == 1 and not err.any()
    else:  # a smooth function: fewer loads computed than asked, the rest within the estimate
        assert asked.size < n and err.max() <= TOL
        assert np.all(_relative(out, _smooth(p0)) <= err + 1e-15)


def test_interpolated_loads_lie_within_their_estimate():
    """Nodes bit for bit; the others within their (positive) estimate and the tolerance; far
    fewer loads computed than asked for."""
    p0 = np.geomspace(1e3, 1e6, 3000)
    direct = Direct(p0)
    out, err = by_load(p0, direct)
    exact = _smooth(p0)
    asked = np.unique(np.concatenate(direct.asked))
    assert asked.size < 100
    assert not err[asked].any() and np.all(err[np.setdiff1d(np.arange(p0.size), asked)] > 0)
    for k in exact:
        np.testing.assert_array_equal(out[k][asked], exact[k][asked])
    rel = _relative(out, exact)
    assert np.all(rel <= err + 1e-15) and err.max() <= TOL
    assert rel.max() < 1e-6  # a smooth function: far below the estimate (noise allowance)


def test_loads_in_any_order_and_repeated_get_the_values_of_their_load():
    p0 = np.geomspace(1e3, 1e6, 1000)
    rng = np.random.default_rng(3)
    shuffled = np.concatenate((p0, p0[:200]))[rng.permutation(1200)]
    ref, ref_err = by_load(p0, Direct(p0))
    out, err = by_load(shuffled, Direct(shuffled))
    where = np.searchsorted(p0, shuffled)
    np.testing.assert_array_equal(out["rho"], ref["rho"][where])
    np.testing.assert_array_equal(err, ref_err[where])


def _sealed(p0: np.ndarray) -> dict[str, np.ndarray]:
    """A smooth positive output that is NaN above 3e4 Pa (a sealed range)."""
    v = np.exp(-0.3 * np.log(p0))
    return {"gap": np.where(p0 > 3e4, np.nan, v)}


def test_a_transition_is_refined_and_its_loads_match_the_direct_path():
    """Loads between two NaN nodes take NaN; those whose stencil straddles the transition are
    tabled again more densely, down to the direct path: the NaN pattern is the direct one."""
    p0 = np.geomspace(1e3, 1e6, 2000)
    direct = Direct(p0, _sealed)
    out, err = by_load(p0, direct)
    exact = _sealed(p0)["gap"]
    np.testing.assert_array_equal(np.isnan(out["gap"]), np.isnan(exact))
    ok = ~np.isnan(exact)
    assert np.all(np.abs(out["gap"][ok] / exact[ok] - 1.0) <= err[ok] + 1e-15)
    assert len(direct.asked) > 1  # the refinement asked again


def test_a_kink_is_refined_or_computed_directly():
    """A kink (no smooth interpolant across it): the loads near it come within their estimate
    (refined tables or the direct path), none beyond the tolerance."""

    def kink(p0):
        x = np.log(p0 / 3e4)
        return {"v": np.exp(np.abs(x) + 0.1 * x)}

    p0 = np.geomspace(1e3, 1e6, 3000)
    out, err = by_load(p0, Direct(p0, kink))
    rel = np.abs(out["v"] / kink(p0)["v"] - 1.0)
    assert np.all(rel <= err + 1e-15) and err.max() <= TOL


def _sweeping_tail(width: float):
    """A row whose bulk stays put (its far tail floored at 1e-300 in the logarithm) and a
    Gaussian of 1e-6 of its height and of ``width`` sweeping across the far tail, 0.9 of the
    grid's unit per unit of ln p0: at 0.01, each element's value changes by hundreds of
    decades between the table's nodes (as the far-tail Gaussians of ``gap_pdf`` with
    Almqvist's separation)."""

    def fn(p0: np.ndarray) -> dict[str, np.ndarray]:
        x = np.log(p0 / 1e3)[:, None]
        with np.errstate(under="ignore"):
            bulk = np.exp(-0.5 * ((U - 1.0) / 0.1) ** 2)
            tail = 1e-6 * np.exp(-0.5 * ((U - 5.0 + 0.9 * x) / width) ** 2)
        return {"rho": bulk + tail}

    return fn


def test_a_row_element_sweeping_between_nodes_is_not_interpolated_past_its_row():
    """The polynomials of such elements (small at every node) rise far above the row between
    nodes, where the check at the odd nodes does not look: the spike test (``SPIKE``) refines
    those loads, and every load comes within its estimate; without it, 2.5e-2 of the row's
    maximum (1988 times the estimate)."""
    p0 = np.geomspace(1e3, 1e6, 3000)
    fn = _sweeping_tail(0.01)
    exact = fn(p0)
    out, err = by_load(p0, Direct(p0, fn))
    rel = _relative(out, exact)
    assert np.all(rel <= err + 1e-15) and err.max() <= TOL
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(stencils_mod, "SPIKE", np.inf)
        blind, blind_err = by_load(p0, Direct(p0, fn))
    assert np.max(_relative(blind, exact) - blind_err) > 1e-2


def test_the_spike_test_costs_no_load_where_nothing_overshoots():
    """A tail wide enough for its polynomials to stay below ``SPIKE_SIZE`` of the row: the
    same loads computed, the same values, with and without the test."""
    p0 = np.geomspace(1e3, 1e6, 3000)
    fn = _sweeping_tail(0.05)
    with_test, without = Direct(p0, fn), Direct(p0, fn)
    out, err = by_load(p0, with_test)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(stencils_mod, "SPIKE", np.inf)
        ref, ref_err = by_load(p0, without)
    np.testing.assert_array_equal(np.concatenate(with_test.asked), np.concatenate(without.asked))
    np.testing.assert_array_equal(out["rho"], ref["rho"])
    np.testing.assert_array_equal(err, ref_err)


P_SEAL = 3e5  # the load at which the singular output below vanishes


def _singular(p0: np.ndarray) -> dict[str, np.ndarray]:
    """``z = p0/P_SEAL`` (as the leak analysis's ``zeta_c/zeta_max``) and, with
    ``t = ln(1/z)``, ``v = exp(-2/t + t)``, which vanishes faster than any power of ``t`` at
    ``P_SEAL`` (as ``u1``)."""
    z = p0 / P_SEAL
    t = -np.log(z)
    return {"z": z, "v": np.exp(-2.0 / t + t)}


def _t_weight(o: dict, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return -np.log(o["z"]), np.zeros(x.size)


def test_a_transformed_output_is_tabled_up_to_its_singularity():
    """``v`` tabled as ``t ln v`` (smooth: ``-2 + t^2``) is interpolated within its estimate up
    to a few loads from ``P_SEAL``, with fewer loads computed than tabling ``ln v``."""
    p0 = np.geomspace(1e3, 0.98 * P_SEAL, 3000)
    weighted, plain = Direct(p0, _singular), Direct(p0, _singular)
    out, err = by_load(p0, weighted, weights=((frozenset({"v"}), _t_weight),))
    ref, ref_err = by_load(p0, plain)
    exact = _singular(p0)
    rel = np.abs(out["v"] / exact["v"] - 1.0)
    assert np.all(rel <= err + 1e-15) and err.max() <= TOL
    n_weighted = np.unique(np.concatenate(weighted.asked)).size
    assert n_weighted < 0.5 * np.unique(np.concatenate(plain.asked)).size
    assert np.count_nonzero(err[p0 > 0.9 * P_SEAL]) > 0  # interpolated close to it


def _two_seals(p0: np.ndarray) -> dict[str, np.ndarray]:
    """Two outputs sealing at 2e4 and 2.1e4 Pa (NaN, then 0; the second as ``(1 - p0/p)^3``,
    refined down to its seal), a flag of the second."""
    a = np.where(p0 < 2e4, p0**-0.3, np.nan)
    b = np.where(p0 < 2.1e4, np.abs(1.0 - p0 / 2.1e4) ** 3 * p0**-0.2, 0.0)
    return {"a": a, "b": b, "flag": (b <= 0).astype(float)}


def test_a_sealed_stretch_between_alike_nodes_is_exact_whatever_its_length():
    """Past both seals every output is irregular and alike: each load between two such nodes
    takes their values (its estimate the noise), even in a refined region holding fewer than
    ORDER of them; only the loads around the seals are computed directly."""
    p0 = np.geomspace(1e3, 1e6, 3000)
    direct = Direct(p0, _two_seals)
    out, err = by_load(p0, direct, keys=frozenset({"flag"}))
    exact = _two_seals(p0)
    sealed = p0 > 2.2e4
    for k in exact:
        np.testing.assert_array_equal(out[k][sealed], exact[k][sealed])
        ok = exact[k] > 0
        np.testing.assert_array_equal(ok, out[k] > 0)
        assert np.all(np.abs(out[k][ok] / exact[k][ok] - 1.0) <= err[ok] + 1e-15)
    asked = np.unique(np.concatenate(direct.asked))
    assert np.all(err[sealed][err[sealed] > 0] == by_load_mod.NOISE)
    # the table's own nodes there (27 at 16 per decade) and a few more; 50 if each refined
    # region needs ORDER sealed nodes of its own
    assert np.count_nonzero(sealed[asked]) < 40


def _both(analysis: str, n: int, least: dict) -> tuple:
    """``analysis`` at ``n`` loads through the table (its minimum lowered as ``least`` says, on
    modules' attributes, to keep the test small) and directly."""
    sc = scene([1.0], analyses={analysis: {}})
    sc["load"] = {"p0": {"start": "1 kPa", "stop": "3 MPa", "num": n}}
    mp = pytest.MonkeyPatch()
    try:
        for (mod, name), value in least.items():
            mp.setattr(mod, name, value)
        table = xpersson.solve(sc)
        mp.setattr(by_load_mod, "TABLE_MIN", 10**9)
        direct = xpersson.solve(sc)
    finally:
        mp.undo()
    return table, direct


@pytest.fixture(scope="module")
def solved():
    """gap_pdf at 300 loads (the table from 100 on), through the table and directly."""
    return _both("gap_pdf", 300, {(by_load_mod, "TABLE_MIN"): 100})


def test_gap_pdf_within_its_stated_error_of_the_direct_path(solved):
    table, direct = solved
    err = table["gap_pdf_load_error"].values
    assert table["gap_pdf_load_error"].attrs["units"] == "1"
    assert not direct["gap_pdf_load_error"].values.any()
    assert 0 < np.count_nonzero(err == 0) < 100 < np.count_nonzero(err) and err.max() <= TOL
    np.testing.assert_array_equal(table["u"].values, direct["u"].values)
    got = {k: table[k].transpose("p0", ...).values for k in ("gap_pdf", "gap_mean")}
    want = {k: direct[k].transpose("p0", ...).values for k in ("gap_pdf", "gap_mean")}
    rel = _relative(got, want)
    assert np.all(rel <= np.where(err > 0, err, 1e-12))
    cw = table["gap_contact_weight"].values
    assert np.all(cw <= 1.0)
    np.testing.assert_allclose(cw, direct["gap_contact_weight"].values, rtol=TOL)


@pytest.mark.parametrize(
    "params", [{"separation": "almqvist"}, {"method": "diffusion", "n_grid": 200}], ids=str
)
def test_gap_pdf_forms_not_smooth_in_the_load_are_computed_directly(params):
    """``_params.UNTABLED``: at a number of loads the default form tables (300 over 3.5
    decades, the minimum lowered to 100), every load computed directly: no estimate, the
    values of the direct path bit for bit."""
    sc = scene([1.0], analyses={"gap_pdf": params})
    sc["load"] = {"p0": {"start": "1 kPa", "stop": "3 MPa", "num": 300}}
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(by_load_mod, "TABLE_MIN", 100)
        got = xpersson.solve(sc)
        mp.setattr(by_load_mod, "TABLE_MIN", 10**9)
        want = xpersson.solve(sc)
    assert not got["gap_pdf_load_error"].values.any()
    for k in ("gap_pdf", "gap_mean", "gap_contact_weight"):
        np.testing.assert_array_equal(got[k].values, want[k].values)


def test_keys_are_taken_from_agreeing_stencils_and_stencils_stay_in_their_segment():
    """A key (a flag, the piece of a piecewise input) changes at 3e4 Pa, where the output has
    a kink: loads far from it are interpolated from one side only, within their estimate;
    every load keeps its own key."""

    def piecewise(p0):
        x = np.log(p0 / 3e4)
        return {"v": np.exp(np.where(x < 0, 0.5 * x, -0.2 * x)), "k": (x >= 0).astype(float)}

    p0 = np.geomspace(1e3, 1e6, 3000)
    direct = Direct(p0, piecewise)
    out, err = by_load(p0, direct, keys=frozenset({"k"}))
    exact = piecewise(p0)
    np.testing.assert_array_equal(out["k"], exact["k"])
    rel = np.abs(out["v"] / exact["v"] - 1.0)
    assert np.all(rel <= err + 1e-15) and err.max() <= TOL
    assert np.unique(np.concatenate(direct.asked)).size < 300


@pytest.fixture(scope="module")
def leaks():
    """leakage at 600 loads (the table from 100 on; its first level holds 32 loads per decade
    of the 3.5 decades), through the table and directly."""
    return _both("leakage", 600, {(by_load_mod, "TABLE_MIN"): 100, (first_mod, "LEAK_MIN"): 100})


def test_leakage_within_its_stated_error_of_the_direct_path(leaks):
    table, direct = leaks
    err = table["leak_load_error"].values
    assert err.max() <= by_load_mod.LEAK_TOL and np.count_nonzero(err) > table.p0.size // 3
    for k in ("leak_sealed", "leak_sealed_emt"):
        np.testing.assert_array_equal(table[k].values, direct[k].values)
    for k in ("leak_zeta_c", "leak_u1", "leak_rate", "leak_rate_emt", "leak_flow_factor"):
        got, want = table[k].values, direct[k].values
        np.testing.assert_array_equal(np.isnan(got), np.isnan(want))
        ok = np.isfinite(want) & (want > 0)
        np.testing.assert_array_equal(got[~ok & ~np.isnan(want)], want[~ok & ~np.isnan(want)])
        rel = np.abs(got[ok] / want[ok] - 1.0)
        # computed directly (0): the same loads in another batch, up to round-off (u1 is a
        # difference quotient: ~1e-12)
        assert np.all(rel <= np.where(err[ok] > 0, err[ok], 1e-10)), k


def test_u1_difference_quotient_is_converged_in_its_step():
    """``u1 = d(A u)/dA`` at zeta_c reads Phi from its spline: halving the difference step
    changes it by < 2e-5 (steep H = 0.95 spectrum, 6 decades). Through Phi's linear look-up
    table (before) the table's error, amplified ~1000x, moved it by 7e-5 here and by 0.05-0.7 %
    (median) on the design scenes of benchmarks/summary.py, irregular in the load."""
    from xpersson.physics import SolvedContact

    spec = {"model": "self_affine", "H": 0.95, "q_L": "100 1/m", "q_1": "1e8 1/m",
            "h_rms": "1 um"}  # fmt: skip
    sc = {
        "spectrum": spec,
        "material": {"E": "10 MPa", "nu": 0.5},
        "load": {"p0": [f"{float(p)!r} Pa" for p in np.geomspace(100.0, 2e3, 8)]},
        "output": {"zeta": [float(z) for z in np.geomspace(1.0, 1e3, 50)]},
        "analyses": {"leakage": {}},
    }
    ds = xpersson.solve(sc)
    zc = ds["leak_zeta_c"].values
    ok = np.isfinite(zc) & (zc < 20.0)
    assert ok.sum() >= 4
    rs = xpersson.Scene(sc).resolve()
    area = ds["area_fraction"].transpose("p0", "zeta").values
    contact = SolvedContact(rs.psd, rs.E_star, rs.p0, ds["zeta"].values, area)
    u = [contact.separation_at(zc, rel_step=h)[ok] for h in (1e-3, 5e-4)]
    assert np.max(np.abs(u[1] / u[0] - 1.0)) < 2e-5


def _drawn(seed: int) -> dict:
    """A seeded self-affine spectrum outside benchmarks/summary.py's design (held out)."""
    rng = np.random.default_rng(1000 + seed)
    H, q_L = float(rng.uniform(0.3, 0.95)), float(10 ** rng.uniform(2.0, 4.0))
    roll = 10 ** float(rng.uniform(0.3, 1.0)) if seed % 2 else 1.0
    return {"model": "self_affine", "H": H, "q_L": f"{q_L!r} 1/m",
            "q_r": f"{q_L * roll!r} 1/m", "q_1": f"{q_L * 10.0 ** int(rng.integers(3, 7))!r} 1/m",
            "h_rms": "1 um"}  # fmt: skip


@pytest.mark.parametrize("seed", range(4))
def test_leakage_table_within_its_estimate_on_drawn_scenes(seed):
    """Seeded held-out spectra (with and without roll-off): every interpolated load of the leak
    analysis within its stated error of the direct path, the error within LEAK_TOL."""
    sc = {
        "spectrum": _drawn(seed),
        "material": {"E": "10 MPa", "nu": 0.5},
        "load": {"p0": {"start": "1 kPa", "stop": "1 MPa", "num": 240}},
        "output": {"zeta": [float(z) for z in np.geomspace(1.0, 1e3, 50)]},
        "analyses": {"leakage": {}},
    }
    mp = pytest.MonkeyPatch()
    try:
        mp.setattr(by_load_mod, "TABLE_MIN", 60)
        mp.setattr(first_mod, "LEAK_MIN", 60)
        mp.setattr(first_mod, "LEAK_PER_DECADE", 8)  # the table's regime at 60 loads
        mp.setattr(by_load_mod, "DENSITY", 1.0)  # (its nodes: 8 per decade, not 16)
        mp.setattr(first_mod, "FEW", 0)  # the plain table (no predicted first level, no kinks)
        table = xpersson.solve(sc)
        mp.setattr(by_load_mod, "TABLE_MIN", 10**9)
        direct = xpersson.solve(sc)
    finally:
        mp.undo()
    err = table["leak_load_error"].values
    assert err.max() <= by_load_mod.LEAK_TOL and np.count_nonzero(err) > 0
    for k in ("leak_zeta_c", "leak_u1", "leak_rate", "leak_rate_emt", "leak_flow_factor_emt"):
        got, want = table[k].values, direct[k].values
        np.testing.assert_array_equal(np.isnan(got), np.isnan(want))
        ok = np.isfinite(want) & (want > 0) & (err > 0)
        assert np.all(np.abs(got[ok] / want[ok] - 1.0) <= err[ok]), k


#: Held-out spectra (``benchmarks/summary_design.design(12, 37)`` and ``(12, 38)``) whose leak
#: table fell short of its estimate 1.28x with a noise allowance of 1e-5: a kink of u1 at
#: zeta_c = 1.64 (roll-off H = 0.83) and the area spline's ringing just past the roll-off
#: (H = 0.63, zeta_c 4.5-4.7), both narrower than the table's spacing.
_KINKED = {
    "kink": {"model": "self_affine", "H": 0.8319, "q_L": "4834.281958533276 1/m",
             "q_r": "22081.48882540658 1/m", "q_1": "48342819.585332766 1/m", "h_rms": "1 um"},
    "ringing": {"model": "self_affine", "H": 0.6276, "q_L": "2405.2229074205247 1/m",
                "q_r": "10447.226407941289 1/m", "q_1": "240522290.74205247 1/m",
                "h_rms": "1 um"},
}  # fmt: skip


@pytest.mark.parametrize("name", sorted(_KINKED))
def test_leakage_table_covers_features_narrower_than_its_spacing(name, leak_1000):
    """At 1000 loads (the table's own settings) every interpolated load of the leak analysis is
    within its stated error of the direct path, on the two held-out spectra with a feature
    narrower than the table's spacing (LEAK_NOISE covers it)."""
    table, direct = leak_1000(_KINKED[name])
    err = table["leak_load_error"].values
    assert np.count_nonzero(err) > 500
    for k in ("leak_zeta_c", "leak_u1", "leak_flow_factor", "leak_rate", "leak_rate_emt"):
        got, want = table[k].values, direct[k].values
        np.testing.assert_array_equal(np.isnan(got), np.isnan(want))
        ok = np.isfinite(want) & (want > 0) & (err > 0)
        assert np.all(np.abs(got[ok] / want[ok] - 1.0) <= err[ok]), k


def test_free_loads_are_nodes_of_the_first_call():
    """Loads marked free are asked for in the first call and keep their own values."""
    p0 = np.geomspace(1e3, 1e6, 3000)
    free = np.zeros(p0.size, dtype=bool)
    free[1500:1520] = True
    direct = Direct(p0)
    out, err = by_load(p0, direct, free=free)
    assert np.isin(np.flatnonzero(free), direct.asked[0]).all()
    assert not err[free].any()
    np.testing.assert_array_equal(out["rho"][free], _smooth(p0[free])["rho"])


def _lagrange_reference(xn: np.ndarray, x: np.ndarray, i: np.ndarray, m: int) -> np.ndarray:
    """The weights as the table computed them before its one-buffer form (a fresh quotient
    array per factor): the bits the load table's results were recorded with."""
    X = xn[i[:, None] + np.arange(m)]
    num = x[:, None] - X
    w = np.ones((x.size, m))
    with np.errstate(divide="ignore", invalid="ignore"):  # (q_bb: 0/0, set to 1)
        for b in range(m):
            q = num[:, b, None] / (X - X[:, b, None])
            q[:, b] = 1.0
            w *= q
    return w


@settings(max_examples=40, deadline=None)
@given(
    st.integers(2, 9),
    st.lists(st.floats(1e-3, 1.0), min_size=10, max_size=40),
    st.lists(st.floats(0.0, 1.0), min_size=1, max_size=30),
)
def test_stencil_weights_reproduce_polynomials_and_keep_their_bits(m, gaps, where):
    """The ``m``-point Lagrange weights sum ``X^j`` to ``x^j`` for ``j < m`` (any nodes, any
    point), bit for bit the per-factor product; a check given the nodes' segments gives the
    same estimate as one that finds them."""
    xn = np.cumsum(gaps)
    x = xn[0] + np.asarray(where) * (xn[-1] - xn[0])
    i = np.clip(np.searchsorted(xn, x) - m // 2, 0, xn.size - m)
    w = stencils_mod._lagrange(xn, x, i, m)
    assert w.tobytes() == _lagrange_reference(xn, x, i, m).tobytes()
    X = xn[i[:, None] + np.arange(m)] - xn[0]  # (shifted: the sums stay well conditioned)
    for j in range(m):
        got = np.sum(w * X**j, axis=1)
        want = (x - xn[0]) ** j
        scale = np.sum(np.abs(w) * np.abs(X) ** j, axis=1) + 1.0
        assert np.all(np.abs(got - want) <= 1e-9 * scale)
    at = {"v": np.exp(-xn), "k": (xn > xn[xn.size // 2]).astype(float)}
    roles = (frozenset({"k"}), ())
    logs = stencils_mod._logs(at, roles, xn)
    seg = stencils_mod._segments(at, roles[0])
    plain = by_load_mod._check(xn, at, logs, roles, m)
    assert plain.tobytes() == by_load_mod._check(xn, at, logs, roles, m, seg).tobytes()


def test_a_group_s_stencils_cross_other_groups_keys_but_not_their_own():
    """Two groups: ``v`` with a kink where its key ``k`` changes (at x = 0), ``w`` smooth
    (a quadratic in ``ln p0``: any 8-point stencil reproduces its logarithm). ``w``'s stencils
    cross ``k`` (exact to round-off at every load, also between ``k``'s segments), ``v``'s
    do not (between them: no stencil, the load refined), as in one group."""
    xn = np.linspace(-2.0, 2.0, 41)
    x = 0.5 * (xn[1:] + xn[:-1])

    def outputs(t):
        return {
            "v": np.exp(np.where(t < 0, 0.5 * t, -0.2 * t)),
            "k": (t >= 0).astype(float),
            "w": np.exp(0.3 * t - 0.05 * t * t),
        }

    at = outputs(xn)
    roles = (frozenset({"k"}), ())
    logs = stencils_mod._logs(at, roles, xn)
    tol = (TOL, 0.0, (8,), 16.0)
    across = np.flatnonzero((x > xn[19]) & (x < xn[20]))  # between the last k = 0 node and k = 1
    groups = (frozenset({"v", "k"}), frozenset({"w"}))

    def grouped(gs):  # each group on its own keys, the estimate the largest (as by_group)
        vals, est = {}, np.zeros(x.size)
        for g in gs:
            own = by_load_mod.own_roles(roles, g)
            lg = {k: v for k, v in logs.items() if k in g}
            v, e = by_load_mod._one_group(xn, {k: a for k, a in at.items() if k in g}, lg, x,
                                          own, tol)  # fmt: skip
            vals.update(v)
            est = np.maximum(est, e)
        return vals, est

    vals, est = grouped(groups)
    np.testing.assert_allclose(vals["w"], outputs(x)["w"], rtol=1e-12)
    assert np.all(np.isinf(est[across]))  # v has no stencil there
    one, est1 = by_load_mod._one_group(xn, at, logs, x, roles, tol)
    assert np.all(np.isinf(est1[across]))
    _, est_w = grouped((frozenset({"w"}),))
    assert np.all(np.isfinite(est_w[across]))  # w's own group: a stencil across k
    far = np.abs(x) > 1.0  # v's stencils within their own side: the same values either way
    np.testing.assert_array_equal(vals["v"][far], one["v"][far])
