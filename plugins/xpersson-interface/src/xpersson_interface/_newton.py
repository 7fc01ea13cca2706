"""The Bruggeman Newton of the leak analysis's effective medium (:func:`newton`) and its
optional compiled step (numba): the numbers of the numpy path, bit for bit.

:func:`newton` iterates 4-10 times over (loads, 240 cells) rows; each iteration is
about twenty numpy calls (five passes over the rows, the rest over one value per row): at the
~70 loads of a load-table call ~0.5 ms, at one load ~0.2 ms of overhead. :func:`newton_step`
does one iteration of every live row in one pass, with the numpy path's operations in its
order:

- ``r = s_k / (s_k + e)`` and ``m r`` element by element (``e = exp(x)`` stays numpy's: the
  caller computes it, numba's ``exp`` is libm's and differs in the last bit);
- the row sum ``(m r).sum(axis=1)`` in numpy's pairwise order (:func:`_pairwise_sum`: blocks of
  8 accumulators, halves split at multiples of 8 beyond 128 elements), added to the reduction's
  identity 0;
- ``np.einsum("ij,ij->i", m r, r)`` in the order of numpy's baseline SIMD loop
  (:func:`_einsum_dot`: two lanes, four vectors per step, multiply then add, the tail
  zero-padded, the lanes added at the end, onto the zeroed output);
- the bracket, step and stopping tests of :func:`newton` as there (``np.where`` as a branch).

It runs only where numba is already imported in the process (the interface physics' compiled
kernels import it once their work pays) and ``xpersson.set_options(compiled=...)``
(``XPERSSON_COMPILED``) is on, and where this numpy's reductions take the orders it reproduces
(:func:`numpy_orders`, checked once when it is built); otherwise the numpy path runs. The
reductions' orders are asserted against numpy in
``plugins/xpersson-interface/tests/test_bruggeman_newton.py``.
"""

from __future__ import annotations

import math
import sys
import types
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from xpersson import numba_cache
from xpersson.options import compiled_enabled

__all__ = ["MAX_CELLS", "compiled", "iterate", "kernel", "newton", "newton_step", "numpy_orders"]

#: Longest row (cells) the compiled step sums (its pairwise sum is unrolled three levels deep).
MAX_CELLS = 512

_STATE: dict[str, Any] = {}  # "fns": the compiled step once built (None: numba missing)


def kernel() -> Callable[..., int] | None:
    """The compiled :func:`newton_step`, or None: the option is off, or numba is not imported
    in this process, or missing."""
    fns = compiled(_STATE, (newton_step,))
    return None if fns is None else fns["newton_step"]


def compiled(
    state: dict[str, Any], fns: tuple[Callable[..., Any], ...], *modules: str
) -> dict[str, Callable[..., Any]] | None:
    """The compiled forms of ``fns`` by name, each with this module's summation helpers
    (:func:`_block_sum` .. :func:`_einsum_dot`) compiled in its scope, kept in ``state``; None:
    the option is off, numba is not imported in this process (its import is the physics
    kernels' to pay), missing, or this numpy's orders are others (:func:`numpy_orders`).
    ``modules``: the other modules whose sources key the disk cache (those of ``fns``)."""
    if not compiled_enabled():
        return None
    if "fns" not in state:
        if "numba" not in sys.modules:
            return None
        state["fns"] = _build(fns, modules)
    return state["fns"]  # type: ignore[no-any-return]


def _build(
    fns: tuple[Callable[..., Any], ...], modules: tuple[str, ...]
) -> dict[str, Callable[..., Any]] | None:
    jit = numba_cache.njit(__name__, *modules, nogil=True, error_model="numpy")
    if jit is None or not numpy_orders():  # pragma: no cover - numba optional; other numpy
        return None
    helpers = (_block_sum, _eighth, _quarter, _half, _pairwise_sum, _einsum_dot)
    scope = dict(globals())
    for fn in helpers:  # each helper compiled with the compiled helpers it calls in scope
        scope[fn.__name__] = jit(types.FunctionType(fn.__code__, scope, fn.__name__))
    return {fn.__name__: jit(types.FunctionType(fn.__code__, scope, fn.__name__)) for fn in fns}


