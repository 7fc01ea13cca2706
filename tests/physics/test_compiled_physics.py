"""The compiled kernels of the interface physics (:mod:`xpersson.physics._compiled`).

Each kernel's Python source is the algorithm (run here as plain Python, without numba, on small
inputs); with numba installed the compiled kernels are tested too. The spline, sub-problem and
Stieltjes kernels give the numpy path's bits; the gap distribution's recurrence is within 1e-12
of each load's largest density.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.linalg.lapack import dgtsv

import xpersson
from xpersson.physics import (
    _band_sums,
    _compiled,
    _curve,
    _fastnum,
    _gap_distribution,
    _gauss_tails,
    _percolation,
    _phi,
    _phi_sums,
    _spline_sums,
    _sub_nodes,
    _subgap,
)
from xpersson.physics._gap_distribution import Detachment, gap_pdf

SCENE = {
    "spectrum": {"model": "self_affine", "H": 0.7, "q_L": "1e3 1/m", "q_r": "3e3 1/m",
                 "q_1": "1e7 1/m", "h_rms": "1 um"},
    "material": {"E": "10 MPa", "nu": 0.5},
    "load": {"p0": {"start": "1 kPa", "stop": "1 MPa", "num": 3}},
    "output": {"zeta": [float(z) for z in np.geomspace(1.0, 1e4, 30)]},
}  # fmt: skip
ANALYSES = {"gap_pdf": {"u_points": 64}, "leakage": {}, "mean_gap": {}, "contact_stiffness": {}}


def _plain(monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """Every module's kernel look-up answered by the plain-Python kernels; the names asked."""
    asked: list[str] = []

    def kernel(work: float, name: str = "gap_rows"):
        asked.append(name)
        for mod in (_compiled, _spline_sums, _band_sums, _phi_sums, _sub_nodes):
            if hasattr(mod, name):
                return getattr(mod, name)
        raise AttributeError(name)

    for mod, attr in (
        (_gap_distribution, "_compiled_kernel"),
        (_subgap, "kernel"),
        (_fastnum, "kernel"),
        (_curve, "kernel"),
        (_percolation, "kernel"),
        (_phi, "kernel"),
    ):
        monkeypatch.setattr(mod, attr, kernel)
    return asked


def _assert_close(ref, got) -> None:
    """Every float output: the same bits, gap_pdf within 1e-12 of each load's largest."""
    for name, var in ref.data_vars.items():
        if var.dtype.kind != "f":
            continue
        a, b = var.values, got[name].values
        if name == "gap_pdf":
            scale = np.max(np.abs(a), axis=-1, keepdims=True)
            assert np.all(np.abs(b - a) <= 1e-12 * scale), name
        else:
            np.testing.assert_array_equal(b, a, err_msg=name)


def test_plain_kernels_give_the_numpy_results(monkeypatch):
    """The interface chain of gap_pdf and leakage (splines, Phi, sub-problem sums, Stieltjes
    sums, gap sum, percolation) run through the kernels' Python form: the numpy path's
    outputs."""
    scene = {**SCENE, "analyses": {"gap_pdf": {"u_points": 16}, "leakage": {}}}
    scene["load"] = {"p0": ["3 kPa", "300 kPa"]}
    with xpersson.set_options(compiled=False, cache=False):
        ref = xpersson.solve(scene)
    asked = _plain(monkeypatch)
    with xpersson.set_options(cache=False):
        got = xpersson.solve(scene)
    want = {"gap_rows", "sub_sums", "spline_coefficients", "spline_values", "df_sums"}
    more = {"crossing_newton", "spline_sub_sums", "band_sums", "df_logs", "table_sums"}
    more |= {"table_values", "phi_cumsum", "node_panels", "node_segments", "node_kernel"}
    assert want | more <= set(asked)
    _assert_close(ref, got)


def test_compiled_kernels_give_the_numpy_results(monkeypatch):
    pytest.importorskip("numba")
    monkeypatch.setattr(_compiled, "MIN_WORK", 0)
    scene = {**SCENE, "analyses": ANALYSES}
    with xpersson.set_options(compiled=False, cache=False):
        ref = xpersson.solve(scene)
    with xpersson.set_options(compiled=True):  # on even under XPERSSON_COMPILED=off; built
        assert _compiled.kernel(1.0) is not None  # with numba's disk cache (caches on)
    with xpersson.set_options(cache=False, compiled=True):
        got = xpersson.solve(scene)
    _assert_close(ref, got)


