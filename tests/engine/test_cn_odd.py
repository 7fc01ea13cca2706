"""Error control of stiff yield-wall windows (``_cn_odd``): Richardson combinations that cancel
the odd powers of the step too, and the controller on level families with a known expansion."""

from __future__ import annotations

from fractions import Fraction
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from xpersson.engine._cn_control import _Judge, richardson_weights
from xpersson.engine._cn_odd import odd_constant, odd_rounds, odd_weights
from xpersson.engine._level import Outputs

EXACT = np.array([[0.25, 1e-3, 3e-7]])  # the "exact" areas of one load at three outputs


@pytest.mark.parametrize("mults", [(1, 2, 3), (1, 2, 3, 4), (2, 3, 4, 5), (3, 4, 5, 6, 7)])
def test_odd_weights_cancel_every_power_from_h2(mults):
    """sum w = 1 and sum w m^-j = 0 for j = 2 .. k (k levels); the constant is |sum w m^-(k+1)|."""
    w, m = odd_weights(mults), np.array(mults, float)
    assert np.sum(w) == pytest.approx(1.0, abs=1e-12)
    for j in range(2, len(mults) + 1):
        assert np.dot(w, m**-j) == pytest.approx(0.0, abs=1e-12)
    assert odd_constant(mults) == pytest.approx(abs(np.dot(w, m ** -(len(mults) + 1.0))))


def test_odd_weights_closed_forms():
    """(1, 2, 3, 4): (-1/60, 4/5, -81/20, 64/15), K = 1/240; (2, 3, 4, 5): K = 1/1680."""
    got = [Fraction(float(x)).limit_denominator(100) for x in odd_weights((1, 2, 3, 4))]
    assert got == [Fraction(-1, 60), Fraction(4, 5), Fraction(-81, 20), Fraction(64, 15)]
    assert 1.0 / odd_constant((1, 2, 3, 4)) == pytest.approx(240.0)
    assert 1.0 / odd_constant((2, 3, 4, 5)) == pytest.approx(1680.0)


@settings(max_examples=40, deadline=None)
@given(st.lists(st.floats(-1e3, 1e3), min_size=3, max_size=3), st.integers(1, 4))
def test_four_levels_are_exact_on_a_quartic_error(c, first):
    """A + c2 h^2 + c3 h^3 + c4 h^4 (h = 1/m): the combination of four levels gives A."""
    mults = tuple(range(first, first + 4))
    levels = [1.0 + sum(ck * m ** -(k + 2.0) for k, ck in enumerate(c)) for m in mults]
    assert np.dot(odd_weights(mults), levels) == pytest.approx(
        1.0, abs=1e-9 * (1 + max(map(abs, c)))
    )


class _Levels:
    """Grid levels ``(n, m)`` whose areas are ``EXACT + sum_p c_p (1 / (n m))^p`` (the
    controller's view of ``_cn._Grids``); ``solved`` counts the levels asked for."""

    def __init__(self, coef: dict[int, float]) -> None:
        self.coef, self.solved, self.stop = coef, set(), None

    def levels(self, n, mults, dense):
        out = []
        for m in mults:
            self.solved.add((n, m))
            h = 1.0 / (n * m)
            area = EXACT + sum(c * h**p * EXACT for p, c in self.coef.items())
            zero = np.zeros_like(area)
            out.append(Outputs(area, zero, zero, zero + 1e6, zero, zero, None))
        return out


def _judge(rtol: float = 1e-6) -> _Judge:
    pb = SimpleNamespace(rtol=rtol, atol=1e-14, lower=None, upper=None, p_out=None)
    return _Judge(pb, np.ones_like(EXACT), graded=False, stiff=True)


