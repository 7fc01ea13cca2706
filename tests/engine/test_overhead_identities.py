"""The engine's per-solve shortcuts give the numbers of what they replace, bit for bit (issue
36): ``_grid.linspace0`` against ``numpy.linspace``, the projection's shortcut where no
absorbed sum exceeds 1 against the full projection, and the stacked Richardson combinations
(``combine``, ``weighted``) against the same formulas field by field, the in-place start
state against its formula, and the one-look-up level grid against its three parts."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from xpersson.engine._grid import linspace0
from xpersson.engine._level import _FIELDS, Outputs, combine, weighted
from xpersson.engine._project import project


def _same(a: np.ndarray, b: np.ndarray) -> bool:
    """Equal shapes and bits (so -0.0 differs from 0.0, and a NaN equals its own bits)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return a.shape == b.shape and a.tobytes() == b.tobytes()


@settings(max_examples=400, deadline=None)
@given(
    stop=st.one_of(
        st.floats(allow_nan=False, allow_infinity=False),
        st.sampled_from([0.0, -0.0, 5e-324, -5e-324, 1e-310, 2.2e-308, 1.7976931348623157e308]),
    ),
    n=st.integers(0, 700),
)
def test_linspace0_is_numpy_linspace_bitwise(stop, n):
    with np.errstate(all="ignore"):
        assert _same(linspace0(stop, n), np.linspace(0.0, stop, n))


def _project_reference(area, abs_l, abs_u):
    """The projection as it was written before its shortcut (every step, every time)."""
    a = np.clip(area, 0.0, 1.0)
    lo = np.maximum(abs_l, 0.0)
    up = np.maximum(abs_u, 0.0)
    total = lo + up
    over = total > 1.0
    scale = np.where(over, 1.0 / np.where(over, total, 1.0), 1.0)
    lo = np.minimum(lo * scale, 1.0)
    up = np.where(over, np.minimum(up * scale, 1.0 - lo), up)
    up = np.where(lo + up > 1.0, np.nextafter(up, 0.0), up)
    dist = {
        "area": np.abs(a - area),
        "absorbed_lower": np.abs(lo - abs_l),
        "absorbed_upper": np.abs(up - abs_u),
        "non_contact_fraction": np.abs(lo + up - (abs_l + abs_u)),
    }
    return (a, lo, up), dist


_PROB = st.one_of(
    st.floats(-0.2, 1.2),
    st.sampled_from([0.0, -0.0, 1.0, 0.5, 1.0 - 2**-53, 1e-300, np.nan]),
)


@settings(max_examples=120, deadline=None)
@given(
    rows=st.lists(st.tuples(_PROB, _PROB, _PROB), min_size=1, max_size=12),
    loads=st.integers(1, 3),
)
def test_projection_shortcut_is_the_full_projection(rows, loads):
    v = np.array(rows * loads, dtype=float).T.reshape(3, loads, len(rows))
    got, got_d = project(v[0], v[1], v[2])
    ref, ref_d = _project_reference(v[0], v[1], v[2])
    assert all(_same(g, r) for g, r in zip(got, ref, strict=True))
    assert got_d.keys() == ref_d.keys()
    assert all(_same(got_d[k], ref_d[k]) for k in ref_d)


def _outputs(rng: np.random.Generator, with_p: bool) -> Outputs:
    fields = {name: rng.standard_normal((2, 5)) for name in _FIELDS if name != "P"}
    fields["area"][0, :3] = [-0.0, 0.0, np.nan]
    fields["P"] = rng.standard_normal((2, 5, 3)) if with_p else None
    return Outputs(**fields)


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 5), with_p=st.booleans())
def test_stacked_combinations_are_the_fieldwise_formulas(seed, n, with_p):
    rng = np.random.default_rng(seed)
    levels = [_outputs(rng, with_p) for _ in range(n)]
    w = rng.standard_normal(n)
    got = weighted(levels, w)
    for name in _FIELDS:
        if getattr(levels[0], name) is None:
            assert getattr(got, name) is None
            continue
        acc = 0
        for c, lv in zip(w, levels, strict=True):
            acc = acc + float(c) * getattr(lv, name)
        assert _same(getattr(got, name), acc)
    fine, coarse = levels[-1], levels[0]
    extrapolated = combine(fine, coarse, True)
    for name in _FIELDS:
        a = getattr(fine, name)
        if a is None:
            assert getattr(extrapolated, name) is None
        else:
            assert _same(getattr(extrapolated, name), a + (a - getattr(coarse, name)) / 3.0)
    kept = combine(fine, coarse, False)
    assert all(getattr(kept, name) is getattr(fine, name) for name in _FIELDS)


