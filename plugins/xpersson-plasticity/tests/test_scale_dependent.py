"""The ``plastic_scale_dependent`` boundary: hardness laws, bad input, moving-wall identities."""

from __future__ import annotations

import pickle

import numpy as np
import pytest
from plasticity_testlib import SIGMA_Y, make_clock, make_ctx

from xpersson_plasticity import PlasticBoundary, ScaleDependentPlasticBoundary
from xpersson_plasticity._series import two_wall_areas
from xpersson_plasticity.scale_dependent import YieldWallLaw

SD = ScaleDependentPlasticBoundary


def test_outputs_match_plastic():
    assert set(SD.outputs) <= set(PlasticBoundary.outputs)
    assert SD.parameters["Y1"].unit == "Pa" and SD.parameters["n"].unit == "1"
    assert not SD.parameters["n"].in_bounds(-0.1)


def test_power_law_and_pickle():
    b = SD(Y1=2e9, n=0.25)
    z = np.array([1.0, 16.0, 1e4])
    np.testing.assert_allclose(b.law.Y(z), 2e9 * z**0.25, rtol=1e-15)
    np.testing.assert_allclose(b.law.dY(z), 0.25 * 2e9 * z**-0.75, rtol=1e-15)
    assert pickle.loads(pickle.dumps(b)) == b
    assert SD(Y1=2e9).law.is_constant and not b.law.is_constant


def test_wall_law_is_chain_rule():
    """dY/dtau = Y'(zeta) / f(zeta), checked against a centred difference of Y(zeta(tau))."""
    clock = make_clock(2 * SIGMA_Y**2)
    b = SD(Y1=SIGMA_Y, n=0.3)
    pos = YieldWallLaw(b.law, clock, derivative=False)
    vel = YieldWallLaw(b.law, clock, derivative=True)
    tau = clock.tau_of_zeta(np.array([3.0, 30.0, 300.0]))
    h = 1e-5 * tau
    fd = (pos(tau + h) - pos(tau - h)) / (2 * h)
    np.testing.assert_allclose(vel(tau), fd, rtol=1e-6)
    assert isinstance(pos(float(tau[0])), float)
    np.testing.assert_allclose(pos(0.0), SIGMA_Y, rtol=1e-12)


@pytest.mark.parametrize(
    ("params", "p0", "name"),
    [
        ({"Y1": 1e8, "n": 0.2}, 1e8, "Y1"),
        ({"Y1": 1e8, "n": 0.2}, [1e6, 2e8], "Y1"),
    ],
)
def test_validate_refuses_yield_at_start(params, p0, name):
    with pytest.raises(ValueError, match=rf"boundary\.{name}") as exc:
        SD(**params).validate(make_ctx(p0))
    assert "Pa" in str(exc.value) and f"{name} >" in str(exc.value)


@pytest.mark.parametrize(
    ("params", "match"),
    [
        ({"Y1": 1e9, "n": -0.1}, r"boundary\.n .*dimensionless.*\[0, inf\].*decreasing"),
        ({"Y1": -1e9, "n": 0.1}, r"boundary\.Y1 .*Pa"),
        ({"Y1": float("nan")}, r"boundary\.Y1"),
        ({"n": 0.1}, r"boundary\.Y1 \[Pa\] is required"),
        ({"Y1": 1e9, "table": "x.txt"}, r"either Y1"),
    ],
)
def test_bad_parameters_named(params, match):
    with pytest.raises(ValueError, match=match):
        SD(**params)


def _write(tmp_path, text):
    path = tmp_path / "hardness.txt"
    path.write_text(text)
    return str(path)


def test_table_law(tmp_path):
    z = np.geomspace(1, 1e4, 9)
    rows = "\n".join(f"{a:.17g}, {2.0 * a**0.2:.17g}" for a in z)
    b = SD(table=_write(tmp_path, "# zeta, Y [GPa]\n" + rows), table_unit="GPa")
    zz = np.geomspace(1, 1e4, 50)
    # a power law is reproduced exactly by PCHIP in log-log
    np.testing.assert_allclose(b.law.Y(zz), 2e9 * zz**0.2, rtol=1e-12)
    np.testing.assert_allclose(b.law.dY(zz), 0.2 * 2e9 * zz**-0.8, rtol=1e-10)
    b.validate(make_ctx(1e9, zeta_max=1e4))
    with pytest.raises(ValueError, match=r"boundary\.table covers zeta in \[1, 10000\]"):
        b.validate(make_ctx(1e9, zeta_max=1e5))
    with pytest.raises(ValueError, match=r"boundary\.table"):
        b.validate(make_ctx(3e9, zeta_max=1e4))


@pytest.mark.parametrize(
    ("text", "unit", "match"),
    [
        (
            "1 3\n10 2\n100 4\n",
            "GPa",
            r"boundary\.table .*non-decreasing.*zeta = 10 and 100|"
            r"boundary\.table .*non-decreasing.*between zeta = 1 and 10",
        ),
        ("1 3\n1 4\n", "GPa", r"boundary\.table .*strictly increasing"),
        ("1 3 4\n10 5 6\n", "GPa", r"boundary\.table .*two columns"),
        ("1 3\n", "GPa", r"boundary\.table .*two rows"),
        ("1 3\n10 4\n", "m", r"boundary\.table_unit = 'm' must be a pressure unit"),
    ],
)
def test_bad_tables_named(tmp_path, text, unit, match):
    with pytest.raises(ValueError, match=match):
        SD(table=_write(tmp_path, text), table_unit=unit)


