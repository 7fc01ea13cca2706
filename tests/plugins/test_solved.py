"""``xpersson.plugins.solved``: the solved curve that the analyses of several plugins read.

Its end-to-end use (the interface analyses sharing one curve per solve, the dropped
full-contact nodes changing no output) is tested with the analyses, in
``plugins/xpersson-interface/tests/test_fast_paths.py``; here the module on its own, on a
core-only solve.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

import xpersson
from xpersson.cache import cache, solve_scope
from xpersson.physics.closures import GAMMA_DEFAULT
from xpersson.plugins import solved
from xpersson.testing import TINY_SCENE


@pytest.fixture(scope="module")
def tiny():
    """A core-only solve (elastic, 2 loads, 3 magnifications per decade) and a bare context."""
    ds = xpersson.solve(TINY_SCENE)
    ctx = SimpleNamespace(p0=ds["p0"].values, boundary=None, coefficient=None, solve_at=None)
    return ctx, ds


def test_solved_curve_reads_the_datasets_area_rows(tiny):
    ctx, ds = tiny
    s = solved.solved_curve(ctx, ds)
    area = ds["area_fraction"].transpose("p0", "zeta").values
    np.testing.assert_array_equal(s.zeta, ds["zeta"].values)
    np.testing.assert_array_equal(s.area, area)
    np.testing.assert_array_equal(s.contact, np.clip(area, 0.0, 1.0))
    np.testing.assert_array_equal(
        s.non_area, np.clip(ds["non_contact_fraction"].transpose("p0", "zeta").values, 0.0, 1.0)
    )
    assert s.s_factor is None and s.form == "closure" and s.gamma is None
    assert s.curve == (s.zeta, s.area, None, s.non_area)


def test_yang_persson_form_is_gamma_plus_area_squared(tiny):
    ctx, ds = tiny
    s = solved.solved_curve(ctx, ds, form="yang_persson")
    assert s.gamma == GAMMA_DEFAULT
    np.testing.assert_array_equal(s.s_factor, GAMMA_DEFAULT + (1.0 - GAMMA_DEFAULT) * s.area**2)
    assert solved.solved_curve(ctx, ds, "yang_persson", gamma=0.3).gamma == 0.3


def test_an_unknown_form_is_refused_naming_the_forms(tiny):
    ctx, ds = tiny
    with pytest.raises(ValueError, match=r"s_factor must be one of \('closure', 'yang_persson'\)"):
        solved.solved_curve(ctx, ds, form="persson")


def test_a_coarse_curve_without_solve_at_warns(tiny):
    """Dense sampling asked for, but no ``ctx.solve_at``: the Dataset's curve, and a warning."""
    ctx, ds = tiny
    with pytest.warns(UserWarning, match="too coarse for the zeta integrals"):
        s = solved.solved_curve(ctx, ds, per_decade=12)
    np.testing.assert_array_equal(s.zeta, ds["zeta"].values)


def test_per_solve_builds_once_inside_a_solve_and_afresh_outside(tiny):
    ctx, _ = tiny
    built = []

    def build():
        built.append(1)
        return np.arange(3.0)

    with xpersson.set_options(cache=True):
        first, second = solved.per_solve(ctx, ("k",), build), solved.per_solve(ctx, ("k",), build)
        assert len(built) == 2  # outside a solve nothing is kept
        with solve_scope():
            a = solved.per_solve(ctx, ("k",), build)
            b = solved.per_solve(ctx, ("k",), build)
            solved.per_solve(ctx, ("other",), build)
            assert len(cache("plugins.solved")) == 2
        assert len(built) == 4 and a is b and not a.flags.writeable
        assert len(cache("plugins.solved")) == 0  # nothing outlives the solve
    np.testing.assert_array_equal(first, second)


def test_dense_zeta_memo_is_the_plain_merge():
    """The dense grid (memoised per scene grid) is the plain merge, and a fresh writable copy
    every call."""
    z = np.concatenate(([1.0], np.geomspace(1.5, 1e4, 30)))
    n = int(12 * (9.0 + np.log10(1e4 - 1.0)))
    plain = np.unique(np.concatenate((z, 1.0 + np.geomspace(1e-9, 1e4 - 1.0, n)[:-1])))
    first = solved.dense_zeta(z, 12)
    np.testing.assert_array_equal(first, plain)
    first[:] = 0.0  # the caller's copy: the next call is unaffected
    np.testing.assert_array_equal(solved.dense_zeta(z, 12), plain)


