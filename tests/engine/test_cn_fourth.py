"""The fourth-order triple of the ``cn`` error control (:func:`xpersson.engine._cn_control.
_fourth`) by one compiled call (:func:`xpersson.engine._cn_outputs.fourth_ratio`) equals the
numpy path's two Richardson combinations and estimate bit for bit, and the default ``cn``
options (:meth:`xpersson.engine._cn.CNOptions.read`, made once per ``atol``) are those of
their fields."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from xpersson import set_options
from xpersson.engine import Wall, _compiled
from xpersson.engine._cn import _DEFAULTS, AIM, CNOptions
from xpersson.engine._cn_control import _fourth, _Judge
from xpersson.engine._level import Outputs
from xpersson.engine._problem import make_problem, window_k

pytest.importorskip("numba")

_VALUES = st.one_of(
    st.floats(-2.0, 2.0), st.sampled_from([0.0, -0.0, np.nan, np.inf, -np.inf, 1e-300])
)


def _bits(a) -> bytes:
    return np.ascontiguousarray(a).tobytes()


@settings(max_examples=80, deadline=None)
@given(
    shape=st.tuples(st.integers(1, 3), st.integers(1, 5)),
    data=st.data(),
    rtol=st.sampled_from([1e-8, 1e-6, 1e-4]),
    graded=st.booleans(),
)
def test_compiled_fourth_is_the_numpy_one(shape, data, rtol, graded):
    """The answer ``E(2n, 4n)``, its estimate and the worst estimate / tolerance of a triple
    of levels equal the numpy path's: signed zeros, NaN and infinities included (where the
    compiled call declines, the numpy path answers)."""
    with set_options(compiled=True):
        assert _compiled.build()
    n = shape[0] * shape[1]

    def field():
        return np.array(data.draw(st.lists(_VALUES, min_size=n, max_size=n))).reshape(shape)

    levels = [Outputs(*(field() for _ in range(6)), None) for _ in range(3)]
    lv = SimpleNamespace(levels=lambda n_base, mults, dense: levels)
    pb = make_problem(np.array([1.0, 2.0]), 0.9, Wall.absorbing(0.0), None, rtol, None,
                      None, 10**6, {})  # fmt: skip
    judge = _Judge(pb, np.abs(field()) + 0.5, graded)
    out = []
    for compiled in (False, True):
        with set_options(compiled=compiled), np.errstate(all="ignore"):
            fit, ratio = _fourth(lv, judge, 24)
        out.append((fit, ratio))
    (want, w_ratio), (got, g_ratio) = out
    assert got.n_used == want.n_used == 96
    assert _bits(got.err) == _bits(want.err)
    for name in Outputs._fields[:6]:
        assert _bits(getattr(got.best, name)) == _bits(getattr(want.best, name)), name
    assert g_ratio == w_ratio or (np.isnan(g_ratio) and np.isnan(w_ratio))


def test_compiled_fourth_answers_ordinary_levels():
    """On ordinary values the one compiled call answers (it is reached): ``E = a + (a - b) / 3``
    and the estimate ``factor |E(a, b) - E(b, c)|`` of the area."""
    with set_options(compiled=True):
        assert _compiled.build()
        fast = _compiled.built("fourth")
    a, b, c = (np.full((1, 2), v) for v in (0.5, 0.25, 0.125))
    out = np.empty((6, 1, 2))
    ok, err, m_area, _ = fast(*[a] * 6, *[b] * 6, *[c] * 6, out, np.ones((1, 2)), 0.5, 1e-6,
                             1e-12)  # fmt: skip
    e_b, e_a = 0.5 + (0.5 - 0.25) / 3.0, 0.25 + (0.25 - 0.125) / 3.0
    assert ok and np.all(out == e_b)
    assert np.all(err == 0.5 * abs(e_b - e_a))
    assert m_area == 0.5 * abs(e_b - e_a) / (1e-6 * e_b + 1e-12)


@pytest.mark.parametrize("atol", [1e-12, 1e-7, 3e-3])
def test_default_options_are_their_fields(atol):
    """The options of no options are the defaults with the window of ``atol``."""
    opts = CNOptions.read({}, atol)
    assert opts == CNOptions(**_DEFAULTS, window_k=window_k(atol), aim=AIM)
    assert CNOptions.read({"nodes": _DEFAULTS["nodes"]}, atol) == opts
