"""The compiled march against the numpy path on generated problems (issue 36: "the pure-numpy
path stays and equals the compiled one to 1e-12").

The compiled level (:mod:`xpersson.engine._moving_fused`) and the compiled steps solve their
tridiagonal systems as LAPACK's ``dgtsv`` does (:func:`xpersson.engine._cnstep._factor` and
:func:`~xpersson.engine._cnstep._solve_factor`: the same operations in the same order, each
system eliminated while the one before is solved) and start from the numpy start state, so a
solve's numbers do not
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
    with xpersson.set_options(compiled=True):  # whatever XPERSSON_COMPILED says
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


def _dgtsv_reference(dl, d, du, b) -> int:
    """LAPACK ``dgtsv`` transcribed row by row (one right-hand side, in place): the reference
    whose operations the compiled kernels repeat in its order."""
    n = d.shape[0]
    for i in range(n - 1):
        if abs(d[i]) >= abs(dl[i]):
            if d[i] == 0.0:
                return i + 1
            fact = dl[i] / d[i]
            d[i + 1] = d[i + 1] - fact * du[i]
            b[i + 1] = b[i + 1] - fact * b[i]
            if i < n - 2:
                dl[i] = 0.0
        else:
            fact = d[i] / dl[i]
            d[i] = dl[i]
            temp = d[i + 1]
            d[i + 1] = du[i] - fact * temp
            if i < n - 2:
                dl[i] = du[i + 1]
                du[i + 1] = -fact * dl[i]
            du[i] = temp
            temp = b[i]
            b[i] = b[i + 1]
            b[i + 1] = temp - fact * b[i + 1]
    if d[n - 1] == 0.0:
        return n
    b[n - 1] = b[n - 1] / d[n - 1]
    if n > 1:
        b[n - 2] = (b[n - 2] - du[n - 2] * b[n - 1]) / d[n - 2]
    for i in range(n - 3, -1, -1):
        b[i] = (b[i] - du[i] * b[i + 1] - dl[i] * b[i + 2]) / d[i]
    return 0


def _systems(rng, steps: int, n: int):
    """``steps`` tridiagonal systems of ``n`` rows that take every branch of the kernels:
    dominant rows, row interchanges, zero and signed-zero entries, exact zero right-hand
    sides (a zero ``x`` in the back substitution), infinite ones, and zero pivots."""
    dl, du = rng.normal(size=(steps, n - 1)), rng.normal(size=(steps, n - 1))
    d = rng.normal(size=(steps, n)) + 4.0
    b = rng.normal(size=(steps, n))
    for s in range(steps):
        kind = s % 6
        if kind == 1:  # interchanges
            d[s, ::3] = 0.3 * rng.normal(size=d[s, ::3].shape)
        elif kind == 2:  # exact zeros, both signs, in the matrix and the right-hand side
            dl[s, ::4], du[s, 1::5] = 0.0, -0.0
            b[s, : n // 2] = np.where(rng.random(n // 2) < 0.5, 0.0, -0.0)
        elif kind == 3:  # a zero pivot (info > 0)
            d[s, rng.integers(0, n)] = 0.0
            dl[s], du[s] = np.where(rng.random(n - 1) < 0.5, 0.0, dl[s]), 0.0 * du[s]
        elif kind == 4:  # non-finite right-hand sides
            b[s, rng.integers(0, n, 2)] = [np.inf, -np.inf]
        elif kind == 5:  # zero rows of the right-hand side, interchanges on them
            b[s, ::2] = -0.0
            d[s, 1::4] = 0.1
    return dl, d, du, b


@pytest.mark.parametrize("n", [2, 3, 4, 9, 40])
def test_overlapped_solves_are_dgtsv_bit_for_bit(n):
    """:func:`_factor` then :func:`_solve_factor` (each system solved while the next one is
    eliminated, as the compiled march does it): the reference dgtsv's ``info`` and, where it
    succeeds, its solution bit for bit (zeros' signs and non-finite values included)."""
    import numba

    from xpersson.engine import _cnstep

    jit = numba.njit(nogil=True, error_model="numpy")  # (the compiled march's options)
    factor, solve_factor = jit(_cnstep._factor), jit(_cnstep._solve_factor)
    rng = np.random.default_rng(n)
    steps = 60
    dl, d, du, b = _systems(rng, steps, n)
    want, infos = b.copy(), []
    with np.errstate(invalid="ignore"):  # (inf - inf on the non-finite right-hand sides)
        for s in range(steps):
            infos.append(_dgtsv_reference(dl[s].copy(), d[s].copy(), du[s].copy(), want[s]))
    fact, swap = np.empty((2, n)), np.empty((2, n), np.bool_)
    s0 = 0
    while s0 < steps:  # a run of steps up to the first failed elimination, then a fresh one
        info = factor(dl[s0], d[s0], du[s0], fact[0], swap[0])
        s = s0
        while info == 0 and s < steps:
            cur, nxt, more = s % 2, (s + 1) % 2, s + 1 < steps
            j = s + 1 if more else s
            args = (dl[j], d[j], du[j], fact[nxt], swap[nxt], more)
            info = solve_factor(dl[s], d[s], du[s], fact[cur], swap[cur], b[s], *args)
            assert infos[s] == 0
            assert b[s].tobytes() == want[s].tobytes(), s
            s += 1
        if s < steps:
            assert info == infos[s] != 0, s
        s0 = s + 1
    assert sum(i != 0 for i in infos) >= steps // 6  # the zero pivots were drawn
