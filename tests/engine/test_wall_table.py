"""The compiled wall protocol (:class:`xpersson.engine.WallTable`): a wall's table gives the
positions of scipy's ``PPoly`` bit for bit (numpy and compiled), and the engine's kinks and
whole ``cn`` solves with the table equal those with the position callable alone, bit for bit.
The compiled parts run where numba is installed (else the numpy path is checked alone)."""

from __future__ import annotations

import dataclasses
import functools
import types

import numpy as np
import pytest
from scipy.interpolate import PchipInterpolator, PPoly

from xpersson import set_options
from xpersson.engine import Wall, WallTable, solve_batch
from xpersson.engine import _wall_table as wt
from xpersson.engine._cn_kinks import _switch_times_batch
from xpersson.plugins import Analysis, FastPaths, SpecError


def _sigma_table(wiggle: float = 0.6) -> tuple[PPoly, float, float]:
    """sigma_a^2 [Pa^2] as a PCHIP in tau [Pa^2] on [1e-3, 20]: a square root that wiggles
    (several crossings of the window's lower edge for a range of loads)."""
    t = np.logspace(-3.0, np.log10(20.0), 60)
    sigma = 2.0 * np.sqrt(t) * (1.0 + wiggle * np.sin(4.0 * np.log(t)))
    pc = PchipInterpolator(t, sigma**2, extrapolate=False)
    return PPoly(pc.c, pc.x, extrapolate=False), float(t[0]), float(t[-1])


def _reference(poly: PPoly, lo: float, hi: float, root: bool, negate: bool):
    """The plain position callable of the table: numpy and scipy."""

    def position(tau):
        v = np.asarray(poly(np.minimum(np.maximum(np.asarray(tau, dtype=float), lo), hi)))
        if root:
            v = np.sqrt(np.maximum(v, 0.0))
        return -v if negate else v

    return position


