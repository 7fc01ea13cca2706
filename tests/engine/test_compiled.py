"""The compiled inner march (:mod:`xpersson.engine._compiled`) against the numpy path.

The kernel's Python source is the reference-equal algorithm (tested here without numba, as
plain Python on small levels); with numba installed, the compiled kernel is tested too.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg.lapack import dgtsv
from test_march_reference import CASES, _level  # the dense reference's cases

import xpersson
from xpersson.engine import _compiled


def _system(rng: np.random.Generator, n: int, dominant: bool):
    dl, du = rng.normal(size=n - 1), rng.normal(size=n - 1)
    d = rng.normal(size=n) + (4.0 * np.sign(rng.normal(size=n)) if dominant else 0.0)
    return dl, d, du, rng.normal(size=n)


@pytest.mark.parametrize("dominant", [True, False])
@pytest.mark.parametrize("n", [2, 3, 17])
def test_gtsv_is_lapack_dgtsv(n, dominant):
    """With and without row interchanges: LAPACK's result (to 1e-12; same operations)."""
    rng = np.random.default_rng(n + 100 * dominant)
    for _ in range(5):
        dl, d, du, b = _system(rng, n, dominant)
        *_, ref, info = dgtsv(dl.copy(), d.copy(), du.copy(), b.copy())
        x = b.copy()
        assert _compiled._gtsv(dl.copy(), d.copy(), du.copy(), x) == info == 0
        np.testing.assert_allclose(x, ref, rtol=1e-12, atol=1e-12 * np.max(np.abs(ref)))


def test_gtsv_reports_a_zero_pivot_as_lapack():
    dl, d, du, b = np.zeros(2), np.array([0.0, 1.0, 1.0]), np.ones(2), np.ones(3)
    info = dgtsv(dl.copy(), d.copy(), du.copy(), b.copy())[-1]
    assert _compiled._gtsv(dl, d, du, b.copy()) == info == 1


OUT = ("area", "absorbed_lower", "absorbed_upper", "load", "moment_lower", "moment_upper")


def _outputs(name: str, **kw):
    lower, upper, p0 = CASES[name]
    inp, level = _level(lower, upper, p0, **kw)
    assert level.ok and inp.out_at.size > 0
    return level.outputs


def _assert_same(ref, got) -> None:
    for key in OUT:
        want, have = getattr(ref, key), getattr(got, key)
        scale = max(float(np.max(np.abs(want))), 1e-300)
        assert np.max(np.abs(have - want)) <= 1e-12 * scale, key


def _patch(monkeypatch, **kernels) -> None:
    """``_compiled.built(name)`` answers ``kernels[name]`` for the names given (the others as
    before)."""
    orig = _compiled.built
    monkeypatch.setattr(_compiled, "built", lambda name: kernels.get(name, orig(name)))


@pytest.mark.parametrize("name", list(CASES))
def test_python_kernel_equals_numpy_march(name, monkeypatch):
    """The kernel's algorithm, run as plain Python on the level, gives the numpy path's
    outputs: yield closure rows, batches (the walls' identity rows), output segments."""
    with xpersson.set_options(compiled=False):
        ref = _outputs(name)
    calls = []

    def kernel(*args):
        calls.append(args[:2])
        return _compiled.march_steps(*args)

    monkeypatch.setattr(_compiled, "kernel", lambda work, *_: kernel)
    _patch(monkeypatch, fused=None)  # the per-block compiled steps
    _assert_same(ref, _outputs(name))
    assert calls  # the kernel ran


@pytest.mark.parametrize("name", list(CASES))
def test_python_fused_level_equals_numpy_march(name, monkeypatch):
    """The fused level (coefficients, steps, wall sums and outputs in one loop), run as plain
    Python: the numpy path's outputs to 1e-12 (bitwise here: the same operations)."""
    from xpersson.engine import _moving_fused

    with xpersson.set_options(compiled=False):
        ref = _outputs(name, mult=2)
    calls = []

    def level(*args):
        calls.append(1)
        return _moving_fused.level_march(*args)

    monkeypatch.setattr(_compiled, "kernel", lambda work, *_: _compiled.march_steps)
    _patch(monkeypatch, fused=(level, _moving_fused.face_coefficients))
    _assert_same(ref, _outputs(name, mult=2))
    assert calls  # the fused level ran


def test_off_switch_and_small_levels_keep_numpy(monkeypatch, compiled_on):
    with xpersson.set_options(compiled=False):
        assert not xpersson.get_options()["compiled"]
        assert _compiled.kernel(1e12) is None
    assert xpersson.get_options()["compiled"]
    monkeypatch.setattr(_compiled, "_STATE", {})  # not built yet: small levels stay numpy
    assert _compiled.kernel(_compiled.MIN_WORK - 1) is None