def _detachment(rng: np.random.Generator) -> Detachment:
    """Bins on every branch of the recurrence: wide and narrow Gaussians (``du/h`` below and
    above D_MAX), centres near the wall, far left of the grid's start (rising from underflow)
    and beyond A_MAX, zero weights."""
    n_load, h = 4, np.array([2e-6, 1e-6, 3e-7, 1e-7, 2e-8, 1e-9])
    u1 = rng.uniform(0.0, 3e-6, (n_load, h.size))
    u1[0, 2] = 44 * h[2]  # centre 44 widths out: the first columns underflow
    u1[1, 3] = 60 * h[3]  # beyond A_MAX: direct band
    u1[2, 0] = 0.0
    w = rng.uniform(0.0, 0.1, (n_load, h.size))
    w[3, 1] = 0.0
    z = np.geomspace(1.0, 10.0, h.size + 1)
    area = np.ones((n_load, z.size))
    return Detachment(np.ones(n_load), z, area, area, w, u1, h, 2e-6)


@pytest.mark.parametrize("points", [2, 17, 200])
def test_gap_rows_recurrence_matches_the_exp_form(points):
    det = _detachment(np.random.default_rng(points))
    u = np.linspace(0.0, 8e-6, points)
    with xpersson.set_options(compiled=False):
        ref = gap_pdf(det, u)
    inv_h = 1.0 / det.h
    u_h = np.minimum(u[None, :] * inv_h[:, None], 1e150)
    weight = det.weight * inv_h / math.sqrt(2.0 * math.pi)
    ls, ks = np.nonzero(weight)
    out = np.zeros_like(ref)
    _compiled.gap_rows(ls, ks, det.u1[ls, ks] * inv_h[ks], weight[ls, ks], u_h, out)
    scale = np.max(np.abs(ref), axis=1, keepdims=True)
    assert np.all(np.abs(out - ref) <= 1e-12 * scale)
    big = ref > 1e-250 * scale  # element by element where the density is not round-off
    assert np.all(np.abs(out - ref)[big] <= 1e-12 * ref[big])


def _exact_terms(det: Detachment, u: np.ndarray) -> tuple:
    """Every pair's term ``w [N(b; a) + N(b; -a)]`` on the grid (numpy's exp), the pairs and
    the gap_rows arguments."""
    inv_h = 1.0 / det.h
    u_h = u[None, :] * inv_h[:, None]
    weight = det.weight * inv_h / math.sqrt(2.0 * math.pi)
    ls, ks = np.nonzero(weight)
    a, w = det.u1[ls, ks] * inv_h[ks], weight[ls, ks]
    with np.errstate(under="ignore"):
        b = u_h[ks]
        terms = w[:, None] * (
            np.exp(-0.5 * (b - a[:, None]) ** 2) + np.exp(-0.5 * (b + a[:, None]) ** 2)
        )
    return terms, ls, ks, a, w, u_h


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_gauss_tails_left_out_are_below_tail_of_the_density(seed):
    """The columns a pair leaves out (beyond :func:`tail_stop`) carry less than TAIL of the
    load's exact density; on widths spread over 100x (as the detachment bins) some are left
    out, and the compiled sum stays within n_pairs TAIL (+ the recurrence's round-off)."""
    rng = np.random.default_rng(seed)
    n_load, h = 5, np.geomspace(2e-6, 2e-8, 12)
    u1 = rng.uniform(0.0, 2.0, (n_load, h.size)) * h
    w = 10.0 ** rng.uniform(-6.0, -1.0, (n_load, h.size))
    w[0, 3] = 0.0
    z = np.geomspace(1.0, 10.0, h.size + 1)
    area = np.ones((n_load, z.size))
    det = Detachment(np.ones(n_load), z, area, area, w, u1, h, 2e-6)
    u = np.linspace(0.0, 1e-5, 256)
    terms, ls, ks, a, wp, u_h = _exact_terms(det, u)
    density = np.zeros((n_load, u.size))
    np.add.at(density, ls, terms)
    floor = np.full(density.shape, -np.inf)
    refs = np.full((n_load, 2, 3), np.nan)
    _gauss_tails.tail_floor(ls, ks, a, wp, u_h, floor, refs)
    left_out = 0
    for p in range(ls.size):
        stop = _gauss_tails.tail_stop(u_h[ks[p]], a[p], wp[p], floor, ls[p], 0, u.size, refs)
        assert np.all(terms[p, stop:] < _gauss_tails.TAIL * density[ls[p], stop:])
        left_out += u.size - stop
    assert left_out > 0.2 * terms.size
    out = np.zeros_like(density)
    _compiled.gap_rows(ls, ks, a, wp, u_h, out)
    big = density > 1e-250 * density.max(axis=1, keepdims=True)
    assert np.all(np.abs(out - density)[big] <= 1e-13 * density[big])


