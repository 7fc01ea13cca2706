"""The Markov-process methods ``markov`` (walkers) and ``markov_ck`` against the closed forms.

Standard errors (SE) are those of a binomial count: sqrt(v (1 - v) / N) for a fraction v of N
walkers; a histogram cell with probability c has SE sqrt(c (1 - c) / N) / width.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy.special import ndtr

from xpersson import engine
from xpersson.engine import Wall, exact, sample_paths

N_BIG = 1_000_000


def _mc(tau, p0, lower=None, upper=None, **opts):
    kw = {} if lower is None else {"lower": lower}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return engine.solve(
            tau,
            p0,
            upper=upper,
            method="markov",
            rtol=0.09,
            options={"walkers": N_BIG, "seed": 7, **opts},
            **kw,
        )


def _cell_probability(cdf, p):
    """Probability of the cells the histogram uses (midpoints between the output pressures)."""
    mid = 0.5 * (p[1:] + p[:-1])
    edges = np.concatenate([[p[0] - (mid[0] - p[0])], mid, [p[-1] + (p[-1] - mid[-1])]])
    return np.diff(cdf(edges)), np.diff(edges)


def _assert_histogram(res, cdfs, n=N_BIG, n_se=4.0):
    for i, cdf in enumerate(cdfs):
        c, w = _cell_probability(cdf, res.p)
        se = np.sqrt(np.maximum(c * (1 - c), 1.0 / n) / n) / w
        z = np.abs(res.P[i] - c / w) / se
        assert z.max() <= n_se, (i, z.max())


# -- must show: 1e6 walkers against the three closed forms ------------------------------------
def test_elastic_closed_form_at_five_magnifications():
    p0 = 1.0
    tau = p0**2 * np.array([0.01, 0.1, 1.0, 10.0, 100.0])  # G = 0.01 ... 100
    p = np.linspace(0.0, 6.0, 61)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = engine.solve(
            tau, p0, method="markov", rtol=0.09, p_out=p, options={"walkers": N_BIG, "seed": 7}
        )
    exact_area = exact.one_wall_area(tau, p0, 0.0)
    z = np.abs(r.area - exact_area) / r.error_estimate
    assert z.max() <= 4.0, z
    # the estimate is the binomial standard error (floored at 1/N where no walker was absorbed)
    np.testing.assert_allclose(
        r.error_estimate[1:], np.sqrt(exact_area * (1 - exact_area) / N_BIG)[1:], rtol=0.05
    )

    def cdf(t):  # int_0^x of the mirrored Gaussian
        s = math.sqrt(2 * t)
        return lambda x: (
            ndtr((np.maximum(x, 0) - p0) / s)
            - ndtr(-p0 / s)
            - ndtr((np.maximum(x, 0) + p0) / s)
            + ndtr(p0 / s)
        )

    _assert_histogram(r, [cdf(t) for t in tau])
    # probability is counted exactly; the load identity holds within its standard error
    assert np.max(np.abs(r.probability_balance)) < 1e-12


def test_linear_moving_wall_of_section_2_2():
    p0, s0, c = 0.5, 0.2, 1.0
    tau = np.array([0.01, 0.1, 0.3, 1.0, 3.0])
    p = np.linspace(-3.2, 4.0, 73)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = engine.solve(
            tau,
            p0,
            lower=Wall.linear(-s0, -c),
            method="markov",
            rtol=0.09,
            p_out=p,
            options={"walkers": N_BIG, "seed": 11},
        )
    a = exact.linear_wall_area(tau, p0, s0, c)
    assert a[1] == pytest.approx(0.9185595730, abs=1e-9)  # physics.md check value
    assert np.max(np.abs(r.area - a) / r.error_estimate) <= 4.0
    assert r.status == "success", r.message

    def cdf(t):
        s = math.sqrt(2 * t)
        wall = -(s0 + c * t)

        def f(x):
            x = np.maximum(x, wall)
            first = ndtr((x - p0) / s) - ndtr((wall - p0) / s)
            img = ndtr((x + p0 + 2 * s0) / s) - ndtr((wall + p0 + 2 * s0) / s)
            return first - math.exp(-c * (p0 + s0)) * img

        return f

    _assert_histogram(r, [cdf(t) for t in tau])


def test_constant_hardness_two_walls_of_section_3_1():
    sy, p0 = 1.0, 0.3
    tau = np.array([0.01, 0.03, 0.1, 0.3, 1.0])
    r = _mc(tau, p0, upper=Wall.absorbing(sy))
    a_el = exact.two_wall_area(tau, p0, 0.0, sy)
    ab_l, ab_u = exact.two_wall_absorbed(tau, p0, 0.0, sy)
    assert a_el[2] == pytest.approx(0.3839343, abs=1e-7)  # physics.md §3.1 check values
    assert ab_u[2] == pytest.approx(0.1138744, abs=1e-7)
    for got, want in ((r.area, a_el), (r.absorbed_upper, ab_u), (r.absorbed_lower, ab_l)):
        se = np.sqrt(np.maximum(want * (1 - want), 1.0 / N_BIG) / N_BIG)
        assert np.max(np.abs(got - want) / se) <= 4.0


# -- the error estimate is honest -------------------------------------------------------------
def test_standard_error_is_honest_over_50_seeds():
    p0 = 1.0
    tau = np.array([0.05, 0.2, 0.5, 1.0, 4.0])
    a = exact.one_wall_area(tau, p0, 0.0)
    inside = []
    for seed in range(50):
        r = engine.solve(
            tau, p0, method="markov", rtol=0.09, options={"walkers": 2000, "seed": seed}
        )
        inside.append(np.abs(r.area - a) <= 2.0 * r.error_estimate)
    inside = np.array(inside)
    frac_runs = inside[:, 2].mean()  # one magnification: 50 independent runs
    frac_all = inside.mean()  # all five magnifications
    assert 0.90 <= frac_runs <= 0.99, frac_runs
    assert 0.90 <= frac_all <= 0.99, frac_all


# -- the moving yield wall (Lambert's closure) against Crank-Nicolson ---------------------------
def test_sticky_yield_wall_matches_crank_nicolson():
    c, y0 = 0.5, 1.0
    up = Wall.yield_closure(lambda t: y0 + c * np.asarray(t), lambda t: np.full(np.shape(t), c))
    tau = np.array([0.05, 0.3, 1.0])
    ref = engine.solve(tau, 0.5, upper=up, method="cn", rtol=1e-6)
    n = 50_000
    r = engine.solve(
        tau, 0.5, upper=up, method="markov", rtol=0.09, options={"walkers": n, "seed": 5}
    )
    for got, want in ((r.area, ref.area), (r.absorbed_upper, ref.absorbed_upper)):
        se = np.sqrt(want * (1 - want) / n)
        assert np.max(np.abs(got - want) / se) <= 4.0
    # the force balance int p P + Y A_pl = p0 holds in expectation (not flagged)
    assert r.status == "success", r.message


# -- Chapman-Kolmogorov propagation on a grid ---------------------------------------------------
@pytest.mark.parametrize(
    ("lower", "upper", "area"),
    [
        (Wall.absorbing(0.0), None, lambda t: exact.one_wall_area(t, 0.5, 0.0)),
        (Wall.linear(-0.2, -1.0), None, lambda t: exact.linear_wall_area(t, 0.5, 0.2, 1.0)),
        (Wall.absorbing(0.0), Wall.absorbing(1.0), lambda t: exact.two_wall_area(t, 0.5, 0, 1)),
    ],
)
def test_chapman_kolmogorov_kernel_meets_its_error_estimate(lower, upper, area):
    tau = np.array([0.001, 0.01, 0.1, 1.0])
    r = engine.solve(tau, 0.5, lower=lower, upper=upper, method="markov_ck", rtol=1e-3)
    err = np.abs(r.area - area(tau))
    assert np.all(err <= r.error_estimate + 1e-12), (err, r.error_estimate)
    assert err.max() < 1e-4
    assert r.success, r.message


def test_transition_kernel_is_the_gaussian_of_variance_two_dtau():
    from xpersson.engine._markov_ck import transition_kernel

    p = np.linspace(-10, 10, 4001)
    k = transition_kernel(p, np.array([0.3]), 0.7)[:, 0]
    h = p[1] - p[0]
    assert np.sum(k) * h == pytest.approx(1.0, abs=1e-12)
    assert np.sum(k * p) * h == pytest.approx(0.3, abs=1e-12)
    assert np.sum(k * (p - 0.3) ** 2) * h == pytest.approx(2 * 0.7, abs=1e-10)
    killed = transition_kernel(p, np.array([0.3]), 0.7, lower=(0.0, 0.0))[:, 0]
    assert np.all(killed[p <= 0] == 0.0)
    assert np.sum(killed) * h == pytest.approx(math.erf(0.3 / (2 * math.sqrt(0.7))), abs=1e-6)


# -- reproducibility, options, paths -------------------------------------------------------------
def test_seed_reproduces_and_loads_draw_their_own_streams():
    tau = np.array([0.1, 1.0])
    a = engine.solve(tau, 1.0, method="markov", rtol=0.09, options={"walkers": 1000, "seed": 3})
    b = engine.solve(tau, 1.0, method="markov", rtol=0.09, options={"walkers": 1000, "seed": 3})
    c = engine.solve(tau, 1.0, method="markov", rtol=0.09, options={"walkers": 1000, "seed": 4})
    np.testing.assert_array_equal(a.area, b.area)
    assert not np.array_equal(a.area, c.area)


def test_tolerance_is_reported_not_met_with_the_walkers_it_would_need():
    r = engine.solve([1.0], 1.0, method="markov", rtol=1e-6, options={"walkers": 1000})
    assert r.status == "tolerance_not_met"
    assert "walkers would meet it" in r.message


@pytest.mark.parametrize(
    ("opts", "match"),
    [({"walkers": 0}, "walkers"), ({"seed": -1}, "seed"), ({"bogus": 1}, "unknown keys")],
)
def test_bad_options_are_named(opts, match):
    with pytest.raises(ValueError, match=match):
        engine.solve([1.0], 1.0, method="markov", options=opts)


def test_markov_ck_refuses_a_sticky_wall():
    up = Wall.yield_closure(lambda t: 1 + np.asarray(t), lambda t: np.ones(np.shape(t)))
    with pytest.raises(ValueError, match="cannot treat"):
        engine.solve([1.0], 0.5, upper=up, method="markov_ck")


def test_sample_paths_stop_at_the_wall_and_survive_as_erf():
    tau = np.linspace(0.0, 1.0, 201)
    paths = sample_paths(tau, 1.0, 20_000, seed=1)
    assert paths.shape == (20_000, 201)
    alive = np.isfinite(paths[:, -1]) & (paths[:, -1] > 0)
    a = math.erf(1.0 / (2.0 * math.sqrt(1.0)))
    assert abs(alive.mean() - a) <= 4 * math.sqrt(a * (1 - a) / 20_000)
    assert np.nanmin(paths) >= 0.0
