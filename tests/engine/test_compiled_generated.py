"""The compiled march against the numpy path on generated problems (issue 36: "the pure-numpy
path stays and equals the compiled one to 1e-12").

The compiled level (:mod:`xpersson.engine._moving_fused`) and the compiled steps solve their
tridiagonal systems as LAPACK's ``dgtsv`` does (:func:`xpersson.engine._cnstep._gtsv`, the same
operations in the same order) and start from the numpy start state, so a solve's numbers do not
depend on whether the process has built the compiled march yet (it starts after some work):
whole ``cn`` solves (every level of the error control, the estimate included) of drawn walls,
loads and tolerances are solved both ways and compared bit for bit.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import xpersson
from xpersson.engine import Wall, _compiled, solve_batch

pytest.importorskip("numba")

TAU = np.logspace(-2.0, 1.0, 7)  # output times [Pa^2]


def _walls(kind: int, a: float, b: float):
    """A lower and an upper wall of one of the march's kinds (``a``, ``b``: shape numbers)."""
    if kind == 0:  # moving absorbing lower wall, speeds by central differences
        return Wall.absorbing(lambda t: a * np.sqrt(t) - 0.2), None
    if kind == 1:  # a square-root onset at a declared breakpoint (graded steps, chords)
        tb = 0.05 + 0.5 * b
        return Wall.absorbing(
            lambda t: a * np.sqrt(np.maximum(t - tb, 0.0)), breakpoints=[tb], still_until=tb
        ), None
    if kind == 2:  # two absorbing walls, the upper one moving
        return Wall.absorbing(-0.1 * a), Wall.absorbing(lambda t: 2.0 + b + 0.2 * a * t)
    # a moving yield wall (closure rows)
    return Wall.absorbing(0.0), Wall.yield_closure(lambda t: 1.5 + b + a * t, lambda t: a + 0.0 * t)


def _same(ref, got) -> None:
    for key in ("area", "absorbed_lower", "absorbed_upper", "load", "error_estimate"):
        want, have = np.asarray(getattr(ref, key)), np.asarray(getattr(got, key))
        assert want.tobytes() == have.tobytes(), key


@settings(max_examples=10, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    kind=st.integers(0, 3),
    a=st.floats(0.1, 0.6),
    b=st.floats(0.0, 1.0),
    p0=st.lists(st.floats(0.6, 1.4), min_size=1, max_size=3),
    rtol=st.sampled_from([1e-4, 1e-6]),
)
def test_compiled_solve_equals_numpy_solve(kind, a, b, p0, rtol):
    lower, upper = _walls(kind, a, b)
    kw = {"rtol": rtol, "method": "cn"}
    with xpersson.set_options(compiled=False):
        ref = solve_batch(TAU, np.array(p0), (lower, upper), **kw)
    assert _compiled.build()  # built: every level takes the compiled march
    got = solve_batch(TAU, np.array(p0), (lower, upper), **kw)
    assert got.status == ref.status
    _same(ref, got)


def test_gtsv_is_lapacks_dgtsv():
    """:func:`_gtsv` on systems with and without row interchanges: LAPACK's solution (to
    1e-12) and ``info``, also with a zero pivot."""
    from scipy.linalg.lapack import dgtsv

    from xpersson.engine._cnstep import _gtsv

    rng = np.random.default_rng(7)
    for n, dominant in ((2, True), (9, True), (17, False), (33, False)):
        for _ in range(4):
            dl, du = rng.normal(size=n - 1), rng.normal(size=n - 1)
            d = rng.normal(size=n) + (4.0 if dominant else 0.0)
            if not dominant:
                d[: n // 2] += 4.0  # plain rows first, then interchanges
            b = rng.normal(size=n)
            *_, ref, info = dgtsv(dl.copy(), d.copy(), du.copy(), b.copy())
            x = b.copy()
            assert _gtsv(dl.copy(), d.copy(), du.copy(), x) == info == 0
            np.testing.assert_allclose(x, ref, rtol=1e-12, atol=1e-12 * np.max(np.abs(ref)))
    dl, d, du = np.zeros(2), np.array([1.0, 0.0, 1.0]), np.ones(2)
    info = dgtsv(dl.copy(), d.copy(), du.copy(), np.ones(3))[-1]
    assert _gtsv(dl, d, du, np.ones(3)) == info == 2
