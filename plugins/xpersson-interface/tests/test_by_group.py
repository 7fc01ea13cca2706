"""The load table with a table per group of outputs (:mod:`xpersson_interface._by_group`) and
the leak direct path that computes only the groups asked for (``_leak_direct.outputs``)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from xpersson_interface._by_group import by_group
from xpersson_interface._by_load import COMPUTED, by_load

GROUPS = (frozenset({"j", "k"}), frozenset({"m"}))


def _outputs(p0: np.ndarray, at: float, width: float) -> dict[str, np.ndarray]:
    """``j``: smooth with a narrow window around ``at`` (``k``: each load in it a key of its
    own, so computed directly), ``m``: smooth everywhere."""
    x = np.log(p0)
    near = np.abs(x - np.log(at)) < width
    return {
        "j": np.exp(-0.3 * x + 0.05 * np.sin(x)),
        "k": np.where(near, -p0, 0.0),
        "m": np.exp(0.2 * x - 0.01 * x * x),
    }


@settings(max_examples=20, deadline=None)
@given(
    n=st.integers(500, 1500),
    at=st.floats(3e3, 3e5),
    width=st.floats(0.08, 0.3),  # (wider than the first level's spacing: a node inside)
    junk=st.sampled_from([np.nan, 1e300, -1.0]),
)
def test_a_group_is_computed_only_where_it_is_asked_for_and_within_its_estimate(n, at, width, junk):
    """Every output of every load within the load's stated error of its exact value, and
    ``exact`` asked for ``m`` at far fewer loads than for ``j``/``k`` (the window's loads are
    computed for their own group only); what ``exact`` returns for a group not asked for
    (``junk``) is never read."""
    p0 = np.geomspace(1e3, 1e6, n)
    asked = np.zeros((2, n), dtype=bool)

    def exact(rows: np.ndarray, which: np.ndarray) -> dict[str, np.ndarray]:
        assert not (asked[:, rows] & which).any()  # each load and group once
        asked[:, rows] |= which
        out = _outputs(p0[rows], at, width)
        out["m"] = np.where(which[1], out["m"], junk)
        return out

    got, err = by_group(p0, exact, 2e-3, frozenset({"k"}), 1e-4, 0, (8,), 4.0 * 2**8, 16, (),
                        np.zeros(n, dtype=bool), GROUPS)  # fmt: skip
    want = _outputs(p0, at, width)
    for k in ("j", "m"):
        assert np.all(np.abs(got[k] / want[k] - 1.0) <= np.maximum(err, 1e-15)), k
    np.testing.assert_array_equal(got["k"], want["k"])
    window = want["k"] < 0
    assert asked[0, window].all()
    assert asked[1].sum() < asked[0].sum() and np.all(err <= 2e-3)
    assert np.all(err[asked.all(axis=0)] == 0.0) and np.all(err[~asked.all(axis=0)] > 0.0)


def test_one_group_of_every_output_is_the_one_table():
    """``by_group`` with one group holding every output: ``by_load``'s table bit for bit (the
    same nodes, refinement and direct calls)."""
    p0 = np.geomspace(1e3, 1e6, 800)
    calls: list[list[np.ndarray]] = [[], []]

    def exact(rows: np.ndarray, which: np.ndarray | None = None) -> dict[str, np.ndarray]:
        calls[which is not None].append(rows)
        return _outputs(p0[rows], 1e4, 0.05)

    args = (p0, exact, 2e-3, frozenset({"k"}), 1e-4, 0, (8,), 4.0 * 2**8, 16, ())
    free = np.zeros(p0.size, dtype=bool)
    free[[100, 500]] = True
    a = by_load(*args, free)
    b = by_group(*args, free[None, :], (frozenset({"j", "k", "m"}),))
    for k in a[0]:
        np.testing.assert_array_equal(a[0][k], b[0][k])
    np.testing.assert_array_equal(a[1], b[1])
    assert len(calls[0]) == len(calls[1]) > 1
    for r0, r1 in zip(*calls, strict=True):
        np.testing.assert_array_equal(r0, r1)


@pytest.fixture(scope="module")
def leak_call():
    """The leak analysis's direct call of a roll-off scene at 600 loads (its ``exact``)."""
    from interface_testlib import scene

    import xpersson
    from xpersson_interface import plugins as plugins_mod

    got = {}
    real = plugins_mod.by_group

    def rec(p0, exact, *a, **k):  # noqa: ANN001, ANN002, ANN003, ANN202
        got["exact"] = exact
        return real(p0, exact, *a, **k)

    sc = scene([1.0], analyses={"leakage": {}})
    sc["load"] = {"p0": {"start": "1 kPa", "stop": "3 MPa", "num": 600}}
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(plugins_mod, "by_group", rec)
        xpersson.solve(sc)
    return got["exact"]


