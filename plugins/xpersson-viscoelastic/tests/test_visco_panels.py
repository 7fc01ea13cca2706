"""Narrow q panels at fewer Gauss nodes (_panels): the running integrals of a dense grid stay
at round-off of the full rule, wide panels and non-Prony models keep the full rule."""

from __future__ import annotations

import numpy as np
import pytest

from xpersson.physics import SelfAffineRollOff
from xpersson_viscoelastic import _panels, kernel, sls, synthetic_tread
from xpersson_viscoelastic._modulus import MasterCurve

PSD = SelfAffineRollOff.from_h_rms(6e-5, 0.8, 600.0, 3000.0, 1e7)
#: a friction-analysis-like dense grid (geometric in zeta - 1 from 1e-7) and an output grid
DENSE = np.unique(np.concatenate([1 + np.geomspace(1e-7, 300, 240), np.geomspace(1, 1e4, 81)]))


def _both(model, zeta, scale, which, monkeypatch):
    got = kernel._cumulative_at(PSD, model, zeta, scale, 1.0, which, 8, 4)
    monkeypatch.setattr(_panels, "NODE_LADDER", ())
    full = kernel._cumulative_at(PSD, model, zeta, scale, 1.0, which, 8, 4)
    monkeypatch.undo()
    return got, full


@pytest.mark.parametrize("model", [synthetic_tread(), sls(3e6, 3e9, 1e-3)])
@pytest.mark.parametrize("scale", [1e-8, 1e-3, 10.0, 1e5])
@pytest.mark.parametrize("which", ["tau", "loss"])
def test_reduced_rule_is_the_full_rule_to_round_off(model, scale, which, monkeypatch):
    got, full = _both(model, DENSE, scale, which, monkeypatch)
    np.testing.assert_allclose(got, full, rtol=2e-14, atol=0)
    assert not np.array_equal(got, full)  # the reduced rule was used


def test_master_curves_and_flash_keep_the_full_rule(monkeypatch):
    w = np.geomspace(1e-2, 1e8, 30)
    E = sls(3e6, 3e9, 1e-3).modulus(w)
    got, full = _both(MasterCurve(w, E.real, E.imag), DENSE, 1e-2, "loss", monkeypatch)
    np.testing.assert_array_equal(got, full)
    assert not _panels.reduced_ok(synthetic_tread(), lambda q: q)  # flash a_T(q)


def test_node_counts_follow_the_ladder():
    half = np.array([1e-5, 2.2e-4, 3e-4, 0.02, 0.05, 0.09, 0.15, 0.2, 1.0])
    np.testing.assert_array_equal(_panels.node_counts(half, 8), [2, 2, 3, 4, 5, 6, 7, 8, 8])
    np.testing.assert_array_equal(_panels.node_counts(half, 4), [2, 2, 3, 4, 4, 4, 4, 4, 4])
    assert (_panels.node_counts(half, 8, reduced=False) == 8).all()
    # each rung at (h / 2.2)^(2 m) <= 1e-16
    for h, m in _panels.NODE_LADDER:
        assert (h / 2.2) ** (2 * m) <= 1e-16
