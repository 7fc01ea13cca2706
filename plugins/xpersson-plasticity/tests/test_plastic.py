"""The ``plastic`` boundary: registration, bad input, walls, interpretation, engine identities."""

from __future__ import annotations

import pickle
import warnings
from importlib.metadata import entry_points
from types import SimpleNamespace

import numpy as np
import pytest
from plasticity_testlib import SIGMA_Y, make_clock, make_ctx

from xpersson_plasticity import ApproximationValidityWarning, PlasticBoundary
from xpersson_plasticity._series import two_wall_areas

DECLARED = {
    "elastic_area_fraction",
    "plastic_area_fraction",
    "non_contact_area_fraction",
    "total_contact_fraction",
    "elastic_load_share",
    "plastic_load_share",
}


def test_entry_point_registered():
    eps = {ep.name: ep.value for ep in entry_points(group="xpersson.boundaries")}
    assert eps["plastic"] == "xpersson_plasticity.plastic:PlasticBoundary"
    assert eps["plastic_scale_dependent"].endswith(":ScaleDependentPlasticBoundary")


def test_metadata():
    spec = PlasticBoundary.parameters["sigma_Y"]
    assert spec.unit == "Pa" and spec.required and not spec.in_bounds(0.0)
    assert PlasticBoundary.parameters["approximation"].default == "none"
    assert DECLARED <= set(PlasticBoundary.outputs)
    for name in DECLARED:
        v = PlasticBoundary.outputs[name]
        assert v.dims == ("p0", "zeta") and v.units == "1" and v.long_name
    assert PlasticBoundary.outputs["yield_stress"].units == "Pa"


def test_pickle_and_equality():
    b = PlasticBoundary(sigma_Y=SIGMA_Y)
    assert pickle.loads(pickle.dumps(b)) == b


@pytest.mark.parametrize("p0", [SIGMA_Y, 2 * SIGMA_Y, [1e6, 1.5 * SIGMA_Y]])
def test_validate_refuses_fully_plastic_start(p0):
    b = PlasticBoundary(sigma_Y=SIGMA_Y)
    with pytest.raises(ValueError, match=r"boundary\.sigma_Y") as exc:
        b.validate(make_ctx(p0))
    msg = str(exc.value)
    assert "Pa" in msg and "sigma_Y >" in msg and f"{np.max(p0):g}" in msg


@pytest.mark.parametrize("bad", [0.0, -1e9, float("nan"), "3 GPa"])
def test_constructor_refuses_bad_sigma_Y(bad):
    with pytest.raises(ValueError, match=r"boundary\.sigma_Y.*Pa"):
        PlasticBoundary(sigma_Y=bad)


def test_bad_approximation_named():
    with pytest.raises(ValueError, match=r"boundary\.approximation.*three_gaussian"):
        PlasticBoundary(sigma_Y=SIGMA_Y, approximation="five_gaussian")


def test_walls(engine):
    b = PlasticBoundary(sigma_Y=SIGMA_Y)
    lo, up = b.walls(make_ctx(3e8), 3e8, make_clock(SIGMA_Y**2))
    assert lo.kind == "absorbing" and lo.is_fixed and float(lo.position) == 0.0
    assert up.kind == "absorbing" and up.is_fixed and float(up.position) == SIGMA_Y


def _fake_results(ctx, clock, y):
    """Engine-like results from the exact series (independent of the engine)."""
    out = []
    for p0 in ctx.p0:
        tau = clock.tau_of_zeta(ctx.zeta)
        r = two_wall_areas(tau, p0, y)
        out.append(
            SimpleNamespace(
                tau=tau,
                area=r.elastic,
                absorbed_upper=r.plastic,
                absorbed_lower=r.non_contact,
                load=r.load,
            )
        )
    return out


def test_interpret_identities_on_exact_input():
    ctx = make_ctx([1e7, 3e8, 9e8])
    clock = make_clock(3 * SIGMA_Y**2)
    b = PlasticBoundary(sigma_Y=SIGMA_Y)
    out = b.interpret(ctx, _fake_results(ctx, clock, SIGMA_Y))
    assert set(out) <= set(b.outputs) and DECLARED <= set(out)
    for name, (dims, data) in out.items():
        assert dims == b.outputs[name].dims
        assert np.all(np.isfinite(data))
        assert data.shape == tuple({"p0": 3, "zeta": ctx.zeta.size}[d] for d in dims)
    el = out["elastic_area_fraction"][1]
    pl = out["plastic_area_fraction"][1]
    non = out["non_contact_area_fraction"][1]
    np.testing.assert_allclose(el + pl + non, 1.0, atol=1e-14)
    np.testing.assert_allclose(out["total_contact_fraction"][1], el + pl, atol=0)
    shares = out["elastic_load_share"][1] + out["plastic_load_share"][1]
    np.testing.assert_allclose(shares, 1.0, atol=1e-14)
    assert np.max(np.abs(out["exact_series_deviation"][1])) < 1e-13
    # the hardness carries p0 / sigma_Y of the area at the largest magnification
    np.testing.assert_allclose(pl[:, -1], ctx.p0 / SIGMA_Y, rtol=1e-6)


def test_three_gaussian_flags_invalid_range():
    b = PlasticBoundary(sigma_Y=SIGMA_Y, approximation="three_gaussian")
    ctx = make_ctx([3e8])
    # small tau: valid, no warning, equal to exact
    clock = make_clock(1e-3 * SIGMA_Y**2)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        out = b.interpret(ctx, _fake_results(ctx, clock, SIGMA_Y))
    assert np.max(out["exact_series_deviation"][1]) < 1e-12
    # tau up to sigma_Y^2: P(0) = 0 violated, flagged and quantified
    clock = make_clock(SIGMA_Y**2)
    with pytest.warns(ApproximationValidityWarning, match=r"sqrt\(2 tau\) << sigma_Y"):
        out = b.interpret(ctx, _fake_results(ctx, clock, SIGMA_Y))
    assert np.max(out["exact_series_deviation"][1]) > 0.1


@pytest.mark.parametrize("method", ["auto", "sine"])
def test_engine_identities(engine, method):
    """Through the engine: int P + A_pl + A_non = 1 and int pP + sigma_Y A_pl = p0."""
    ctx = make_ctx([1e7, 3e8, 9e8], zeta_max=1e4, n_zeta=41)
    clock = make_clock(5 * SIGMA_Y**2, zeta_max=1e4)
    b = PlasticBoundary(sigma_Y=SIGMA_Y)
    b.validate(ctx)
    tau = clock.tau_of_zeta(ctx.zeta)
    results = []
    for p0 in ctx.p0:
        lo, up = b.walls(ctx, p0, clock)
        res = engine.solve(tau, p0, lo, up, rtol=1e-8, method=method)
        assert res.success, res.message
        results.append(res)
    out = b.interpret(ctx, results)
    el, pl = out["elastic_area_fraction"][1], out["plastic_area_fraction"][1]
    non = out["non_contact_area_fraction"][1]
    tol = 10 * 1e-8
    assert np.max(np.abs(el + pl + non - 1)) < tol
    assert np.max(np.abs(out["plastic_force_balance_residual"][1])) < tol
    assert np.max(out["exact_series_deviation"][1]) < tol
    np.testing.assert_allclose(pl[:, -1], ctx.p0 / SIGMA_Y, atol=tol)