def test_gauss_tails_keep_every_column_of_a_load_with_a_negative_weight():
    u_h = np.linspace(0.0, 30.0, 64)[None, :] * np.array([[1.0], [0.1]])
    ls, ks = np.array([0, 0]), np.array([0, 1])
    a, w = np.array([0.5, 0.5]), np.array([1.0, -1e-3])
    floor, refs = np.full((1, 64), -np.inf), np.full((1, 2, 3), np.nan)
    _gauss_tails.tail_floor(ls, ks, a, w, u_h, floor, refs)
    assert np.all(floor == -np.inf)
    assert _gauss_tails.tail_stop(u_h[0], 0.5, 1.0, floor, 0, 0, 64, refs) == 64
    w[1] = 1e-3  # both positive: the narrow pair's tail below the wide one's is left out
    floor[:] = -np.inf
    _gauss_tails.tail_floor(ls, ks, a, w, u_h, floor, refs)
    assert _gauss_tails.tail_stop(u_h[0], 0.5, 1.0, floor, 0, 0, 64, refs) < 64
    assert _gauss_tails.tail_stop(u_h[0], 0.5, 0.0, floor, 0, 0, 64, refs) == 0


@pytest.mark.parametrize("seed", [4, 5])
def test_gauss_tails_start_from_the_wide_reference_changes_no_stop(seed):
    """The analytic start (a wider reference leaves the pair out beyond its root) skips only
    columns the test leaves out: the stops of the full scan from the last column."""
    rng = np.random.default_rng(seed)
    n_u = 256
    for _ in range(200):
        h = 10.0 ** rng.uniform(-2.0, 0.0, 3)
        rows = np.linspace(0.0, 40.0, n_u)[None, :] / h[:, None]
        ls, ks = np.zeros(3, dtype=np.intp), np.arange(3)
        a, w = rng.uniform(0.0, 6.0, 3), 10.0 ** rng.uniform(-8.0, 0.0, 3)
        floor, refs = np.full((1, n_u), -np.inf), np.full((1, 2, 3), np.nan)
        _gauss_tails.tail_floor(ls, ks, a, w, rows, floor, refs)
        none = np.full((1, 2, 3), np.nan)
        for p in range(3):
            args = (rows[p], a[p], w[p], floor, 0, 0, n_u)
            full = _gauss_tails.tail_stop(*args, none)
            assert _gauss_tails.tail_stop(*args, refs) == full


def test_uniform_grid_test():
    assert _compiled.uniform_from_zero(np.linspace(0.0, 3e-6, 256))
    assert not _compiled.uniform_from_zero(np.geomspace(1e-9, 1.0, 50))
    assert not _compiled.uniform_from_zero(np.linspace(1e-9, 1.0, 50))
    assert not _compiled.uniform_from_zero(np.zeros(4))


@pytest.mark.parametrize("dominant", [True, False])
def test_spline_slopes_is_lapack_dgtsv_on_every_column(dominant):
    """With and without row interchanges, several right-hand sides at once: LAPACK's bits."""
    rng = np.random.default_rng(7 + dominant)
    n = 9
    dl, du = rng.normal(size=n - 1), rng.normal(size=n - 1)
    d = rng.normal(size=n) + (4.0 * np.sign(rng.normal(size=n)) if dominant else 0.0)
    b = rng.normal(size=(n, 5))
    *_, ref, info = dgtsv(dl.copy(), d.copy(), du.copy(), b.copy(order="F"))
    x = b.copy()
    assert _compiled.spline_slopes(dl.copy(), d.copy(), du.copy(), x) == info == 0
    np.testing.assert_array_equal(x, ref)


def test_spline_slopes_reports_a_zero_pivot():
    dl, d, du = np.zeros(2), np.array([0.0, 1.0, 1.0]), np.ones(2)
    assert _compiled.spline_slopes(dl, d, du, np.ones((3, 2))) == 1


def test_pairwise_is_numpys_sum():
    rng = np.random.default_rng(3)
    for n in (1, 7, 8, 9, 63, 128):
        a = rng.normal(size=n) * 10.0 ** rng.uniform(-8, 8, n)
        assert _compiled._pairwise(a, n) == np.sum(a)


def test_off_switch_and_small_work_keep_numpy(monkeypatch):
    with xpersson.set_options(compiled=False):
        assert _compiled.kernel(1e12) is None
    monkeypatch.setattr(_compiled, "_STATE", {})  # not built yet: small work stays numpy
    assert _compiled.kernel(_compiled.MIN_WORK - 1) is None


