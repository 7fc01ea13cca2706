"""Synthesised maps carry the spectrum's moments (Persson's normalisation, (2 pi)^2 included)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from xpersson import bem
from xpersson.physics import SelfAffineRollOff

L = 1e-4
Q_L = 2 * math.pi / L


def _psd(ratio: float = 16.0, roll: float = 1.0) -> SelfAffineRollOff:
    return SelfAffineRollOff.from_rms_slope(
        0.1, H=0.8, q_L=Q_L, q_r=roll * Q_L, q_1=ratio * roll * Q_L
    )


def test_ensemble_moments_equal_lattice_sums() -> None:
    """Mean power of many maps = the lattice sums of C (2 pi / L)^2 (4 % at 64 maps)."""
    psd = _psd()
    h = bem.synthesise(psd.C, L, 64, seed=3, realisations=64, q_max=16 * Q_L)
    h_rms, slope = bem.map_moments(h, L)
    h_ref, s_ref = bem.discrete_moments(psd.C, L, 64, q_max=16 * Q_L)
    assert h_rms == pytest.approx(h_ref, rel=0.08)
    assert slope == pytest.approx(s_ref, rel=0.02)


def test_slope_matches_continuum_spectrum() -> None:
    """The rms slope (many modes) of the lattice equals 2 pi int q^3 C dq within 5 %; with a
    roll-off plateau the rms height does too."""
    psd = _psd(ratio=8.0, roll=4.0)
    _, s_lat = bem.discrete_moments(psd.C, L, 128, q_max=32 * Q_L)
    h_lat, _ = bem.discrete_moments(psd.C, L, 128, q_max=32 * Q_L)
    h_c, s_c = bem.spectrum_moments(psd.C, Q_L, 32 * Q_L)
    assert s_lat == pytest.approx(s_c, rel=0.05)
    assert h_lat == pytest.approx(h_c, rel=0.1)
    assert s_c == pytest.approx(0.1, rel=1e-3)


def test_seeded_and_realisation_stable() -> None:
    """Realisation i does not depend on how many are drawn; the maps are real, zero-mean."""
    psd = _psd()
    a = bem.synthesise(psd.C, L, 32, seed=7, realisations=3)
    b = bem.synthesise(psd.C, L, 32, seed=7, realisations=1)
    np.testing.assert_array_equal(a[0], b[0])
    assert not np.array_equal(a[0], a[1])
    assert abs(a.mean()) < 1e-6 * a.std()


def test_bad_grid_named() -> None:
    with pytest.raises(ValueError, match=r"n \[1\]"):
        bem.synthesise(_psd().C, L, 33)
