"""Known cases and identities of the BEM layer (tamaas): Westergaard, Barber, adhesion."""

from __future__ import annotations

import math

import numpy as np
import pytest

from xpersson import bem
from xpersson.physics import SelfAffineRollOff

pytest.importorskip("tamaas")


@pytest.mark.parametrize("ratio", [0.1, 0.4, 0.8])
def test_westergaard_wavy_surface(ratio: float) -> None:
    """A cos(2 pi x / lambda) surface: p0/p* = sin^2(pi a / lambda), p* = pi E* D / lambda,
    contact width 2a (Johnson 1985, 13.2); within one pixel on each contact edge."""
    n, L, D, E = 128, 1.0, 1e-3, 1.0
    x = np.arange(n) * L / n
    h = np.tile((D * np.cos(2 * np.pi * x / L))[:, None], (1, n))
    p_star = math.pi * E * D / L
    (s,) = bem.solve(h, L, E, [ratio * p_star])
    exact = 2 / math.pi * math.asin(math.sqrt(ratio))
    assert s.area_fraction == pytest.approx(exact, abs=2.0 / n)


@pytest.fixture(scope="module")
def rough() -> np.ndarray:
    q_L = 2 * math.pi
    psd = SelfAffineRollOff.from_h_rms(1e-3, H=0.8, q_L=q_L, q_r=4 * q_L, q_1=8 * q_L)
    return bem.synthesise(psd.C, 1.0, 64, seed=1, q_max=8 * q_L)[0]


@pytest.mark.parametrize("p0", [4e-4, 3e-3])
def test_barber_direct_conduction_equals_stiffness(rough: np.ndarray, p0: float) -> None:
    """The conduction problem solved on the BEM contact set equals c K from the BEM's own
    loading curve (Barber's analogy) to 3 % on a 64^2 grid."""
    f = math.exp(0.05)
    lo, mid, hi = bem.solve(rough, 1.0, 1.0, [p0 / f, p0, p0 * f], keep_fields=True)
    K = bem.stiffness(lo.p0, hi.p0, lo.mean_gap, hi.mean_gap)
    c = bem.electrical_factor(1.7e-8, 1.7e-8, 1.0)
    g = bem.conductance_direct(mid.contact, 1.0, 3.4e-8)
    assert g == pytest.approx(c * K, rel=0.03)
    assert bem.thermal_factor(400.0, 400.0, 2.0) == pytest.approx(200.0)


def test_gap_pdf_and_contact_weight_sum_to_one(rough: np.ndarray) -> None:
    (s,) = bem.solve(rough, 1.0, 1.0, [1e-3], keep_fields=True)
    edges = np.linspace(0.0, 1.01 * s.gap.max(), 41)
    pdf = bem.gap_pdf(s.gap, s.contact, edges)
    assert np.sum(pdf * np.diff(edges)) + s.area_fraction == pytest.approx(1.0)
    assert np.sum(pdf * np.diff(edges) * 0.5 * (edges[1:] + edges[:-1])) == pytest.approx(
        s.mean_gap, rel=0.05
    )


def test_adhesion_pulls_off_and_adds_area(rough: np.ndarray) -> None:
    """Adhesive retraction holds tension (pull-off > 0) and more area than the non-adhesive
    solve at the same compressive load; a non-converged state would be NaN, not a value."""
    h = rough[::4, ::4].copy()
    h_rms = float(h.std())
    work, rho = 2e-3 * h_rms, 0.1 * h_rms
    path = bem.adhesive_path(h, 1.0, 1.0, work, rho, strict=False)
    assert all(s.converged for s in path["approach"])
    p_ref = path["approach"][-1].p0
    area, pull = bem.retraction_branch(path["retract"], np.array([0.5 * p_ref, -1e-12]))
    (el,) = bem.solve(h, 1.0, 1.0, [0.5 * p_ref])
    assert pull > 0
    assert area[0] > el.area_fraction
    assert area[1] > 0
