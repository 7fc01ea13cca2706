"""BEM sanity identities on small grids (tamaas)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from xpersson import bem
from xpersson.physics import SelfAffineRollOff

pytest.importorskip("tamaas")

L = 1e-4
Q_L = 2 * math.pi / L
E_STAR = 1e6


@pytest.fixture(scope="module")
def surface() -> np.ndarray:
    psd = SelfAffineRollOff.from_rms_slope(0.1, H=0.8, q_L=Q_L, q_r=Q_L, q_1=8 * Q_L)
    return bem.synthesise(psd.C, L, 64, seed=1, q_max=8 * Q_L)[0]


def test_area_grows_and_gap_falls_with_load(surface: np.ndarray) -> None:
    states = bem.solve(surface, L, E_STAR, [1e3, 3e3, 1e4])
    area = [s.area_fraction for s in states]
    gap = [s.mean_gap for s in states]
    assert all(s.converged for s in states)
    assert area[0] < area[1] < area[2] < 1
    assert gap[0] > gap[1] > gap[2] > 0
    for s in states:
        assert s.p0 == pytest.approx(s.pressure_mean, rel=1e-12)
        assert np.sum(s.gap_density * np.diff(s.gap_edges)) == pytest.approx(1.0)


def test_small_area_pressure_identity(surface: np.ndarray) -> None:
    """Mean contact pressure times the area = the nominal pressure."""
    (s,) = bem.solve(surface, L, E_STAR, [2e3])
    assert s.pressure_contact_mean * s.area_fraction == pytest.approx(2e3, rel=1e-9)


def test_plastic_caps_pressure(surface: np.ndarray) -> None:
    (el,) = bem.solve(surface, L, E_STAR, [5e3])
    (pl,) = bem.solve(surface, L, E_STAR, [5e3], hardness=2e4)
    assert pl.pressure_max <= 2e4 * (1 + 1e-9) < el.pressure_max
    assert pl.area_fraction > el.area_fraction
    assert 0 < pl.plastic_area_fraction <= pl.area_fraction


def test_not_converged_is_an_error_or_nan(surface: np.ndarray) -> None:
    with pytest.raises(bem.BemConvergenceError, match="did not converge"):
        bem.solve(surface, L, E_STAR, [2e3], max_iter=2)
    (s,) = bem.solve(surface, L, E_STAR, [2e3], max_iter=2, strict=False)
    assert not s.converged and math.isnan(s.area_fraction) and math.isnan(s.mean_gap)
