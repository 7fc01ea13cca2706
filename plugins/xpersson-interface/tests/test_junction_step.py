"""``u1``'s difference quotient near ``zeta = 1`` (``SolvedContact.separation_at``): its step at
most ``STEP_SHARE`` of ``ln zeta_c``, so the junction is the converged derivative there and
smooth in the load, and the load table interpolates it (``benchmarks/leakage_junction_step.py``).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import xpersson
from xpersson.physics import _solved_contact as solved_mod
from xpersson_interface._leakage import junction_piece

#: A steep spectrum without roll-off (held-out flat H = 0.87 4dec of ``benchmarks/summary.py
#: --held-out 4242``): at 1-4 kPa the area falls from 1 to ``a_c`` within ``ln zeta < 1e-2``.
STEEP = {"model": "self_affine", "H": 0.8657, "q_L": "8618.6 1/m", "q_r": "8618.6 1/m",
         "q_1": "8.6186e7 1/m", "h_rms": "1 um"}  # fmt: skip


def _scene(loads: object) -> dict:
    return {
        "spectrum": STEEP,
        "material": {"E": "10 MPa", "nu": 0.5},
        "load": {"p0": loads},
        "output": {"zeta": [float(z) for z in np.geomspace(1.0, 1e3, 50)]},
        "analyses": {"leakage": {}},
    }


@pytest.fixture(scope="module")
def contact():
    """The leak analysis's own solved contact (dense re-solve) at 24 loads, 10 Pa - 40 kPa, and
    the ``zeta_c`` it asked ``u1`` at (``ln zeta_c`` from ~ 6e-8 to ~ 0.4)."""
    got = []
    orig = solved_mod.SolvedContact.separation_at

    def rec(self, za, **kw):  # noqa: ANN001, ANN003, ANN202
        got.append((self, np.array(za, dtype=float)))
        return orig(self, za, **kw)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(solved_mod.SolvedContact, "separation_at", rec)
        xpersson.solve(_scene([f"{float(p)!r} Pa" for p in np.geomspace(10.0, 4e4, 24)]))
    return got[0]


def test_u1_is_the_converged_derivative_near_zeta_1(contact):
    """At every load, on both sides of ``ln zeta_c = 1e-3 / STEP_SHARE`` (where the step stops
    shrinking) and down to ``ln zeta_c`` ~ 6e-8: ``u1`` within 1e-4 of the quotient at a step
    ten times smaller (the fixed step of 1e-3 was 9-11 % off below ``ln zeta_c = 1e-3``)."""
    sc, zc = contact
    lz = np.log(zc)
    assert lz.min() < 1e-7 and lz.max() > 1e-3 / solved_mod.STEP_SHARE
    u = sc.separation_at(zc)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(solved_mod, "STEP_SHARE", solved_mod.STEP_SHARE / 10)
        fine = sc.separation_at(zc, rel_step=1e-4)
    np.testing.assert_allclose(u, fine, rtol=1e-4)


def test_u1_is_continuous_where_its_step_stops_shrinking_and_smooth_towards_zeta_1(contact):
    """``u1`` of the load whose ``zeta_c`` lies nearest ``ln zeta = 1e-3 / STEP_SHARE`` (where
    the step stops shrinking), at ``zeta`` just below and just above it: equal to 1e-7; and
    ``ln u1`` over the loads (geometric in ``p0``) smooth down to ``zeta_c -> 1``: its second
    differences negative and growing in size with the load where ``ln zeta_c < 0.05`` (with
    the fixed step the secant's error fell 11 % -> 1 % over three loads there)."""
    sc, zc = contact
    edge = 1e-3 / solved_mod.STEP_SHARE
    i = int(np.argmin(np.abs(np.log(zc) - edge)))
    at = np.full(zc.size, np.nan)
    at[i] = math.exp(edge * (1.0 - 1e-9))
    below = sc.separation_at(at)[i]
    at[i] = math.exp(edge * (1.0 + 1e-9))
    assert np.isfinite(below) and sc.separation_at(at)[i] == pytest.approx(below, rel=1e-7)
    low = np.log(zc) < 0.05
    d2 = np.diff(np.log(sc.separation_at(zc))[low], 2)
    assert low.sum() > 8 and np.all(d2 < 0.0) and np.all(np.diff(d2) < 0.0)


class _Nodes:
    """A spectrum's breakpoints (``q_L``, a roll-off at 10 q_L, ``q_1``) for ``junction_piece``."""

    q_L = 1e3

    @staticmethod
    def nodes() -> np.ndarray:
        return np.array([1e3, 1e4, 1e7])


def test_junction_piece_never_reaches_q_L():
    """A load's junction piece (the breakpoints its quotient's window reaches) is the same for
    every ``zeta_c`` just above 1 as at 1.5: ``q_L`` is no breakpoint of the junction; the
    roll-off still is."""
    zc = np.array([1.0 + 1e-9, 1.0 + 1e-6, math.exp(1e-3), math.exp(2.5e-3), 1.5])
    piece = junction_piece(_Nodes, zc, 1e4, np.ones(zc.size))
    assert np.all(piece == piece[-1])
    near = junction_piece(_Nodes, np.array([10.0, 10.0 * math.exp(3e-3)]), 1e4, np.ones(2))
    assert near[0] != near[1] and near[1] == junction_piece(_Nodes, np.array([13.0]), 1e4, [1])


def test_the_table_interpolates_the_junction_near_zeta_1_within_its_estimate():
    """1000 loads, 1 kPa - 1 MPa: the loads whose ``zeta_c`` lies within 0.2 % of 1 (1-2 kPa;
    before, each a piece of its own, all computed directly) are interpolated, and every
    interpolated load lies within its stated error of the direct path."""
    from xpersson_interface import _by_load as by_load_mod

    sc = _scene({"start": "1000.0 Pa", "stop": "1000000.0 Pa", "num": 1000})
    table = xpersson.solve(sc)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(by_load_mod, "TABLE_MIN", 10**9)
        direct = xpersson.solve(sc)
    err = table["leak_load_error"].values
    low = np.log(direct["leak_zeta_c"].values) < 2e-3
    assert low.sum() > 50 and np.mean(err[low] > 0) > 0.8
    for k in ("leak_u1", "leak_flow_factor", "leak_rate", "leak_flow_factor_emt"):
        got, want = table[k].values, direct[k].values
        ok = np.isfinite(want) & (np.abs(want) > 0)
        rel = np.abs(got[ok] / want[ok] - 1.0)
        assert np.all(rel <= np.where(err[ok] > 0, err[ok], 1e-10)), k
