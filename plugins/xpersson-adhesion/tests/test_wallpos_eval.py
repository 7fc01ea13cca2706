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
