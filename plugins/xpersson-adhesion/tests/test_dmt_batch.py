"""``dmt``'s batched solve (:mod:`xpersson_adhesion._dmt_batch`): the same ``p_rep`` as the
per-load reference (Brent's method on the engine's map, :func:`~xpersson_adhesion.dmt.solve_dmt`)
to the requested tolerance, and a load's result independent of the loads solved with it."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from adhesion_testlib import PSD, with_

import xpersson
from xpersson.physics import diffusion_time
from xpersson.testing import material, scene
from xpersson_adhesion import LAWS, AdhesionLimitWarning
from xpersson_adhesion._dmt_batch import NMAX, _cheb_coefficients, key, node_p
from xpersson_adhesion._dmt_reference import solve_dmt

E_STAR = 4.0e6 / 3.0  # material("1 MPa"), nu = 0.5
LOADS = ["-150 Pa", "2 kPa", "7 kPa", "20 kPa", "300 kPa"]
BASE = scene(material=material("1 MPa"), p0=LOADS, zeta_per_decade=4)
RTOL = 1e-7


def _dmt(law: str) -> dict:
    return {"model": "dmt", "work_of_adhesion": "0.005 J/m**2", "range": "2 nm", "law": law}


def _solve(data: dict):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AdhesionLimitWarning)
        return xpersson.solve(data)


@pytest.mark.parametrize("law", LAWS)
def test_batch_equals_the_per_load_brent_reference(law):
    ds = _solve(with_(BASE, boundary=_dmt(law), solver={"rtol": RTOL}))
    zeta = ds["zeta"].values
    for i, p0 in enumerate(ds["p0"].values):
        ref = solve_dmt(
            PSD,
            E_STAR,
            float(p0),
            lambda z: diffusion_time(PSD, E_STAR, z),
            zeta,
            law,
            0.005,
            2e-9,
            rtol=1e-10,
        )
        # both to RTOL of the same root (the reference to 1e-10)
        assert abs(ds["p_rep"].values[i] / ref.p_rep - 1.0) <= 2 * RTOL
        assert abs(ds["mean_gap"].values[i] / ref.mean_gap - 1.0) <= 1e-5
        assert ds["dmt_residual"].values[i] <= RTOL
        np.testing.assert_allclose(
            ds["p_att_discretization_error"].values[i], ref.discretization_error, rtol=1e-3
        )


def test_a_load_alone_equals_the_same_load_in_a_batch():
    together = _solve(with_(BASE, boundary=_dmt("lj93"), solver={"rtol": RTOL}))
    subset = _solve(
        with_(BASE, boundary=_dmt("lj93"), solver={"rtol": RTOL}, load={"p0": LOADS[1::2]})
    )
    for name in ("p_rep", "dmt_iterations", "mean_gap"):
        np.testing.assert_allclose(subset[name].values, together[name].values[1::2], rtol=1e-12)
    for i, p0 in enumerate(LOADS):
        alone = _solve(with_(BASE, boundary=_dmt("lj93"), solver={"rtol": RTOL}, load={"p0": p0}))
        for name in ("p_rep", "dmt_iterations", "p_att_discretization_error"):
            # the same exact samples of p_att, whatever else is solved: equal to rounding
            np.testing.assert_allclose(alone[name].values, together[name].values[i], rtol=1e-12)


def test_beyond_pull_off_is_a_clear_error():
    with pytest.raises(ValueError, match=r"load.p0 = -1e\+06 Pa.*pull-off"):
        _solve(with_(BASE, boundary=_dmt("exponential"), load={"p0": ["-1 MPa", "1 kPa"]}))


def test_chebyshev_coefficients_and_nodes():
    n = 8
    t = np.cos(np.pi * np.arange(n + 1) / n)
    values = 4 * t**3 - 3 * t + 0.5  # T_3 + T_0 / 2
    np.testing.assert_allclose(
        _cheb_coefficients(values), [0.5, 0, 0, 1, 0, 0, 0, 0, 0], atol=1e-14
    )
    # nested nodes: the octave's ends are exact powers of two shared with the neighbours
    assert node_p(5, NMAX) == 32.0 and node_p(5, 0) == 64.0 and key(5, 0) == (6, NMAX)
    assert np.isclose(node_p(5, NMAX // 2), 32.0 * np.sqrt(2.0), rtol=1e-15)


def test_unconverged_octaves_fall_back_to_brent_on_the_exact_map(monkeypatch):
    from xpersson_adhesion._dmt_batch import AttractionMap

    fast = _solve(with_(BASE, boundary=_dmt("lj93"), solver={"rtol": RTOL}))
    monkeypatch.setattr(AttractionMap, "_converged", lambda self, k, n: False)
    slow = _solve(with_(BASE, boundary=_dmt("lj93"), solver={"rtol": RTOL}))
    np.testing.assert_allclose(slow["p_rep"].values, fast["p_rep"].values, rtol=2 * RTOL)
    assert np.all(slow["dmt_residual"].values <= RTOL)
    # Brent's evaluations on top of the scan and the (unconverged) degree-64 nodes
    assert np.all(slow["dmt_iterations"].values > fast["dmt_iterations"].values)


def test_tensile_loads_just_inside_pull_off_are_solved_just_outside_refused():
    """Near pull-off ``h(p) = p - p_att(p)`` dips below ``p0`` only between two powers of two
    (the scan's nodes): such a load has a root and must be solved, not refused. The pull-off
    stress ``-min h`` is taken from a dense independent sampling of the exact map."""
    from xpersson_adhesion._curves import curve_grid, increasing
    from xpersson_adhesion._dmt_batch import AttractionMap

    zeta = _solve(with_(BASE, boundary=_dmt("exponential")))["zeta"].values
    curves = tuple(
        increasing(z, diffusion_time(PSD, E_STAR, z))
        for z in (curve_grid(zeta), curve_grid(zeta, per_decade=16))
    )
    amap = AttractionMap(PSD, E_STAR, curves, "exponential", 0.005, 2e-9, 1e-8)
    p = np.geomspace(1e2, 1e7, 801)
    h = p - amap.exact(p)[0]
    i = int(np.argmin(h))
    fine = np.geomspace(p[max(i - 1, 0)], p[min(i + 1, p.size - 1)], 401)
    pull_off = -float(np.min(fine - amap.exact(fine)[0]))
    assert pull_off > 0
    inside = -0.995 * pull_off
    ds = _solve(with_(BASE, boundary=_dmt("exponential"), load={"p0": f"{inside} Pa"}))
    p_rep = float(ds["p_rep"].values)
    assert abs(p_rep - float(amap.exact(np.array([p_rep]))[0][0]) - inside) <= 1e-6 * p_rep
    with pytest.raises(ValueError, match="pull-off"):
        _solve(with_(BASE, boundary=_dmt("exponential"), load={"p0": f"{-1.005 * pull_off} Pa"}))