def test_many_small_levels_build_the_kernel(monkeypatch, compiled_on):
    """Rent or buy: small levels stay numpy until their estimated numpy time adds up to
    BUILD_AFTER, then the compiled march is built (numba present) or None stays (absent)."""
    monkeypatch.setattr(_compiled, "_STATE", {})
    per_block = 100 * (_compiled.NUMPY_STEP + _compiled.NUMPY_NODE_STEP * 50)
    n_blocks = int(_compiled.BUILD_AFTER / per_block)
    for _ in range(n_blocks - 1):
        assert _compiled.kernel(5000.0, 100, 50) is None
    for _ in range(3):  # (past BUILD_AFTER, whatever the round-off of the sum)
        _compiled.kernel(5000.0, 100, 50)
    assert _compiled.kernel(5000.0, 100, 50) is not None
    assert _compiled.kernel(1.0) is not None  # built: every level takes it


@pytest.mark.parametrize("name", ["yield closure, batch", "two walls, batch", "moving lower"])
def test_compiled_kernel_equals_numpy_march(name, monkeypatch, compiled_on):
    monkeypatch.setattr(_compiled, "MIN_WORK", 0)
    assert _compiled.kernel(1.0) is not None
    with xpersson.set_options(compiled=False):
        ref = _outputs(name, mult=2)
    assert _compiled.built("fused") is not None  # built with the march: whole levels compiled
    _assert_same(ref, _outputs(name, mult=2))
    _patch(monkeypatch, fused=None)  # and the per-block steps
    _assert_same(ref, _outputs(name, mult=2))


def _window_arrays(win) -> list:
    return [win.real_lower, win.real_upper, *win.start, *win.end, win.chord]


@pytest.mark.parametrize("name", list(CASES))
def test_window_edges_equal_numpy_edges(name, monkeypatch):
    """The window of the compiled path (one loop over loads and steps, here run as plain
    Python) is the numpy path's, bit for bit: regimes, edges, speeds, chords."""
    from xpersson.engine import _cn_edges

    lower, upper, p0 = CASES[name]
    with xpersson.set_options(compiled=False):
        ref = _level(lower, upper, p0, mult=2)[0].window
    _patch(monkeypatch, edges=_cn_edges.window_edges)
    got = _level(lower, upper, p0, mult=2)[0].window
    for want, have in zip(_window_arrays(ref), _window_arrays(got), strict=True):
        assert have.shape == want.shape and have.dtype == want.dtype
        np.testing.assert_array_equal(have, want)


def test_compiled_window_is_bitwise_and_level_equal(monkeypatch, compiled_on):
    """With numba, the compiled window is the numpy path's bit for bit, and the fused level's
    outputs equal the numpy march's (to 1e-12: its solve is LAPACK's algorithm recompiled;
    bit for bit on the development machine) on a batch with a yield closure and on a graded
    (breakpoint) march."""
    assert _compiled.build() and _compiled.built("edges") is not None
    for name in ("yield closure, batch", "breakpoint lower"):
        lower, upper, p0 = CASES[name]
        with xpersson.set_options(compiled=False):
            inp_ref, ref = _level(lower, upper, p0, mult=2)
        monkeypatch.setattr(_compiled, "MIN_WORK", 0)
        inp, got = _level(lower, upper, p0, mult=2)
        for want, have in zip(
            _window_arrays(inp_ref.window), _window_arrays(inp.window), strict=True
        ):
            np.testing.assert_array_equal(have, want)
        _assert_same(ref.outputs, got.outputs)


@pytest.mark.parametrize("name", ["yield closure, batch", "two walls", "breakpoint lower"])
def test_fused_level_in_blocks_equals_numpy_march(name, monkeypatch):
    """A level marched in blocks of 3 steps (the state, the yield rows, the wall sums and the
    next output carried from call to call; an odd block leaves the state in the other buffer)
    gives the numpy path's outputs."""
    from xpersson.engine import _moving_fused

    lower, upper, p0 = CASES[name]
    with xpersson.set_options(compiled=False):
        ref = _outputs(name, mult=2)
    nn = 2 * 12 + 1  # the level's nodes (n_base 12, mult 2)
    monkeypatch.setattr(_moving_fused, "_OPS", 3 * 4 * len(p0) * nn)
    calls = []

    def level(*args):
        calls.append(args[:2])
        return _moving_fused.level_march(*args)

    monkeypatch.setattr(_compiled, "kernel", lambda work, *_: _compiled.march_steps)
    _patch(monkeypatch, fused=(level, _moving_fused.face_coefficients))
    _assert_same(ref, _outputs(name, mult=2))
    assert len(calls) > 2 and all(i1 - i0 <= 3 for i0, i1 in calls)
