"""The solved-curve machinery's fast paths equal plain reference evaluations (issue 25).

Every fast path of ``_phi``/``_curve``/``_subgap``/``_percolation`` is checked against a plain
evaluation over all elements written here (scipy's ``PPoly``/``CubicSpline``, the linear
table look-up in one expression, ``np.exp``): bit for bit where only the layout or the blocks
changed, to 1e-14 (stated) where the sums are regrouped (the sparse product of the sub-gaps
in full contact).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.interpolate import CubicSpline

import xpersson
from xpersson.cache import cache
from xpersson.physics import SolvedContact, _compiled, critical_magnification
from xpersson.physics._curve import _Curve, _edges
from xpersson.physics._fastnum import _exp_inplace, _ppoly_at, _row_slopes
from xpersson.physics._percolation import _crossing_coefficients
from xpersson.physics._phi import _Phi
from xpersson.physics._subgap import _sub_mean_gap, _sub_prep
from xpersson.physics.elastic import area_fraction, diffusion_time
from xpersson.physics.psd import SelfAffineRollOff

E_STAR = 10e6 / (1.0 - 0.5**2)
LOADS = np.geomspace(1e3, 3e6, 12)


@pytest.fixture(scope="module")
def psd():
    return SelfAffineRollOff.from_h_rms(1e-6, 0.8, 1e3, 1e4, 1e8)


@pytest.fixture(scope="module")
def contact(psd):
    """A dense Persson curve (full contact over the first decades at high load)."""
    zeta = np.concatenate(([1.0], 1.0 + np.geomspace(1e-9, 1e5 - 1.0, 400)))
    A, N = area_fraction(LOADS[:, None], diffusion_time(psd, E_STAR, zeta)[None, :])
    return SolvedContact(psd, E_STAR, LOADS, zeta, A, None, N)


def _spline(rng, n_knot=40, n_row=5):
    x = np.sort(rng.uniform(-3.0, 7.0, n_knot))
    return CubicSpline(x, rng.normal(size=(n_row, n_knot)), axis=1)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_ppoly_at_is_scipys_evaluation(seed):
    rng = np.random.default_rng(seed)
    spl = _spline(rng)
    # random points, every breakpoint and both ends; more points than one block
    xs = np.concatenate((rng.uniform(spl.x[0], spl.x[-1], 20000), spl.x))
    ref = np.maximum(spl(xs), 0.0)
    np.testing.assert_array_equal(_ppoly_at(spl, xs), ref)
    out = np.full((5, xs.size + 3), np.nan)
    _ppoly_at(spl, xs, out=out[:, 3:])
    np.testing.assert_array_equal(out[:, 3:], ref)
    assert np.all(np.isnan(out[:, :3]))  # only its columns written
    out_t = np.full((xs.size + 3, 5), np.nan)  # the transposed layout: its rows only
    assert _ppoly_at(spl, xs, out_t=out_t[3:]) is not None
    np.testing.assert_array_equal(out_t[3:], ref.T)
    assert np.all(np.isnan(out_t[:3]))


def test_exp_inplace_is_numpys_exp():
    y = np.concatenate([np.linspace(-800.0, 5.0, 40001), [-np.inf, np.nan, 0.0]])
    np.testing.assert_array_equal(_exp_inplace(y.copy()), np.exp(y))
    fast = np.linspace(-700.0, 1.0, 1001)  # no value below the slow band: one pass
    np.testing.assert_array_equal(_exp_inplace(fast.copy()), np.exp(fast))


def test_phi_table_is_the_spline_on_the_grid(contact):
    """The table is max(spline, 0) on its grid from each load's own first live nodes on, 0
    below (as that load alone: its look-ups never depend on the other loads)."""
    ph = _Phi(contact.psd, E_STAR, contact.p0, contact.curve)
    grid, tab = ph._table()
    tab = _full_table(ph)
    ref = np.maximum(ph._spl(grid), 0.0)  # scipy's PPoly evaluation
    own = []
    for row in range(LOADS.size):
        live = np.flatnonzero(ph.phi[row, 1:] != 0.0)
        g = int(np.searchsorted(grid, ph.s[max(0, int(live[0]) - 8)]))
        np.testing.assert_array_equal(tab[row, g:], ref[row, g:])
        assert np.all(tab[row, :g] == 0.0)
        assert np.all(np.abs(ref[row, :g]) < 1e-20 * tab[row].max())  # ringing: 3e-23
        own.append(g)
    g0 = min(own)
    assert 0 < g0 < grid.size and max(own) > g0  # zero blocks, the loads' own
    assert ph._table()[1].flags["C_CONTIGUOUS"] and ph._lo == g0 - 2
    assert ph._table()[1].shape == (LOADS.size, grid.size - ph._lo)  # (loads, nodes)


@pytest.mark.parametrize("order", ["unsorted", "increasing"])
def test_phi_at_tau_is_the_spline_and_its_linear_first_interval(contact, order):
    """Any ``tau``, and increasing ``tau`` (the mean gap's rule: the linear first interval a
    prefix, the spline evaluated past it only): the same bits."""
    ph = contact.phi
    tau = np.concatenate((np.geomspace(1e-3, 1e3, 500) * ph.tau1, [0.0, ph.tau1]))
    if order == "increasing":
        tau = np.sort(tau)
    lin = ph.phi[:, 1:2] * np.clip(tau / ph.tau1, 0.0, 1.0)
    s = np.clip(np.log(np.maximum(tau, 1e-300)), ph.s[0], ph.s[-1])
    ref = np.where(tau < ph.tau1, lin, np.maximum(ph._spl(s), 0.0))  # scipy's PPoly
    got = ph.at_tau(tau)
    np.testing.assert_array_equal(got, ref)
    assert got.flags["C_CONTIGUOUS"]  # the mean gap's matrix product keeps its order


def _full_table(ph):
    """The table on every grid node (the nodes below ``_lo`` are 0)."""
    grid, tab = ph._table()
    full = np.zeros((tab.shape[0], grid.size))
    full[:, ph._lo :] = tab
    return full


def _plain_look_up(ph, lt, load):
    """Phi of load ``load`` at ``ln tau = lt`` (any shape): the linear table look-up."""
    grid, tab = ph._table()[0], _full_table(ph)
    n = grid.size
    u = np.clip((lt - grid[0]) * (1.0 / (grid[1] - grid[0])), 0.0, n - 1.000001)
    i = u.astype(np.intp)
    u = u - i
    row = tab[load]
    val = row[i] + u * (row[i + 1] - row[i])
    low = lt < math.log(ph.tau1)
    phi1 = ph.phi[load, 1]
    t = np.exp(np.where(low, lt, 0.0)) / ph.tau1
    return np.where(low, phi1 * np.clip(t, 0.0, 1.0), val)


def test_sub_mean_gap_is_the_plain_sum_of_look_ups(contact):
    """The blocked, buffered sums at every edge and at selected pairs = a plain loop."""
    z = np.concatenate(([1.0], 1.0 + np.geomspace(1e-9, 1e5 - 1.0, 30)))
    qa = z * contact.q_L
    A = 1.0 - contact.curve.non_area_at(np.broadcast_to(np.log(z), (LOADS.size, z.size)))
    prep = _sub_prep(contact.psd, E_STAR, qa[None, :], contact.q_hi)
    got = _sub_mean_gap(contact.psd, E_STAR, contact.phi, None, A, contact.q_hi, prep=prep)
    where = (A > 0.2) & (A < 1.0)
    part = _sub_mean_gap(
        contact.psd, E_STAR, contact.phi, None, A, contact.q_hi, where=where, prep=prep
    )
    log_tc, kern = prep
    with np.errstate(divide="ignore"):
        la2 = 2.0 * np.log(A)
    ref = np.empty(A.shape)
    for load in range(LOADS.size):
        lt = log_tc[0] + la2[load][:, None]
        ref[load] = (_plain_look_up(contact.phi, lt, load) * kern[0]).sum(axis=-1)
    # A_a = 1 (shared arguments): one sparse product, the same terms in another order and
    # (1 - u) T_i + u T_i+1 for T_i + u (T_i+1 - T_i): round-off of sums of terms >= 0
    full = A == 1.0
    np.testing.assert_allclose(got[full], math.pi * ref[full], rtol=1e-14, atol=0.0)
    np.testing.assert_array_equal(got[~full], math.pi * ref[~full])  # the look-ups themselves
    np.testing.assert_array_equal(part, np.where(where, math.pi * ref, 0.0))
    assert full.mean() > 0.2 and np.count_nonzero(got[full]) > full.sum() // 2


def test_pressure_part_equals_every_pair_computed(contact):
    """Pairs with A_k = A_k+1 take u_next (the same arguments): u1 of the other pairs as
    computing them all."""
    z = np.concatenate(([1.0], 1.0 + np.geomspace(1e-9, 1e5 - 1.0, 60)))
    det = contact.detachment(z, "pressure")
    zz, A, N = _edges(contact.curve, z)
    prep = _sub_prep(contact.psd, E_STAR, (zz * contact.q_L)[None, :], contact.q_hi)
    dA = np.diff(N, axis=1)
    ok = dA > 0
    mixed = _sub_mean_gap(
        contact.psd,
        E_STAR,
        contact.phi,
        None,
        A[:, :-1],
        contact.q_hi,
        where=ok,
        prep=(prep[0][:, 1:], prep[1][:, 1:]),
    )
    mixed[:, -1] = 0.0
    u_next = det.ubar[:, 1:]
    same = ok & (A[:, :-1] == A[:, 1:])  # dA below the round-off of A (both 1)
    assert same.any()  # the skipped pairs exist here
    # there the mixed gap is u_next itself (the same arguments), up to the round-off of the
    # two sums (the shared sparse product for u_next), which 1/dA ~ 1e300 would amplify
    np.testing.assert_allclose(mixed[same], u_next[same], rtol=1e-14, atol=0.0)
    mixed = np.where(same, u_next, mixed)
    safe = np.where(ok, dA, 1.0)
    u1 = np.where(ok, u_next + A[:, :-1] * (mixed - u_next) / safe, 0.0)
    np.testing.assert_array_equal(det.u1, np.maximum(u1, 0.0))


def _kernels(compiled: bool):
    """The option context of the compiled kernels (built first when on)."""
    if compiled:
        pytest.importorskip("numba")
        with xpersson.set_options(compiled=True):
            if _compiled.kernel(math.inf, "sub_sums") is None:
                pytest.skip("numba not importable")
    return xpersson.set_options(compiled=compiled)


@pytest.mark.parametrize("compiled", [False, True])
@pytest.mark.parametrize("needed_share", [0.0, 0.3, 1.0])
def test_sub_mean_gap_needed_entries_are_those_of_every_entry(contact, needed_share, compiled):
    """``needed``: the entries asked for bit for bit as computed with every entry (shared
    cut-offs' columns and per-load entries alike), whatever the others are; with the
    compiled kernels and without."""
    z = np.concatenate(([1.0], 1.0 + np.geomspace(1e-9, 1e5 - 1.0, 30)))
    A = 1.0 - contact.curve.non_area_at(np.broadcast_to(np.log(z), (LOADS.size, z.size)))
    prep = _sub_prep(contact.psd, E_STAR, (z * contact.q_L)[None, :], contact.q_hi)
    needed = np.random.default_rng(7).random(A.shape) < needed_share
    phi = _Phi(contact.psd, E_STAR, LOADS, contact.curve)
    with _kernels(compiled):
        every = _sub_mean_gap(contact.psd, E_STAR, phi, None, A, contact.q_hi, prep=prep)
        got = _sub_mean_gap(
            contact.psd, E_STAR, phi, None, A, contact.q_hi, prep=prep, needed=needed
        )
    assert got[needed].tobytes() == every[needed].tobytes()
    assert (A[needed] == 1.0).any() or needed_share == 0.0  # both kinds of entry asked for


@pytest.mark.parametrize("compiled", [False, True])
@pytest.mark.parametrize("separation", ["almqvist", "pressure"])
def test_detachment_negligible_bins_change_nothing_counted(contact, separation, compiled):
    """``negligible``: the weights, ``u(p0)`` and the counted bins' ``u1`` bit for bit those
    of every bin computed (the others' ``u1`` 0), and so :func:`gap_cdf` with the same
    ``negligible``; the left-out bins exist here (near full contact)."""
    from xpersson.physics import gap_cdf
    from xpersson.physics._gap_band import counted

    z = np.concatenate(([1.0], 1.0 + np.geomspace(1e-9, 1e5 - 1.0, 60)))
    with _kernels(compiled):
        every = SolvedContact(contact.psd, E_STAR, LOADS, contact.curve).detachment(z, separation)
        some = SolvedContact(contact.psd, E_STAR, LOADS, contact.curve).detachment(
            z, separation, negligible=1e-30
        )
    count = counted(every.weight, 1e-30)
    assert (every.weight != 0.0).sum() > count.sum()  # some bins left out
    assert some.weight.tobytes() == every.weight.tobytes()
    assert some.mean_gap.tobytes() == every.mean_gap.tobytes()
    assert some.u1[count].tobytes() == every.u1[count].tobytes()
    assert not some.u1[~count].any()
    u = np.geomspace(1e-12, 1e-4, 50)
    assert (
        gap_cdf(some, u, negligible=1e-30).tobytes()
        == gap_cdf(every, u, negligible=1e-30).tobytes()
    )


@pytest.mark.parametrize("compiled", [False, True])
@pytest.mark.parametrize("with_s", [False, True])
def test_rows_are_a_contact_of_those_loads_alone(contact, with_s, compiled):
    """:meth:`SolvedContact.rows`: the curve, ``Phi`` and mean gap sliced (built on the whole
    batch first, as the leak direct call does) give the detachment, mean gap and ``u1`` of a
    SolvedContact built for those loads alone, bit for bit; with and without ``S``, with the
    compiled kernels and without."""
    cur = contact.curve
    S = (0.6 + 0.4 * cur.area**2) if with_s else None
    sel = np.array([2, 5, 6, 10])
    z = np.concatenate(([1.0], 1.0 + np.geomspace(1e-9, 1e5 - 1.0, 60)))
    zc = np.geomspace(1.5, 300.0, sel.size)
    with _kernels(compiled):
        whole = SolvedContact(contact.psd, E_STAR, LOADS, cur.zeta, cur.area, S, cur.non_area)
        whole.mean_gap()  # Phi's spline and the mean gap built for every load
        assert whole._phi is not None and whole._u is not None
        part = whole.rows(sel)
        alone = SolvedContact(
            contact.psd, E_STAR, LOADS[sel], cur.zeta, cur.area[sel],
            None if S is None else S[sel], cur.non_area[sel],
        )  # fmt: skip
        got = part.detachment(z, negligible=1e-30)
        ref = alone.detachment(z, negligible=1e-30)
        for name in ("weight", "u1", "mean_gap", "area"):
            assert getattr(got, name).tobytes() == getattr(ref, name).tobytes(), name
        assert part.separation_at(zc).tobytes() == alone.separation_at(zc).tobytes()
        assert part.elastic_energy().tobytes() == alone.elastic_energy().tobytes()
    assert np.isfinite(got.u1).all() and (got.weight > 0).any()


def test_crossing_coefficients_are_the_cubic_splines():
    rng = np.random.default_rng(5)
    x = np.sort(rng.uniform(0.0, 9.0, 50))
    A = np.sort(rng.uniform(0.0, 1.0, (7, 50)), axis=1)[:, ::-1]
    k = rng.integers(0, 49, 7)
    ref = CubicSpline(x, A, axis=1).c[:, k, np.arange(7)]
    np.testing.assert_array_equal(np.array(_crossing_coefficients(x, A, k)), ref)
    yt, dx, slope, sl = _row_slopes(x, A)
    np.testing.assert_array_equal(yt, A.T)
    np.testing.assert_array_equal(sl[:-1], CubicSpline(x, A, axis=1).c[2])  # knot slopes


@pytest.mark.parametrize("a_c", [0.05, 0.42, 0.9])
def test_critical_magnification_solves_the_spline(contact, a_c):
    """A(zeta_c) = a_c on CubicSpline(ln zeta, A) (exact at the crossing), NaN if not crossed."""
    cur: _Curve = contact.curve
    zc = critical_magnification(cur.zeta, cur.area, a_c)
    spl = CubicSpline(cur.x, cur.area, axis=1)
    crossed = np.any(cur.area <= a_c, axis=1)
    assert np.array_equal(np.isfinite(zc), crossed) and crossed.any()
    for load in np.flatnonzero(crossed):
        assert spl(np.log(zc[load]))[load] == pytest.approx(a_c, abs=1e-12)


def test_per_load_look_ups_are_the_plain_look_up(contact):
    """The per-load look-up (ln tau given; all rows or some) over the whole range, below the
    table's kept nodes included, equals the look-up on the full table."""
    ph = contact.phi
    rng = np.random.default_rng(3)
    grid = ph._table()[0]
    lt = rng.uniform(grid[0] - 5.0, grid[-1] + 5.0, (LOADS.size, 3000))
    ref = np.array([_plain_look_up(ph, lt[k], k) for k in range(LOADS.size)])
    np.testing.assert_array_equal(ph.at_log_tau_per_load(lt.copy(), slice(0, LOADS.size)), ref)
    rows = np.array([3, 0, 7])
    np.testing.assert_array_equal(ph.at_log_tau_per_load(lt[rows], rows), ref[rows])
    assert (lt < grid[ph._lo]).any() and np.count_nonzero(ref) > ref.size // 4


@pytest.mark.parametrize("with_s", [False, True])
def test_curve_is_the_plain_log_spline(contact, with_s):
    """``ln(1 - F)``, its spline, the spline of ``ln(1 - A)`` and the dead-node mask equal the
    plain formulas (``F = A S``, ``1 - F = 1 - A + A (1 - S)``, 0 at ``zeta = 1``), bit for bit,
    with and without ``S``."""
    ref = contact.curve
    A, N = ref.area, ref.non_area
    S = (0.6 + 0.4 * A**2) if with_s else None
    cur = _Curve(ref.zeta, A, S, N)
    S1 = np.ones_like(A) if S is None else S
    nf = np.clip(N + A * (1.0 - S1), 0.0, 1.0)
    nf[:, 0] = 0.0
    np.testing.assert_array_equal(cur.NF, nf)
    np.testing.assert_array_equal(cur.F, A * S1)
    y = np.log(np.maximum(nf, 1e-300))
    spl = CubicSpline(cur.x[1:], y[:, 1:], axis=1)  # no jump: the cubic spline throughout
    np.testing.assert_array_equal(cur._spl.c, spl.c)
    np.testing.assert_array_equal(cur._dead, y[:, 1:] <= math.log(1e-300))
    yA = np.log(np.maximum(N, 1e-300))
    np.testing.assert_array_equal(cur._spl_a.c, CubicSpline(cur.x[1:], yA[:, 1:], axis=1).c)
    assert (cur._spl_a is cur._spl) == (not with_s)
    x = np.linspace(-1.0, cur.x[-1], 400)
    lin = nf[:, 1:2] * np.clip(x / cur.x[1], 0.0, 1.0)
    ref_nf = np.where(x < cur.x[1], lin, np.exp(np.minimum(spl(np.maximum(x, cur.x[1])), 0.0)))
    np.testing.assert_array_equal(cur.nf(x), ref_nf)


@pytest.fixture
def caches_on():
    """The caches on, also in CI's run with XPERSSON_CACHE=off."""
    with xpersson.set_options(cache=True):
        yield


@pytest.mark.usefixtures("caches_on")
def test_spectrum_caches_are_the_plain_evaluation(psd):
    """The rule and the bin edges' sub-problem nodes of a spectrum are computed once per
    content (read-only, shared by the next solve and by an equal spectrum) and equal those
    computed with the caches off."""
    zeta = np.concatenate(([1.0], 1.0 + np.geomspace(1e-9, 1e5 - 1.0, 200)))
    A, N = area_fraction(LOADS[:, None], diffusion_time(psd, E_STAR, zeta)[None, :])
    mutable = SelfAffineRollOff.from_h_rms(1e-6, 0.8, 1e3, 1e4, 1e8)
    frozen = SelfAffineRollOff.from_h_rms(1e-6, 0.8, 1e3, 1e4, 1e8).freeze()
    assert not mutable.frozen and mutable.cache_key() == frozen.cache_key()
    edges = 1.0 + np.geomspace(1e-9, 1e5 - 1.0, 30)
    edges = np.concatenate(([1.0], edges))
    with xpersson.set_options(cache=False):
        plain = SolvedContact(frozen, E_STAR, LOADS, zeta, A, None, N)
        d0 = plain.detachment(edges)
        plain_gap, plain_rule = plain.mean_gap(), plain.rule
    first = SolvedContact(frozen, E_STAR, LOADS, zeta, A, None, N)
    second = SolvedContact(mutable, E_STAR, LOADS, zeta, A, None, N)  # equal content
    d1, d2 = (sc.detachment(edges) for sc in (first, second))
    for name in ("ubar", "u1", "h", "weight"):
        np.testing.assert_array_equal(getattr(d1, name), getattr(d0, name))
        np.testing.assert_array_equal(getattr(d2, name), getattr(d0, name))
    assert d1.h is d2.h and d0.h is not d1.h and not d1.h.flags.writeable
    np.testing.assert_array_equal(second.mean_gap(), plain_gap)
    assert first.rule is second.rule and plain_rule is not first.rule
    np.testing.assert_array_equal(second.phi.phi, plain.phi.phi)  # Phi's cached weights
    np.testing.assert_array_equal(second.phi.s, plain.phi.s)
    assert not second.rule.dI3.flags.writeable
    stack = list(cache("physics.edge_prep")._store.values())  # every array of every value
    assert stack
    while stack:
        v = stack.pop()
        if isinstance(v, np.ndarray):
            assert not v.flags.writeable
        elif isinstance(v, tuple | list):
            stack.extend(v)


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf, -1e-300, 1.0 + 1e-15])
def test_curve_refuses_areas_and_factors_out_of_range(contact, bad):
    """An area fraction or ``S`` that is not finite or lies outside [0, 1] ((0, 1] for ``S``)
    anywhere is refused, as the separate checks of each did."""
    ref = contact.curve
    A = ref.area.copy()
    A[3, 7] = bad
    with pytest.raises(ValueError, match="area fractions"):
        _Curve(ref.zeta, A, None, ref.non_area)
    S = np.ones_like(ref.area)
    S[2, 5] = 0.0 if bad == -1e-300 else bad
    if bad != 1.0 + 1e-15:  # (S may exceed 1 by 1e-12)
        with pytest.raises(ValueError, match="s_factor"):
            _Curve(ref.zeta, ref.area, S, ref.non_area)


def test_curve_clips_the_complement_only_where_needed(contact):
    """A complement already in [0, 1] (signed zeros included) is kept as it is, bit for bit;
    one beyond is clipped as ``np.clip`` does, and the splines follow the clipped values."""
    ref = contact.curve
    N = ref.non_area.copy()
    N[:, :3] = -0.0
    cur = _Curve(ref.zeta, ref.area, None, N)
    assert cur.non_area is N
    M = N.copy()
    M[1, 2], M[4, -1] = -1e-3, 1.0 + 1e-9
    out = _Curve(ref.zeta, ref.area, None, M)
    np.testing.assert_array_equal(out.non_area, np.clip(M, 0.0, 1.0))
    np.testing.assert_array_equal(np.signbit(out.non_area), np.signbit(np.clip(M, 0.0, 1.0)))
    want = _Curve(ref.zeta, ref.area, None, np.clip(M, 0.0, 1.0))
    np.testing.assert_array_equal(out._spl.c, want._spl.c)
    assert not np.shares_memory(out.non_area, M)