def test_even_expansion_is_answered_by_the_sixth_order_of_four_levels():
    """Without odd powers the first answer is S(2, 3, 4) of levels 1-4 (no fifth level), and
    its error is within its estimate."""
    lv = _Levels({2: 30.0, 4: 3e3, 6: 1e4})
    fit = odd_rounds(lv, _judge(), 24, 0.5)
    assert fit is not None and lv.solved == {(24, m) for m in (1, 2, 3, 4)}
    est, best, _ = fit
    levels = lv.levels(24, (2, 3, 4), 1)
    s = sum(w * o.area for w, o in zip(richardson_weights((2, 3, 4)), levels, strict=True))
    np.testing.assert_allclose(best.area, s, rtol=1e-13)
    assert np.all(np.abs(best.area - EXACT) <= est)


def test_an_h3_term_is_seen_and_cancelled():
    """An h^3 term that the sixth order's estimate underrates (its combinations fall as h^3):
    the distance to the four-level combination rejects S(2, 3, 4), the odd combinations take
    over, and the accepted error is within its estimate and the tolerance."""
    coef = {2: 30.0, 3: 2e5, 4: 3e3, 5: 1e7}
    lv = _Levels(coef)
    fit = odd_rounds(lv, _judge(), 24, 0.5)
    assert fit is not None and max(m for _, m in lv.solved) >= 5
    est, best, _ = fit
    err = np.abs(best.area - EXACT)
    assert np.all(err <= est)
    assert np.all(err <= 1e-6 * EXACT)
    # the sixth-order answer of levels 1-4 was off by more than the tolerance
    levels = lv.levels(24, (2, 3, 4), 1)
    s = sum(w * o.area for w, o in zip(richardson_weights((2, 3, 4)), levels, strict=True))
    assert np.max(np.abs(s - EXACT) / (1e-6 * EXACT)) > 1.0


def test_five_levels_answer_with_the_batch_worst_distance():
    """Level errors ``1e-6 sum_p a_p m^-p`` of the area (in tolerances: ``a_p``) with an h^3
    term that rejects the sixth order and an h^5 term that the four-level combination X_b
    leaves (with the h^6 term: 0.28 tolerances): the answer at five levels is the combination
    of levels 1-5 that cancels h^2 .. h^5 (0.056 tolerances off), within its estimate
    (ODD_MARGIN x the batch's worst distance to X_b: 0.68 tolerances), which is the same
    fraction of the tolerance at every load and output; no sixth level is solved (5x the
    asymptotic error of X_b, the estimate before, is 1.13 tolerances)."""
    exact = np.array([[0.25, 1e-3, 3e-7], [0.5, 2e-2, 1e-5]])
    scale = np.array([[1.0], [0.1]])  # the second load's errors 10x smaller
    a = {2: 1e3, 3: 2e4, 4: -3e3, 5: 600.0, 6: -100.0}
    lv = _Levels({})

    def levels(n, mults, dense):
        out = []
        for m in mults:
            lv.solved.add((n, m))
            rel = 1e-6 * sum(c * float(m) ** -p for p, c in a.items())
            area = exact * (1.0 + rel * scale)
            zero = np.zeros_like(area)
            out.append(Outputs(area, zero, zero, zero + 1e6, zero, zero, None))
        return out

    lv.levels = levels
    pb = SimpleNamespace(rtol=1e-6, atol=1e-14, lower=None, upper=None, p_out=None)
    judge = _Judge(pb, np.ones_like(exact), graded=False, stiff=True)
    est, best, n_used = odd_rounds(lv, judge, 24, 0.5)
    assert lv.solved == {(24, m) for m in range(1, 6)} and n_used == 5 * 24
    five = levels(24, (1, 2, 3, 4, 5), 1)
    x5 = sum(w * o.area for w, o in zip(odd_weights((1, 2, 3, 4, 5)), five, strict=True))
    np.testing.assert_allclose(best.area, x5, rtol=1e-12)
    tol = 1e-6 * np.abs(best.area) + 1e-14
    np.testing.assert_allclose(est / tol, (est / tol).max(), rtol=1e-9)
    assert np.all(np.abs(best.area - exact) <= est) and np.all(est <= tol)
    assert 0.6 < (est / tol).max() < 0.75