def test_many_small_calls_build_the_kernels(monkeypatch):
    """Rent or buy: calls below MIN_WORK stay numpy until their work adds up to BUILD_AFTER;
    then the kernels are built (numba present: every later call takes them) or stay None.
    The compiled path on, whatever ``XPERSSON_COMPILED`` says (the count is that path's)."""
    monkeypatch.setattr(_compiled, "_STATE", {})
    small = _compiled.MIN_WORK / 4
    n_calls = int(_compiled.BUILD_AFTER / small)
    with xpersson.set_options(compiled=True):
        for _ in range(n_calls - 1):
            assert _compiled.kernel(small) is None
        with xpersson.set_options(compiled=False):  # the off switch neither counts nor builds
            assert _compiled.kernel(small) is None
        assert "fns" not in _compiled._STATE
        for _ in range(3):  # (past BUILD_AFTER, whatever the round-off of the sum)
            _compiled.kernel(small)
        built = _compiled._STATE["fns"]
        assert (_compiled.kernel(1.0) is None) == (built is None)


def test_nan_weight_spoils_its_load_only(monkeypatch):
    det = _detachment(np.random.default_rng(5))
    w = det.weight.copy()
    w[2, 1] = np.nan
    u = np.linspace(0.0, 8e-6, 40)
    with xpersson.set_options(compiled=False):
        ref = gap_pdf(det, u)
    _plain(monkeypatch)
    got = gap_pdf(Detachment(**{**det.__dict__, "weight": w}), u)
    assert np.isnan(got[2]).all()
    keep = [0, 1, 3]
    scale = np.max(ref[keep], axis=1, keepdims=True)
    assert np.all(np.abs(got[keep] - ref[keep]) <= 1e-12 * scale)


def _crossings(rng: np.random.Generator, n: int) -> tuple:
    """``n`` decreasing cubics about ``lo`` crossing 0.42 inside ``[lo, hi]`` (or not: then the
    steps bisect), from the middle of the bracket."""
    lo = rng.uniform(0.0, 5.0, n)
    hi = lo + rng.uniform(0.01, 1.0, n)
    coef = np.array([rng.normal(0, 0.1, n), rng.normal(0, 0.1, n), -rng.uniform(0.5, 2, n),
                     rng.uniform(0.5, 1.0, n)])  # fmt: skip
    return coef, lo.copy(), lo + 0.5 * (hi - lo), lo, hi


@pytest.mark.parametrize("compiled", [False, True])
def test_crossing_newton_is_the_numpy_newton_bit_for_bit(compiled):
    """critical_magnification's Newton steps by the kernel (plain Python, or compiled): the
    numpy steps' bits, rows in lockstep (the same number of steps for every row)."""
    if compiled:
        pytest.importorskip("numba")
    fn = _compiled.kernel(math.inf, "crossing_newton") if compiled else _compiled.crossing_newton
    if fn is None:
        pytest.skip("compiled kernels are off (XPERSSON_COMPILED=off)")
    rng = np.random.default_rng(36)
    for n in (1, 2, 7, 40):
        coef, xk, xc, lo, hi = _crossings(rng, n)
        with xpersson.set_options(compiled=False):
            want = _percolation._newton(tuple(coef), xk, xc.copy(), lo, hi, 0.42)
        got, lo2, hi2 = xc.copy(), lo.copy(), hi.copy()
        fn(coef, xk, got, lo2, hi2, 0.42)
        np.testing.assert_array_equal(got, want)


@pytest.mark.parametrize("compiled", [False, True])
def test_sub_sums_leave_phis_linear_interval_to_numpy(compiled):
    """An argument in Phi's linear first interval (Phi_1 != 0) needs numpy's ``exp``, which
    differs from libm's (numba's ``math.exp``) in the last bit for some arguments: the kernel
    declines (False) and the caller takes the numpy path; elsewhere it sums the table."""
    if compiled:
        pytest.importorskip("numba")
        with xpersson.set_options(compiled=True):
            fn = _compiled.kernel(math.inf, "sub_sums")
        assert fn is not None
    else:
        fn = _compiled.sub_sums
    grid = np.linspace(0.0, 4.0, 9)  # ln tau nodes; tau1 = e^0.5 (below: the linear interval)
    table = np.vstack([np.linspace(0.1, 0.9, 9), np.linspace(0.2, 1.0, 9)])
    kern = np.array([[0.5, 0.25, 0.25]])
    need = np.ones((2, 1), dtype=bool)
    phi1 = np.array([0.05, 0.1])
    tau1 = math.exp(0.5)
    inside = np.array([[1.0, 2.5, 3.75]])  # every argument on the table
    out = np.zeros((2, 1))
    assert fn(inside, kern, np.zeros((2, 1)), need, out, table, grid, 0, tau1, phi1)
    want = [np.interp(inside[0], grid, row) @ kern[0] for row in table]
    np.testing.assert_allclose(out[:, 0], want, rtol=1e-15)
    below = np.array([[0.2, 2.5, 3.75]])  # one argument in the linear interval
    args = (below, kern, np.zeros((2, 1)), need, np.zeros((2, 1)), table, grid, 0, tau1)
    assert not fn(*args, phi1)
    assert fn(*args, np.zeros(2))  # Phi_1 = 0: the interval is exactly 0, no exp