@pytest.mark.parametrize("share", [0.1, 0.7])
def test_the_direct_call_computes_the_medium_only_where_asked_and_the_same_values(leak_call, share):
    """A direct call asked for the junction at every load and for the effective medium at a
    share of them (fewer than half: on a SolvedContact of their own; more: every load's
    computed): the junction's outputs bit for bit those of the call with both groups, the
    medium's equal to round-off where asked (the gap cells' band sums: ~1e-14) and NaN or
    the computed value elsewhere."""
    rows = np.arange(0, 600, 5)
    ask = np.random.default_rng(7).random(rows.size) < share
    both = leak_call(rows, np.ones((2, rows.size), dtype=bool))
    part = leak_call(rows, np.stack([np.ones(rows.size, dtype=bool), ask]))
    for k in ("leak_zeta_c", "leak_u1", "leak_flow_factor", "leak_rate", "leak_sealed", "piece"):
        np.testing.assert_array_equal(part[k], both[k], err_msg=k)
    for k in ("leak_flow_factor_emt", "leak_rate_emt", "leak_sealed_emt"):
        np.testing.assert_allclose(part[k][ask], both[k][ask], rtol=1e-13, atol=0, err_msg=k)
        other = part[k][~ask]
        assert np.all(np.isnan(other) | (other == both[k][~ask])), k
    # the groups computed: the junction everywhere, the medium where asked, at the loads
    # sealed by both theories (not computed: exact), or (most asked) everywhere; its values
    # there are the computed ones, the others NaN
    done = part[COMPUTED]
    sealed = (part["leak_sealed"] == 1) & (part["leak_sealed_emt"] == 1)
    assert done[:, 0].all() and np.all(done[:, 1] >= ask)
    assert done[:, 1].all() if share > 0.5 else np.all(done[:, 1] <= ask | sealed)
    for k in ("leak_flow_factor_emt", "leak_rate_emt", "leak_sealed_emt"):
        assert np.array_equal(np.isnan(part[k]), ~done[:, 1]), k


def test_loads_in_any_order_and_repeated_get_the_values_of_their_load():
    """Shuffled loads with repeats: each load's outputs and error those of the sorted,
    distinct loads (the table is built once over the distinct loads)."""
    p0 = np.geomspace(1e3, 1e6, 900)
    order = np.random.default_rng(3).permutation(np.concatenate((np.arange(900), [5, 450, 899])))

    def exact_of(p: np.ndarray):  # noqa: ANN202
        return lambda rows, which: _outputs(p[rows], 2e4, 0.1)

    args = (2e-3, frozenset({"k"}), 1e-4, 0, (8,), 4.0 * 2**8, 16, ())
    a, ea = by_group(p0, exact_of(p0), *args, np.zeros(900, dtype=bool), GROUPS)
    b, eb = by_group(p0[order], exact_of(p0[order]), *args, np.zeros(order.size, bool), GROUPS)
    for k in a:
        np.testing.assert_array_equal(b[k], a[k][order])
    np.testing.assert_array_equal(eb, ea[order])