def test_constant_dispatches_to_fixed_wall(engine):
    clock = make_clock(SIGMA_Y**2)
    lo, up = SD(Y1=SIGMA_Y, n=0.0).walls(make_ctx(3e8), 3e8, clock)
    assert up.kind == "absorbing" and up.is_fixed and float(up.position) == SIGMA_Y
    lo, up = SD(Y1=SIGMA_Y, n=0.1).walls(make_ctx(3e8), 3e8, clock)
    assert up.kind == "yield_closure" and not up.is_fixed


def _solve(engine, boundary, ctx, clock, rtol=1e-6):
    boundary.validate(ctx)
    tau = clock.tau_of_zeta(ctx.zeta)
    results = []
    for p0 in ctx.p0:
        lo, up = boundary.walls(ctx, float(p0), clock)
        res = engine.solve(tau, float(p0), lo, up, rtol=rtol)
        assert res.status in ("success", "tolerance_not_met"), res.message
        results.append(res)
    return boundary.interpret(ctx, results), results


@pytest.mark.parametrize("n", [0.05, 0.3])
def test_moving_wall_identities(engine, n):
    """A_el + A_pl + A_non = 1 and int pP + Y(zeta) A_pl = p0 through the engine."""
    ctx = make_ctx([1e8, 5e8], zeta_max=1e3, n_zeta=13)
    clock = make_clock(2 * SIGMA_Y**2)
    rtol = 1e-5
    out, results = _solve(engine, SD(Y1=SIGMA_Y, n=n), ctx, clock, rtol)
    el, pl = out["elastic_area_fraction"][1], out["plastic_area_fraction"][1]
    non = out["non_contact_area_fraction"][1]
    tol = 10 * rtol
    assert np.max(np.abs(el + pl + non - 1)) < tol
    assert np.max(np.abs(out["plastic_force_balance_residual"][1])) < tol
    # the plastic contact carries Y(zeta) and at most the whole load: Y A_pl <= p0
    assert np.all(pl * SIGMA_Y * ctx.zeta**n <= ctx.p0[:, None] * (1 + tol))
    assert np.all(out["elastic_load_share"][1] >= -tol)
    np.testing.assert_allclose(out["yield_stress"][1], SIGMA_Y * ctx.zeta**n, rtol=1e-12)
    # the hardening wall keeps more elastic contact than the fixed wall
    ex = np.array([two_wall_areas(clock.tau_of_zeta(ctx.zeta), p, SIGMA_Y).plastic for p in ctx.p0])
    assert np.all(pl[:, -1] < ex[:, -1])


def test_moving_wall_converges_to_constant_hardness(engine):
    ctx = make_ctx([3e8], zeta_max=1e3, n_zeta=13)
    clock = make_clock(1 * SIGMA_Y**2)
    ex = two_wall_areas(clock.tau_of_zeta(ctx.zeta), 3e8, SIGMA_Y)
    errs = []
    for n in (0.04, 0.02, 0.01):
        out, _ = _solve(engine, SD(Y1=SIGMA_Y, n=n), ctx, clock, rtol=1e-6)
        el, pl = out["elastic_area_fraction"][1][0], out["plastic_area_fraction"][1][0]
        errs.append(max(np.max(np.abs(el - ex.elastic)), np.max(np.abs(pl - ex.plastic))))
    # O(n) convergence: halving n roughly halves the distance
    assert errs[1] < 0.7 * errs[0] and errs[2] < 0.7 * errs[1]
    assert errs[2] < 0.05


def test_wall_declares_the_kinks_of_its_speed(tmp_path):
    """The clock's kinks of f (a roll-off knee) and a table's nodes, inside (1, zeta_max),
    become the yield wall's kinks in diffusion time: dY/dtau = Y'(zeta) / f(zeta) has a
    kink there (the engine makes them step boundaries)."""
    from xpersson.plugins import DiffusionClock

    base = make_clock(2 * SIGMA_Y**2, zeta_max=1e3)
    clock = DiffusionClock(base.tau_fn, base.f, 1e3, kinks=(1.0, 6.5, 1e5))
    _, up = SD(Y1=SIGMA_Y, n=0.2).walls(make_ctx(1e8), 1e8, clock)
    np.testing.assert_allclose(up.kinks, clock.tau_of_zeta(np.array([6.5])), rtol=1e-15)
    assert SD(Y1=SIGMA_Y, n=0.2).walls(make_ctx(1e8), 1e8, base)[1].kinks == ()
    z = np.geomspace(1, 1e4, 9)
    rows = "\n".join(f"{a:.17g} {2.0 * a**0.2:.17g}" for a in z)
    table = SD(table=_write(tmp_path, rows), table_unit="GPa")
    _, up = table.walls(make_ctx(1e8), 1e8, clock)
    inside = np.unique(np.concatenate([[6.5], z[(z > 1) & (z < 1e3)]]))
    np.testing.assert_allclose(up.kinks, clock.tau_of_zeta(inside), rtol=1e-15)