def _initial_reference(la, wa, x, w, p0, t0, k, image):
    """The start state as it was written before the in-place version (every operation on a
    fresh array, Python scalars)."""
    import math

    from scipy.special import erf

    pn = la[:, :1] + wa[:, :1] * x[None, :]
    c = 1.0 / math.sqrt(4.0 * math.pi * t0)
    r2 = wa[:, :1] * np.exp(-((pn - p0) ** 2) / (4.0 * t0)) * c
    mass = math.erf(k / math.sqrt(2.0))
    if image is not None:
        r2 = r2 - wa[:, :1] * np.exp(-((pn + p0 - 2.0 * image) ** 2) / (4.0 * t0)) * c
        s = 2.0 * math.sqrt(t0)
        lo, up, q = la[:, 0], la[:, 0] + wa[:, 0], p0[:, 0]
        direct = erf((up - q) / s) - erf((lo - q) / s)
        mirror = erf((up + q - 2.0 * image) / s) - erf((lo + q - 2.0 * image) / s)
        mass = 0.5 * (direct - mirror)
    r2[:, 0] = 0.0
    r2[:, -1] = 0.0
    return (r2 * (mass / (r2 @ w))[:, None]).ravel()


@settings(max_examples=200, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    loads=st.integers(1, 4),
    n=st.integers(2, 40),  # (one interval: both nodes on walls, no mass to normalise)
    image=st.booleans(),
)
def test_initial_state_in_place_is_the_formula_bitwise(seed, loads, n, image):
    from types import SimpleNamespace

    from xpersson.engine._level import level_nodes
    from xpersson.engine._moving import _initial_state

    rng = np.random.default_rng(seed)
    nodes = level_nodes(n, float(rng.uniform(0.0, 2.0)))
    t0 = float(10.0 ** rng.uniform(-6, 12))
    p0 = rng.uniform(1.0, 1e6, (loads, 1))
    k = float(rng.uniform(3.0, 9.0))
    half = k * np.sqrt(2.0 * t0)
    la = p0 - half * rng.uniform(0.2, 1.0, (loads, 1))  # a wall may cut the window
    wa = (p0 + half * rng.uniform(0.2, 1.0, (loads, 1))) - la
    la, wa = np.hstack([la, la + 1.0]), np.hstack([wa, wa * 2.0])  # (loads, steps) rows
    wall = float(la.min() - half * rng.uniform(0.0, 0.5)) if image else None
    win = SimpleNamespace(start=SimpleNamespace(lower=la, width=wa))
    got = _initial_state(win, nodes.x, nodes.w, p0, np.float64(t0), k, wall)
    assert _same(got, _initial_reference(la, wa, nodes.x, nodes.w, p0, t0, k, wall))


def test_level_grid_is_its_three_parts():
    from xpersson.engine._level import face_basis, level_grid, level_nodes, system_rows

    for loads, n, stretch in [(1, 24, 1.5), (3, 48, 0.0), (2, 7, 2.5)]:
        grid = level_grid(loads, n, stretch)
        assert all(_same(a, b) for a, b in zip(grid.nodes, level_nodes(n, stretch), strict=True))
        rows = system_rows(loads, n, stretch)
        assert all(np.array_equal(a, b) for a, b in zip(grid.rows, rows, strict=True))
        assert _same(grid.basis, face_basis(n, stretch))
        assert not grid.basis.flags.writeable and not grid.rows.volumes.flags.writeable