def _times(x: np.ndarray, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    edges = [x[0], x[-1], np.nan, 0.0, -0.0, np.inf, -np.inf, -1.0, 1e3]
    return np.concatenate([rng.uniform(0.0, 1.2 * x[-1], 300), x, np.nextafter(x, 0), edges])


@pytest.mark.parametrize("root", [True, False])
@pytest.mark.parametrize("negate", [True, False])
@pytest.mark.parametrize("extrapolate", [True, False])
def test_table_values_are_ppoly_bit_for_bit(root, negate, extrapolate):
    """Numpy path and (where numba is installed) the compiled loop: the plain callable's
    values, NaN where it gives NaN, signed zeros kept; any shape, times in and out of order."""
    poly, lo, hi = _sigma_table()
    poly.extrapolate = extrapolate
    lo, hi = (lo, hi) if extrapolate else (0.5 * lo, 2.0 * hi)  # (NaN outside without extrap.)
    table = WallTable(poly.c, poly.x, lo, hi, extrapolate, root, negate)
    ref = _reference(poly, lo, hi, root, negate)
    # (also at the clip's ends and next to them: the compiled loop skips the clip strictly inside)
    ends = np.array([lo, hi])
    t = np.concatenate([_times(poly.x, 1), ends, np.nextafter(ends, 0.0), np.nextafter(ends, 1e9)])
    with set_options(compiled=True):  # whatever XPERSSON_COMPILED says
        paths = [False] + ([True] if wt.build() else [])
    for compiled in paths:
        with set_options(compiled=compiled):
            for tt in (t, np.sort(t)[::-1], t.reshape(-1, 3)):
                got, want = table.values(tt), ref(tt)
                assert got.shape == want.shape
                np.testing.assert_array_equal(got, want)
                assert (np.isnan(want) | (np.signbit(got) == np.signbit(want))).all()
            assert (table.compiled(t) is None) == (not compiled)
    assert table.values(3.0).shape == ()


def _wall(with_table: bool, wiggle: float = 0.6) -> Wall:
    poly, lo, hi = _sigma_table(wiggle)
    table = WallTable(poly.c, poly.x, lo, hi, False, True, True)
    position = _reference(poly, lo, hi, True, True)
    return Wall.absorbing(position, table=table if with_table else None)


def _counted(position, calls: list, t):
    calls.append(1)
    return position(t)


@pytest.mark.parametrize("loads", [(0.3,), tuple(np.linspace(-0.4, 1.6, 12))])
def test_kinks_of_a_table_are_the_callables(loads):
    """The window-edge kinks by the table's compiled finder equal the numpy finder's on the
    callable, bit for bit: one load (a few brackets, stepped on floats) and twelve (more
    brackets than the float steps take: the vectorised steps)."""
    k, compiled, calls = 1.5, wt.build(), []
    found = {}
    for with_table in (False, True):
        wall = _wall(with_table)
        counted = functools.partial(_counted, wall.position, calls)
        wall = dataclasses.replace(wall, position=counted)
        pbs = [types.SimpleNamespace(lower=wall, upper=None, p0=p) for p in loads]
        calls.clear()
        found[with_table] = _switch_times_batch(pbs, k, 1e-3, 20.0)
    assert len(found[False]) >= (2 if len(loads) == 1 else 9)  # several crossings per load
    assert found[True] == found[False]
    assert (len(calls) == 0) == compiled  # the table's finder never calls the position back


def test_cn_solve_with_a_table_is_the_callables(monkeypatch):
    """A ``cn`` solve of two loads against a wiggling wall (window-edge kinks found): every
    output and the work record are the same with the table as with the callable alone."""
    from xpersson.engine import _cn

    kinks = []

    def spy(*args):
        kinks.append(found := _switch_times_batch(*args))
        return found

    monkeypatch.setattr(_cn, "_switch_times_batch", spy)
    wt.build()  # (the table's compiled code where numba is installed)
    tau = np.logspace(-1.0, np.log10(15.0), 5)
    p0 = np.array([0.2, 1.0])
    res = [
        solve_batch(tau, p0, (_wall(t, 0.3), None), rtol=1e-3, method="cn") for t in (False, True)
    ]
    for name in ("area", "error_estimate", "nsteps", "n_nodes"):
        np.testing.assert_array_equal(getattr(res[0], name), getattr(res[1], name))
    assert len(kinks) == 2 and kinks[0] == kinks[1] and len(kinks[0]) >= 2


def test_bad_tables_are_refused():
    poly, lo, hi = _sigma_table()
    with pytest.raises(ValueError, match="must match"):
        WallTable(poly.c[:, :-1], poly.x, lo, hi)
    with pytest.raises(ValueError, match="strictly increasing"):
        WallTable(poly.c, poly.x[::-1], lo, hi)
    with pytest.raises(ValueError, match="t_lo <= t_hi"):
        WallTable(poly.c, poly.x, hi, lo)
    with pytest.raises(ValueError, match="table of a wall must be a WallTable"):
        Wall.absorbing(np.sqrt, table=(poly.c, poly.x))
    table = WallTable(poly.c, poly.x, lo, hi)
    assert not np.shares_memory(table.c, poly.c)  # its own copy
    # not part of the wall's equality (the position is)
    f = _reference(poly, lo, hi, True, True)
    assert Wall.absorbing(f, table=table) == Wall.absorbing(f)


def test_wall_tables_is_declared_by_boundaries_only():
    with pytest.raises(SpecError, match="wall_tables applies to boundaries only"):
        type(
            "Wrong",
            (Analysis,),
            {"summary": "x", "provides": (), "fast_paths": FastPaths(wall_tables=True)},
        )

    assert "wall_tables" in FastPaths(wall_tables=True).declared()


@pytest.mark.parametrize("shape", ["row", "shared", "per_load"])
@pytest.mark.parametrize("case", ["passes", "nan_beyond", "load_below"])
def test_compiled_table_check_is_the_numpy_check(shape, case):
    """The compiled input check of a tabled lower wall (its sample times made in the kernel)
    accepts exactly what the numpy check accepts: positions finite at every sample time of
    ``sample_times`` and every load above the wall at tau = 0; refused inputs then raise the
    numpy check's error."""
    from xpersson.engine._problem import _checked_table, make_problem, sample_times

    if not wt.build():
        pytest.skip("compiled march unavailable (numba missing or XPERSSON_COMPILED=off)")
    poly, lo, hi = _sigma_table()
    # "nan_beyond": no clip to the table's end (tau_out reaches past it: NaN positions there)
    table = WallTable(poly.c, poly.x, lo, hi if case != "nan_beyond" else 1e9, root=True,
                      negate=True)  # fmt: skip
    wall = Wall.absorbing(_reference(poly, lo, hi, True, True), table=table)
    loads = np.array([0.5, 1.0, 2.0]) if case != "load_below" else np.array([0.5, -9.0])
    row = np.array([0.0, 0.3, 1.0, 4.0, 30.0])
    tau = {
        "row": row,
        "shared": np.broadcast_to(row, (loads.size, row.size)),
        "per_load": row * np.arange(1.0, loads.size + 1.0)[:, None],
    }[shape]
    t = sample_times(tau)
    pos = -np.sqrt(np.maximum(poly(np.minimum(np.maximum(t, lo), table.t_hi)), 0.0))
    expected = bool(np.all(np.isfinite(pos)) and np.all(loads > pos[0]))
    assert _checked_table(tau, loads, wall) is expected
    assert expected is (case == "passes")
    args = (tau, loads, wall, None, 1e-6, None, None, 100, None)
    if expected:
        make_problem(*args, batch=True)
    else:
        with pytest.raises(ValueError, match="lower|p0"):
            make_problem(*args, batch=True)