def newton(
    x: NDArray[np.float64],
    lo: NDArray[np.float64],
    hi: NDArray[np.float64],
    m: NDArray[np.float64],
    s_k: NDArray[np.float64],
    base: NDArray[np.float64],
    rtol: float,
) -> NDArray[np.float64]:
    """:func:`._leakage._bruggeman_rows`' safeguarded Newton in ``x = ln s`` for the roots of
    ``f = base + 2 sum m s_k/(s_k + s)`` (decreasing), from ``x`` in the brackets
    ``[lo, hi]`` (all three updated in place; ``x`` returned). Compiled where built
    (:func:`iterate`: the same numbers, bit for bit)."""
    tol = math.sqrt(rtol)
    if iterate(x, lo, hi, m, s_k, base, tol, rtol):
        return x  # compiled (the same numbers, bit for bit)
    # the rows held in ma, sa (compacted once half of them converged); `live` of those iterate
    cur, ma, sa, buf, buf2 = np.arange(x.size), m, s_k, np.empty_like(m), np.empty_like(m)
    live = np.ones(x.size, dtype=bool)
    for _ in range(200):
        xa, la, ha = x[cur], lo[cur], hi[cur]
        with np.errstate(over="ignore"):
            r = np.add(sa, np.exp(xa)[:, None], out=buf)
            np.divide(sa, r, out=r)  # in [0, 1]: (s_k - s)/(s_k + s) = 2r - 1, stable
        mr = np.multiply(ma, r, out=buf2)
        s1 = mr.sum(axis=1)
        f = base[cur] + 2.0 * s1
        df = 2.0 * (np.einsum("ij,ij->i", mr, r) - s1)  # d f / d ln s = -2 sum m r (1 - r)
        la = np.where(f > 0, xa, la)
        ha = np.where(f <= 0, xa, ha)
        step = f / np.where(df < 0, df, -1.0)
        xn = xa - step
        # a step within tol is final even where it rounds onto the bracket's end
        newt = ((xn > la) & (xn < ha) | (np.abs(step) <= tol)) & (df < 0)
        xn = np.where(newt, xn, 0.5 * (la + ha))
        upd = cur[live]
        x[upd], lo[upd], hi[upd] = xn[live], la[live], ha[live]
        live &= ~((newt & (np.abs(step) <= tol)) | ~(ha - la > rtol))
        n_live = int(np.count_nonzero(live))
        if not n_live:
            break
        if 2 * n_live <= live.size:
            cur, ma, sa = cur[live], ma[live], sa[live]
            buf, buf2 = buf[: ma.shape[0]], buf2[: ma.shape[0]]
            live = np.ones(n_live, dtype=bool)
    return x


def iterate(
    x: NDArray[np.float64],
    lo: NDArray[np.float64],
    hi: NDArray[np.float64],
    m: NDArray[np.float64],
    s_k: NDArray[np.float64],
    base: NDArray[np.float64],
    tol: float,
    rtol: float,
) -> bool:
    """:func:`newton`'s iterations by :func:`newton_step` (``x``, ``lo``, ``hi`` updated in
    place, at most 200 iterations as there); False (nothing done) where the kernel is not
    built or the rows are longer than :data:`MAX_CELLS`."""
    fn = kernel() if m.shape[1] <= MAX_CELLS else None
    if fn is None:
        return False
    rows, live = np.arange(x.size), np.empty(x.size, dtype=bool)
    m, s_k = np.ascontiguousarray(m), np.ascontiguousarray(s_k)
    r, mr = np.empty(m.shape[1]), np.empty(m.shape[1])
    for _ in range(200):
        with np.errstate(over="ignore"):
            e = np.exp(x[rows])  # numpy's exp (numba's is libm's: other last bits)
        if not fn(m, s_k, e, rows, x, lo, hi, base, tol, rtol, live, r, mr):
            break
        rows = rows[live[: rows.size]]
    return True


def numpy_orders() -> bool:
    """Whether this numpy's row sum and ``einsum`` row dot take the orders the compiled step
    reproduces (:func:`_pairwise_sum`, :func:`_einsum_dot`), on rows of 1-300 elements over
    many decades: a numpy built with another SIMD baseline would not, and the numpy path then
    runs (checked once per process, when the step is built)."""
    rng = np.random.default_rng(36)
    for n in (1, 3, 7, 8, 9, 17, 31, 127, 128, 129, 240, 255, 300):
        a, b = rng.random((2, n)) * 10.0 ** rng.uniform(-20, 5, (2, n))
        if _pairwise_sum(a, n) != a[None].sum(axis=1)[0]:
            return False
        if 0.0 + _einsum_dot(a, b, n) != np.einsum("ij,ij->i", a[None], b[None])[0]:
            return False
    return True