def test_values_computed_unasked_serve_a_later_level_instead_of_a_call():
    """An ``exact`` that reports (``COMPUTED``) the groups it computed unasked: a later level
    that asks for those loads takes the kept values (no load computed twice; without the
    report 80 of them are, ``m``'s refinement around its step at the junction's first-level
    loads), and the outputs and errors are the same bits (an ``exact`` whose loads do not
    depend on each other)."""
    p0 = np.geomspace(1e3, 1e6, 1000)
    step = 2e4
    free = np.zeros((2, p0.size), dtype=bool)
    free[0] = np.abs(np.log(p0 / step)) < 0.15  # (the junction's loads of the first level)

    def outputs(p: np.ndarray) -> dict[str, np.ndarray]:
        x = np.log(p)
        m = np.exp(0.2 * x + 0.3 * np.tanh((x - np.log(step)) / 0.05))
        return {"j": np.exp(-0.3 * x + 0.05 * np.sin(x)), "k": np.zeros(p.size), "m": m}

    res, repeated = {}, {}
    for report in (False, True):
        seen: list[np.ndarray] = []

        def exact(rows: np.ndarray, which: np.ndarray, report: bool = report, seen=seen) -> dict:  # noqa: ANN001
            seen.append(rows)
            out = outputs(p0[rows])
            if report:
                out[COMPUTED] = np.ones((rows.size, 2), dtype=bool)
            return out

        res[report] = by_group(p0, exact, 2e-3, frozenset({"k"}), 1e-4, 0, (8,), 4.0 * 2**8,
                               16, (), free, GROUPS)  # fmt: skip
        rows = np.concatenate(seen)
        repeated[report] = rows.size - np.unique(rows).size
    assert repeated[False] > 20 and repeated[True] == 0
    for k in res[False][0]:
        np.testing.assert_array_equal(res[True][0][k], res[False][0][k], err_msg=k)
    np.testing.assert_array_equal(res[True][1], res[False][1])


def test_the_leak_table_keeps_the_medium_computed_for_the_junction_loads():
    """A roll-off scene at 1000 loads (held-out design seed 2026's roll-off H = 0.67, 5
    decades): the effective medium's second-level loads were computed in the first call
    (for the junction; the medium for every load of the call) and are taken from there, so
    no load is computed twice (without: 8 are, in a second call of their own), and every
    leak output equals the one computed again to round-off (1e-13; the junction's bit for
    bit)."""
    import xpersson
    from xpersson_interface import _by_load

    sc = {
        "spectrum": {"model": "self_affine", "H": 0.674, "q_L": "262.32 1/m",
                     "q_r": "1945.25 1/m", "q_1": "2.6232e7 1/m", "h_rms": "1 um"},
        "material": {"E": "10 MPa", "nu": 0.5},
        "load": {"p0": {"start": "1 kPa", "stop": "1 MPa", "num": 1000}},
        "output": {"zeta": np.geomspace(1.0, 1e3, 50).tolist()},
        "analyses": {"leakage": {}},
    }  # fmt: skip
    run, seen = _by_load._Direct.run, []

    def recording(direct) -> None:  # noqa: ANN001 - each direct call's rows
        exact = direct.exact
        direct.exact = lambda rows, which: seen.append(rows) or exact(rows, which)
        try:
            run(direct)
        finally:
            direct.exact = exact

    got, repeated = {}, {}
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(_by_load._Direct, "run", recording)
        for serve in (True, False):
            if not serve:
                mp.setattr(_by_load._Direct, "_serve", lambda self, ask: ask)
            seen.clear()
            got[serve] = xpersson.solve(sc)
            rows = np.concatenate(seen)
            repeated[serve] = rows.size - np.unique(rows).size
    assert repeated[True] == 0 and repeated[False] > 0
    for k in ("leak_zeta_c", "leak_u1", "leak_flow_factor", "leak_rate", "leak_sealed"):
        np.testing.assert_array_equal(got[True][k].values, got[False][k].values, err_msg=k)
    for k in ("leak_flow_factor_emt", "leak_rate_emt", "leak_sealed_emt", "leak_load_error"):
        np.testing.assert_allclose(got[True][k].values, got[False][k].values, rtol=1e-13,
                                   atol=0, err_msg=k)  # fmt: skip
