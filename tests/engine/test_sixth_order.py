"""The sixth-order mode of ``cn`` (Richardson on levels N, 2N, ..., LN; ``_cn_control``) and
the vectorised window-edge kinks (``_cn_plan``): closed forms and the exact moving wall."""

from __future__ import annotations

import math
from itertools import combinations

import numpy as np
import pytest
from scipy.optimize import brentq

from xpersson.engine import Wall, exact, solve
from xpersson.engine import _cn_control as ctl
from xpersson.engine._cn_outputs import EST_FLOOR
from xpersson.engine._cn_plan import _bracketed_roots, _switch_times_batch
from xpersson.engine._problem import make_problem

P0, S0 = 0.5, 0.2


def test_richardson_weights_closed_forms():
    np.testing.assert_allclose(ctl.richardson_weights((1, 2)), [-1.0 / 3.0, 4.0 / 3.0], rtol=1e-14)
    # three levels 1, 2, 3: w = (1/24, -16/15, 81/40)
    np.testing.assert_allclose(
        ctl.richardson_weights((1, 2, 3)), [1 / 24, -16 / 15, 81 / 40], rtol=1e-13
    )
    for ms in combinations(range(1, 9), 3):
        w = ctl.richardson_weights(ms)
        m = np.asarray(ms, float)
        # sum 1 (the probability balance is kept), h^2 and h^4 cancelled
        np.testing.assert_allclose([w.sum(), w @ m**-2, w @ m**-4], [1, 0, 0], atol=1e-12)
        # the h^6 constant of three levels is prod m^-2 (used by the controller's predictions)
        assert w @ m**-6 == pytest.approx(ctl._k6(ms), rel=1e-10)
    assert ctl._k6((1, 2, 3)) == pytest.approx(1 / 36)
    assert ctl._k6((2, 3, 4)) == pytest.approx(1 / 576)
    with pytest.raises(ValueError, match="mults"):
        ctl.richardson_weights((1, 1, 2))


def test_combination_is_exact_for_an_even_error_expansion():
    """u(h) = u0 + a h^2 + b h^4 + c h^6: three levels leave exactly c h^6 K, K = prod m^-2."""
    u0, a, b, c, h = 0.3, 2.0, -5.0, 7.0, 0.1
    for ms in ((1, 2, 3), (2, 3, 4), (4, 5, 6)):
        w = ctl.richardson_weights(ms)
        u = [u0 + a * (h / m) ** 2 + b * (h / m) ** 4 + c * (h / m) ** 6 for m in ms]
        assert float(w @ u) - u0 == pytest.approx(c * h**6 * ctl._k6(ms), rel=1e-6)


def test_sixth_next_prefers_the_next_level_when_it_reaches_the_aim():
    # top 4 -> 5 lowers the asymptotic error by (2/5)^2 = 0.16
    work, extend, _ = ctl._sixth_next(4, 3.0, 0.5)
    assert extend and work == pytest.approx(ctl.DENSE * 25)
    # far off: a new grid (four levels) is cheaper than extending to S_LMAX and beyond
    work, extend, grow = ctl._sixth_next(4, 1e6, 0.5)
    assert not extend and grow == pytest.approx((1e6 / 0.5) ** (1 / ctl.S_ORDER))


def _spy(monkeypatch) -> list:
    calls: list = []
    orig = ctl._sixth

    def spy(lv, judge, n, top=4):
        out = orig(lv, judge, n, top)
        calls.append((n, top, out[1]))
        return out

    monkeypatch.setattr(ctl, "_sixth", spy)
    return calls


@pytest.mark.parametrize("c, rtol", [(1.0, 1e-7), (-2.0, 1e-7), (5.0, 1e-9)])
def test_linear_wall_sixth_order_meets_exact(monkeypatch, c, rtol):
    """The exact moving wall (physics.md §2.2) through the sixth-order mode: the error is
    within the tolerance and within the reported estimate at every output; the probability
    balance still closes to round-off (the weights sum to 1)."""
    calls = _spy(monkeypatch)
    tau = np.logspace(-3, 0, 13)
    res = solve(tau, P0, Wall.absorbing(lambda t: -(S0 + c * t)), rtol=rtol, method="cn")
    assert calls, "the sixth-order mode was not used"
    assert res.status == "success", res.message
    ex = exact.linear_wall_area(tau, P0, S0, c)
    err = np.abs(res.area - ex)
    assert np.all(err <= rtol * ex)
    assert np.all(err <= res.error_estimate)
    assert np.max(np.abs(res.probability_balance)) < 1e-12


def test_sixth_order_is_not_used_for_densities_or_breakpoints(monkeypatch):
    calls = _spy(monkeypatch)
    tau = np.logspace(-3, 0, 7)
    wall = Wall.absorbing(lambda t: -(S0 + 1.0 * t))
    res = solve(tau, P0, wall, rtol=1e-7, method="cn", p_out=np.linspace(-1, 3, 9))
    assert res.status == "success" and not calls
    bw = Wall.absorbing(lambda t: -(S0 + 1.0 * np.asarray(t)), breakpoints=[0.1])
    res = solve(tau, P0, bw, rtol=1e-7, method="cn")
    assert res.status == "success" and not calls