def _block_sum(a: Any, s: int, n: int) -> float:
    """numpy's ``pairwise_sum`` of ``a[s:s + n]`` for ``n <= 128``: 8 accumulators."""
    if n < 8:
        r = 0.0
        for i in range(n):
            r += a[s + i]
        return r
    r0, r1, r2, r3 = a[s], a[s + 1], a[s + 2], a[s + 3]
    r4, r5, r6, r7 = a[s + 4], a[s + 5], a[s + 6], a[s + 7]
    i = 8
    while i < n - n % 8:
        r0 += a[s + i]
        r1 += a[s + i + 1]
        r2 += a[s + i + 2]
        r3 += a[s + i + 3]
        r4 += a[s + i + 4]
        r5 += a[s + i + 5]
        r6 += a[s + i + 6]
        r7 += a[s + i + 7]
        i += 8
    res = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    while i < n:
        res += a[s + i]
        i += 1
    return res


def _eighth(a: Any, s: int, n: int) -> float:
    return _block_sum(a, s, n)  # (n <= 128 here: the rows are at most MAX_CELLS long)


def _quarter(a: Any, s: int, n: int) -> float:
    if n <= 128:
        return _block_sum(a, s, n)
    n2 = n // 2 - (n // 2) % 8
    return _eighth(a, s, n2) + _eighth(a, s + n2, n - n2)


def _half(a: Any, s: int, n: int) -> float:
    if n <= 128:
        return _block_sum(a, s, n)
    n2 = n // 2 - (n // 2) % 8
    return _quarter(a, s, n2) + _quarter(a, s + n2, n - n2)


def _pairwise_sum(a: Any, n: int) -> float:
    """``a[:n].sum()`` in numpy's pairwise order (``n <= MAX_CELLS``)."""
    if n <= 128:
        return _block_sum(a, 0, n)
    n2 = n // 2 - (n // 2) % 8
    return _half(a, 0, n2) + _half(a, n2, n - n2)


def _einsum_dot(a: Any, b: Any, n: int) -> float:
    """``np.einsum("ij,ij->i")`` of one contiguous row: numpy's baseline SIMD loop (two lanes,
    four vectors a step, ``a3 b3 + acc``, then ``a2 b2 +``, ``a1 b1 +``, ``a0 b0 +``; the tail
    in vectors zero-padded; the lanes added)."""
    l0, l1 = 0.0, 0.0
    i = 0
    while n - i >= 8:
        t0 = a[i + 6] * b[i + 6] + l0
        t1 = a[i + 7] * b[i + 7] + l1
        t0 = a[i + 4] * b[i + 4] + t0
        t1 = a[i + 5] * b[i + 5] + t1
        t0 = a[i + 2] * b[i + 2] + t0
        t1 = a[i + 3] * b[i + 3] + t1
        l0 = a[i] * b[i] + t0
        l1 = a[i + 1] * b[i + 1] + t1
        i += 8
    while i < n:
        l0 = a[i] * b[i] + l0
        l1 = (a[i + 1] * b[i + 1] if i + 1 < n else 0.0) + l1
        i += 2
    return l0 + l1


def newton_step(
    m: Any,
    s_k: Any,
    e: Any,
    rows: Any,
    x: Any,
    lo: Any,
    hi: Any,
    base: Any,
    tol: float,
    rtol: float,
    live: Any,
    r: Any,
    mr: Any,
) -> int:  # pragma: no cover - compiled (its plain-Python form is tested)
    """One iteration of :func:`newton` for the rows ``rows`` (``e[p] = exp(x[rows[p]])``):
    ``x``, ``lo``, ``hi`` updated in place, ``live[p]`` whether row ``rows[p]`` goes on; the
    number of those. ``r``, ``mr``: scratch rows of the cells' length."""
    k = m.shape[1]
    n_live = 0
    for p in range(rows.size):
        c = rows[p]
        ep = e[p]
        for j in range(k):
            t = s_k[c, j] / (s_k[c, j] + ep)
            r[j] = t
            mr[j] = m[c, j] * t
        s1 = 0.0 + _pairwise_sum(mr, k)
        f = base[c] + 2.0 * s1
        df = 2.0 * ((0.0 + _einsum_dot(mr, r, k)) - s1)
        xa, la, ha = x[c], lo[c], hi[c]
        if f > 0:
            la = xa
        if f <= 0:
            ha = xa
        step = f / (df if df < 0 else -1.0)
        xn = xa - step
        small = abs(step) <= tol
        newton = ((xn > la and xn < ha) or small) and df < 0
        if not newton:
            xn = 0.5 * (la + ha)
        x[c], lo[c], hi[c] = xn, la, ha
        go = not ((newton and small) or not (ha - la > rtol))
        live[p] = go
        if go:
            n_live += 1
    return n_live