def test_past_full_contact_keeps_the_first_two_nodes_and_a_margin():
    """Nodes where every load is in exact full contact are dropped, but for ``zeta = 1``, the
    first node above it and :data:`PLATEAU_MARGIN` nodes before the first open one."""
    non = np.zeros((2, 100))
    non[0, 60:] = np.geomspace(1e-200, 0.5, 40)
    keep = solved._past_full_contact(1.0 - non, non, None)
    np.testing.assert_array_equal(keep[:2], [0, 1])
    np.testing.assert_array_equal(keep[2:], np.arange(60 - solved.PLATEAU_MARGIN, 100))
    # S < 1 opens the contact for the energy and gap integrals too: F = A (1 - S) counts
    S = np.ones((2, 100))
    S[1, 40:] = 0.5
    keep = solved._past_full_contact(1.0 - non, non, S)
    assert keep[2] == 40 - solved.PLATEAU_MARGIN


def test_the_kept_columns_are_the_fancy_index():
    """:func:`_columns` joins two slices where ``keep`` is the first two columns and a run to
    the last (else it fancy-indexes): a new array equal to ``a[:, keep]``, read-only input
    or not."""
    rng = np.random.default_rng(3)
    a = rng.normal(size=(4, 30))
    a.setflags(write=False)
    for keep in (
        np.arange(30),
        np.concatenate(([0, 1], np.arange(9, 30))),
        np.concatenate(([0, 1], np.arange(29, 30))),
        np.array([0, 1]),
        np.array([0, 1, 5, 6]),  # a run that stops short of the last column
        np.array([0, 2, 3, 29]),
    ):
        got = solved._columns(a, keep)
        np.testing.assert_array_equal(got, a[:, keep])
        assert got.flags.writeable and not np.shares_memory(got, a)


def test_the_total_of_kept_columns_is_the_columns_of_the_sum():
    """:func:`_total` is ``sum(arrays)`` (a new array, ``-0.0`` made ``+0.0`` as ``0 + a``),
    and of ``keep``'s columns the same numbers as those columns of the sum."""
    rng = np.random.default_rng(4)
    a = [rng.normal(size=(3, 20)) for _ in range(3)]
    a[0][0, :4] = -0.0
    keep = np.concatenate(([0, 1], np.arange(6, 20)))
    for arrays in (a[:1], a):
        ref = sum(arrays)
        assert solved._total(arrays).tobytes() == ref.tobytes()
        assert solved._total(arrays, keep).tobytes() == ref[:, keep].tobytes()
        assert not np.shares_memory(solved._total(arrays), arrays[0])


def test_the_curve_variables_alone_give_the_same_curve(tiny):
    """``curve_variables``: a Dataset of those variables alone (what the load table selects
    for some loads) gives the solved curve of the whole Dataset, field by field."""
    ctx, ds = tiny
    names = solved.curve_variables(ctx)
    assert {"area_fraction", "non_contact_fraction", "psd_C", "E_star", "zeta"} <= set(names)
    small = ds[[k for k in names if k in ds.variables]]
    assert len(small.data_vars) < len(ds.data_vars)
    for form in ("closure", "yang_persson"):
        a, b = solved.solved_curve(ctx, ds, form), solved.solved_curve(ctx, small, form)
        for f in ("p0", "zeta", "area", "non_area", "contact", "s_factor"):
            np.testing.assert_array_equal(getattr(b, f), getattr(a, f), err_msg=f)
        assert b.E_star == a.E_star and np.array_equal(b.psd.C(a.zeta), a.psd.C(a.zeta))


def test_curve_variables_are_the_boundarys_declared_areas():
    """A boundary that declares its own area variables: those are named (and no default)."""

    class Plastic:
        elastic_area = "elastic_fraction"
        elastic_area_complement = ("free_fraction", "plastic_fraction")
        contact_area = ("elastic_fraction", "plastic_fraction")

    names = solved.curve_variables(SimpleNamespace(boundary=Plastic()))
    assert names[:3] == ("elastic_fraction", "free_fraction", "plastic_fraction")
    assert "area_fraction" not in names and len(names) == len(set(names))


def test_the_first_loads_coarseness_is_its_row_of_the_test(tiny):
    """``_coarse_first``: the first load's row of ``_coarse`` (each row tested alone), read
    from the Dataset (loads along ``p0``, either order of the dimensions)."""
    ctx, ds = tiny
    area = ds["area_fraction"].transpose("p0", "zeta").values
    non = ds["non_contact_fraction"].transpose("p0", "zeta").values
    want = bool(solved._coarse(area, non)[0])
    assert solved._coarse_first(ds, "area_fraction", ("non_contact_fraction",)) == want
    flipped = ds.transpose("zeta", "p0", ...)
    assert solved._coarse_first(flipped, "area_fraction", ("non_contact_fraction",)) == want
    rng = np.random.default_rng(3)
    rows = np.sort(rng.random((5, 9)), axis=1)[:, ::-1]  # decreasing areas
    assert np.array_equal(
        solved._coarse(rows, 1.0 - rows)[:1], solved._coarse(rows[:1], 1.0 - rows[:1])
    )