def test_bracketed_roots_match_brentq():
    targets = np.array([2.0, 3.0, 10.0, 0.5])
    f = lambda t, idx: t**3 - targets[idx]  # noqa: E731
    a, b = np.full(4, 0.1), np.full(4, 4.0)
    roots = _bracketed_roots(f, a, b, f(a, np.arange(4)), f(b, np.arange(4)), 1e-15 * b)
    want = [brentq(lambda t, v=v: t**3 - v, 0.1, 4.0, xtol=1e-15) for v in targets]
    np.testing.assert_allclose(roots, want, rtol=1e-14)
    # a root on a bracket end is returned as is; no sign change gives NaN
    lo, hi = np.array([2.0 ** (1 / 3), 3.0]), np.array([3.0, 4.0])
    r = _bracketed_roots(f, lo, hi, np.array([0.0, 17.0]), np.array([25.0, 54.0]), 1e-15 * hi)
    assert r[0] == 2.0 ** (1 / 3) and np.isnan(r[1])


def test_few_brackets_on_floats_equal_the_array_steps(monkeypatch):
    """Up to a few brackets each is stepped on Python floats: the same roots, bit for bit, as
    the array steps over all brackets (also a NaN-valued function and a bracket end)."""
    from xpersson.engine import _cn_kinks

    targets = np.array([2.0, 3.0, 10.0, 0.5])

    def f(t, idx):
        v = t**3 - targets[idx]
        return np.where(t > 3.9, np.nan, v)  # (the last bracket meets NaN)

    a, b = np.array([0.1, 0.1, 0.1, 3.0]), np.array([4.0, 4.0, 4.0, 3.95])
    fa, fb = f(a, np.arange(4)), np.array([1.0, 1.0, 1.0, -1.0])  # a sign change each
    assert _cn_kinks._SCALAR_ROOTS >= 4
    floats = _cn_kinks._bracketed_roots(f, a, b, fa, fb, 1e-15 * b)
    monkeypatch.setattr(_cn_kinks, "_SCALAR_ROOTS", 0)
    arrays = _cn_kinks._bracketed_roots(f, a, b, fa, fb, 1e-15 * b)
    np.testing.assert_array_equal(floats, arrays)
    assert np.isfinite(floats[:3]).all()


def test_switch_times_of_a_linear_wall_closed_form():
    """The wall -(s0 + c tau) meets the window edge p0 - k sqrt(2 tau) where
    (c/2) s^2 - k s + (s0 + p0) = 0, s = sqrt(2 tau): both roots, for every load."""
    c, k = 3.0, 6.0
    loads = np.array([0.1, 0.5, 1.0])
    wall = Wall.absorbing(lambda t: -(S0 + c * np.asarray(t)))
    pbs = [make_problem([1.0], p, wall, None, 1e-6, None, None, 10**5, None) for p in loads]
    got = sorted(_switch_times_batch(pbs, k, 1e-6, 1e3))
    want = []
    for p in loads:
        disc = math.sqrt(k * k - 2.0 * c * (S0 + p))
        want += [((k - disc) / c) ** 2 / 2.0, ((k + disc) / c) ** 2 / 2.0]
    np.testing.assert_allclose(got, sorted(want), rtol=1e-13)


def test_switch_times_on_floats_equal_the_array_steps(monkeypatch):
    """The kinks of a few brackets are stepped on floats with the gap evaluated on floats
    (``gap_one``): the same roots, bit for bit, as the array steps of the vectorised gap."""
    from xpersson.engine import _cn_kinks

    wall = Wall.absorbing(lambda t: -(S0 + 3.0 * np.sqrt(np.asarray(t)) + 0.7 * np.asarray(t)))
    pb = make_problem([1.0], 0.3, wall, None, 1e-6, None, None, 10**5, None)
    floats = _switch_times_batch([pb], 6.0, 1e-6, 1e3)
    assert len(floats) >= 1
    monkeypatch.setattr(_cn_kinks, "_SCALAR_ROOTS", 0)
    assert _switch_times_batch([pb], 6.0, 1e-6, 1e3) == floats


@pytest.mark.parametrize("c, rtol", [(1.0, 1e-4), (-2.0, 1e-4), (5.0, 1e-5)])
def test_reported_estimate_bounds_the_error_at_every_output(c, rtol):
    """Second- and fourth-order answers too: the estimate is reported as a uniform fraction
    of the tolerance (the largest estimated), so it bounds the error of the exact moving wall
    at every output, not only at the worst one (level differences cross zero)."""
    tau = np.logspace(-3, 0, 13)
    res = solve(tau, P0, Wall.absorbing(lambda t: -(S0 + c * t)), rtol=rtol, method="cn")
    assert res.status == "success", res.message
    ex = exact.linear_wall_area(tau, P0, S0, c)
    assert np.all(np.abs(res.area - ex) <= res.error_estimate)
    # a uniform fraction of the tolerance on the marched outputs, at least EST_FLOOR (the
    # analytic start's outputs: EST_FLOOR)
    frac = res.error_estimate / (rtol * np.abs(res.area) + 1e-7 * rtol)
    assert np.all(frac[tau > 0] >= EST_FLOOR * (1.0 - 1e-12))
    marched = frac > 1.5 * EST_FLOOR
    assert marched.sum() >= 10
    np.testing.assert_allclose(frac[marched], np.max(frac), rtol=1e-4)
    assert np.max(frac) <= 1.0
