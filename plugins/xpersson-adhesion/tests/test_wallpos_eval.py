"""The detachment wall evaluates its PPoly table by scipy's own compiled loop, called directly
(issue 36: the engine evaluates the wall a dozen times per solve): the same numbers as
``PPoly.__call__``, bit for bit, inside and outside the table, for any shape of times."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.interpolate import PchipInterpolator, PPoly

from xpersson_adhesion._wallpos import DetachmentWall, _Pchip, _ppoly_values, _SqrtPos


def _table(seed: int) -> PchipInterpolator:
    rng = np.random.default_rng(seed)
    x = np.sort(rng.uniform(0.0, 10.0, 40))
    return PchipInterpolator(x, rng.normal(size=40))


@pytest.mark.parametrize("extrapolate", [True, False])
def test_ppoly_values_are_ppoly_call(extrapolate):
    pc = _table(0)
    pc.extrapolate = extrapolate
    t = np.random.default_rng(1).uniform(-1.0, 11.0, 500)  # (outside: NaN without extrapolate)
    for shape in ((500,), (20, 25)):
        want, got = pc(t.reshape(shape)), _ppoly_values(pc, t.reshape(shape))
        assert got.shape == want.shape
        np.testing.assert_array_equal(got, want)
    assert np.isnan(_ppoly_values(pc, t)).any() == (not extrapolate)


def test_other_tables_take_their_own_call():
    """A periodic PPoly or any other callable: its own ``__call__``."""
    pc = _table(2)
    per = PPoly(pc.c, pc.x, extrapolate="periodic")
    t = np.linspace(-5.0, 15.0, 101)
    np.testing.assert_array_equal(_ppoly_values(per, t), per(t))
    np.testing.assert_array_equal(_ppoly_values(np.cos, t), np.cos(t))


def test_detachment_wall_is_the_clipped_square_root_of_its_table():
    pc = _table(3)
    poly = PPoly(pc.c, pc.x)
    wall = DetachmentWall(_Pchip(_SqrtPos(poly), 1.0, 9.0))
    t = np.random.default_rng(4).uniform(0.0, 10.0, 300)
    want = -np.sqrt(np.maximum(poly(np.clip(t, 1.0, 9.0)), 0.0))
    np.testing.assert_array_equal(wall(t), want)
    assert wall(5.0).shape == () and wall(5.0) == wall(np.array([5.0]))[0]


# -- the compiled loop (numba, optional): the numpy path's numbers bit for bit ----------------
def _walls(seed: int, extrapolate: bool, root: bool) -> tuple[DetachmentWall, np.ndarray]:
    rng = np.random.default_rng(seed)
    pc = _table(seed)
    x = pc.x
    lo, hi = (x[0], x[-1]) if seed % 3 else (rng.uniform(-1.0, 2.0), rng.uniform(8.0, 11.0))
    table = PPoly(pc.c, x, extrapolate=extrapolate)
    wall = DetachmentWall(_Pchip(_SqrtPos(table) if root else table, lo, hi))
    edges = [lo, hi, x[0], x[-1], np.nan, 0.0, -0.0, np.inf, -np.inf]
    t = np.concatenate([rng.uniform(-1.0, 11.0, 200), x, np.nextafter(x, np.inf), edges])
    return wall, (np.sort(t) if seed % 2 else t)


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("extrapolate", [True, False])
@pytest.mark.parametrize("root", [True, False])
def test_compiled_wall_equals_numpy_wall(seed, extrapolate, root):
    """Times in and out of order, on breakpoints, at and past the clip, NaN and signed zeros:
    the compiled loop gives the numpy path's values and signs (NaN where it gives NaN)."""
    pytest.importorskip("numba")
    from xpersson import set_options
    from xpersson.engine import _wall_table

    if not _wall_table.build():
        pytest.skip("compiled code off (XPERSSON_COMPILED=off)")
    wall, t = _walls(seed, extrapolate, root)
    for shape in (t.shape, (t.size // 2, 2) if t.size % 2 == 0 else (1, t.size)):
        tt = t.reshape(shape)
        with set_options(compiled=False):
            want, want_sigma = wall(tt), wall.sigma_of_tau(tt)
        got, got_sigma = wall(tt), wall.sigma_of_tau(tt)
        assert wall.sigma_of_tau.values(tt, True) is not None  # the compiled loop ran
        for a, b in ((want, got), (want_sigma, got_sigma)):
            assert a.shape == b.shape
            np.testing.assert_array_equal(a, b)  # NaN where NaN
            assert (np.isnan(a) | (np.signbit(a) == np.signbit(b))).all()  # -0.0 stays -0.0
    assert wall(5.0).shape == ()


def test_compiled_wall_needs_its_option_and_a_plain_table():
    """Off with ``compiled=False``; a table with a repeated breakpoint (two intervals could
    hold a time) takes the numpy path."""
    pytest.importorskip("numba")
    from xpersson import set_options
    from xpersson.engine import _wall_table

    _wall_table.build()
    with set_options(compiled=False):
        assert _wall_table.kernels() is None
    pc = _table(7)
    x = np.concatenate([pc.x[:5], pc.x[4:]])
    c = np.concatenate([pc.c[:, :4], np.zeros((4, 1)), pc.c[:, 4:]], axis=1)
    table = _Pchip(PPoly(c, x), float(x[0]), float(x[-1]))
    assert table.wall_table(False) is None and table.values(np.ones(3), False) is None
