"""All loads of a ``dmt`` scene at once: ``p_att(p_rep)`` sampled once, shared by every load.

``p_att(p_rep)`` [Pa] (:mod:`.dmt`) depends on the scene only, not on the load, so its exact
evaluations are shared by all loads and made for many pressures in one vectorised call (one
detachment step, one quadrature). The pressures evaluated do not depend on which loads are
solved (a load alone gives the same ``p_rep`` as in a batch):

1. **Bracket** (the largest root): ``g(p) = p - p_att(p) - p0`` on the powers of two
   ``p = 2^k`` Pa, scanned down from the first one above ``max(p0, 0) + max traction`` (where
   ``g > 0`` holds without evaluation: ``p_att <= max traction``); the first ``2^k`` with
   ``g < 0`` (every ``2^k <= p0`` qualifies without evaluation) brackets the root in the
   octave ``[2^k, 2^(k+1)]``.
2. **Interpolate**: per octave holding a root, ``p_att`` is interpolated in ``ln p`` at the
   Chebyshev-Lobatto points of degree ``n = 4, 8, 16, 32, 64`` (nested: each degree reuses
   the previous one's values) until the last three Chebyshev coefficients are below
   ``rtol / 100`` of ``2^k``; each load's root is found on the interpolant.
3. **Check**: ``p_att`` is evaluated exactly at every root (the residual, mean gap, area and
   quadrature diagnostics of :class:`~.dmt.DMTState`); a root whose error estimated from the
   exact residual, ``|g| / |g'|`` (``g'`` of the interpolant), exceeds ``rtol p_rep`` is solved
   again by Brent's method on the exact map within its octave (as a cold solve would).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import brentq
from scipy.special import erf, erfc

from ._traction import attraction, attraction_quadrature, max_traction

__all__ = ["AttractionMap", "NMAX"]

Array = NDArray[np.float64]
#: Largest degree of an octave's interpolant; node ``J`` of degree ``n`` is ``J * NMAX / n``.
NMAX = 64
#: Lowest octave scanned below the first power of two above the largest root (halvings).
SCAN_DEPTH = 66
#: Octave of a tensile load whose scan found no sign change on the powers of two.
LOST = -(1 << 40)
#: Pressures evaluated per vectorised call (bounds the memory of the quadrature).
CHUNK = 8


class AttractionMap:
    """``p_att(p_rep)`` [Pa] of one scene, its exact evaluations cached by node.

    Parameters
    ----------
    psd : PowerSpectrum
        Roughness spectrum (Persson convention, m^4).
    E_star : float
        Contact modulus [Pa].
    curves : tuple of (ndarray, ndarray)
        ``(zeta, tau)`` of the dense and of the half-density area curve [1, Pa^2], each
        strictly increasing.
    law, work, rng : str, float, float
        Traction-gap law, work of adhesion [J/m^2] and range [m].
    rtol : float
        Relative tolerance of ``p_rep``.
    """

    def __init__(
        self,
        psd: Any,
        E_star: float,
        curves: tuple[tuple[Array, Array], tuple[Array, Array]],
        law: str,
        work: float,
        rng: float,
        rtol: float,
    ) -> None:
        self.psd, self.E_star, self.curves = psd, float(E_star), curves
        self.law, self.work, self.rng, self.rtol = law, float(work), float(rng), float(rtol)
        self.values: dict[tuple[int, int], float] = {}  # (octave k, node J) -> p_att [Pa]
        self.degree: dict[int, int] = {}  # octave -> converged degree (0: none)
        self.evaluations = 0

    # -- exact evaluations ---------------------------------------------------------------------
    def exact(self, p: Array, coarse: bool = False) -> tuple[Array, Array, Array, Array]:
        """``(p_att [Pa], mass error [1], mean gap [m], area at zeta_max [1])`` at ``p`` [Pa].

        The elastic contact at ``p`` is the closed form ``A = erf(p / (2 sqrt(tau)))`` (the
        core's exact path for an absorbing wall at ``0``), evaluated for all ``p`` at once.
        """
        from xpersson.physics.interface import detachment

        zeta, tau = self.curves[1 if coarse else 0]
        out = [np.empty(len(p)) for _ in range(4)]
        for s in range(0, len(p), CHUNK):
            pp = np.asarray(p[s : s + CHUNK], dtype=float)
            with np.errstate(divide="ignore"):
                x = pp[:, None] / (2.0 * np.sqrt(tau[None, :]))
            area = erf(x)
            det = detachment(self.psd, self.E_star, pp, zeta, area, non_area=erfc(x))
            if self.law == "lj93":
                pa, merr = attraction_quadrature(self.law, det, self.work, self.rng)
            else:
                pa, merr = attraction(self.law, det, self.work, self.rng), np.zeros(pp.size)
            for o, v in zip(out, (pa, merr, det.mean_gap, area[:, -1]), strict=True):
                o[s : s + CHUNK] = v
        if not coarse:
            self.evaluations += len(p)
        return out[0], out[1], out[2], out[3]

    def fill(self, nodes: list[tuple[int, int]]) -> int:
        """Evaluate the nodes ``(k, J)`` not yet known (one call); returns how many."""
        new = sorted({key(*n) for n in nodes} - set(self.values))
        if new:
            vals = self.exact(np.array([node_p(k, j) for k, j in new]))[0]
            self.values.update(zip(new, (float(v) for v in vals), strict=True))
        return len(new)

    def nodes(self, k: int) -> set[tuple[int, int]]:
        """Keys of the nodes evaluated for octave ``k``'s interpolant (all :data:`NMAX` + 1
        where it did not converge)."""
        n = self.degree.get(k, 0) or NMAX
        return {key(k, j) for j in range(0, NMAX + 1, NMAX // n)}

    def grid(self, k: int) -> float:
        """``p_att(2^k)`` [Pa] (must be known)."""
        return self.values[(k, NMAX)]

    # -- 1. bracket ----------------------------------------------------------------------------
    def octaves(self, p0: Array) -> tuple[NDArray[np.int64], list[set[tuple[int, int]]]]:
        """Per load, the octave ``k`` (``2^k <= root < 2^(k+1)`` [Pa]) of the largest root and
        the scan's nodes it rests on.

        Raises
        ------
        ValueError
        Tensile loads without a sign change within :data:`SCAN_DEPTH` octaves get octave
        :data:`LOST` (a compressive load's scan ends at ``p0``).
        """
        peak = max_traction(self.law, self.work, self.rng)
        top = np.array([math.ceil(math.log2(max(q, 0.0) + peak)) for q in p0])
        k = top - 1
        used: list[set[tuple[int, int]]] = [set() for _ in p0]
        todo = list(range(p0.size))
        while todo:
            # tensile, no sign change on the powers of two (compressive: the scan ends at p0);
            # the root may still lie between two of them: see near_pull_off
            lost = {i for i in todo if p0[i] <= 0 and top[i] - k[i] > SCAN_DEPTH}
            for i in lost:
                k[i] = LOST
            todo = [i for i in todo if i not in lost]
            if not todo:
                break
            # two octaves per round and load, all loads' pressures in one call
            self.fill(
                [(int(k[i]) - d, NMAX) for i in todo for d in (0, 1) if 2.0 ** (k[i] - d) > p0[i]]
            )
            still = []
            for i in todo:
                for _ in (0, 1):
                    p = 2.0 ** k[i]
                    if p <= p0[i]:
                        break
                    used[i].add((int(k[i]), NMAX))
                    if p - self.grid(int(k[i])) - p0[i] < 0:
                        break
                    k[i] -= 1
                else:
                    still.append(i)
            todo = still
        return k, used

    # -- 2. interpolate ------------------------------------------------------------------------
    def interpolant(self, octaves: list[int]) -> dict[int, Callable[[float], float]]:
        """Converged Chebyshev interpolants ``p [Pa] -> p_att [Pa]`` of the given octaves
        (``None`` where degree :data:`NMAX` does not meet the tolerance)."""
        pending = sorted(set(octaves) - set(self.degree))
        n = 4
        while pending and n <= NMAX:
            self.fill([(k, j) for k in pending for j in range(0, NMAX + 1, NMAX // n)])
            still = []
            for k in pending:
                if self._converged(k, n):
                    self.degree[k] = n
                else:
                    still.append(k)
            pending, n = still, 2 * n
        for k in pending:
            self.degree[k] = 0
        return {k: self._cheb(k, self.degree[k]) for k in set(octaves)}

    def _values(self, k: int, n: int) -> Array:
        return np.array([self.values[key(k, j)] for j in range(0, NMAX + 1, NMAX // n)])

    def _converged(self, k: int, n: int) -> bool:
        """The last three Chebyshev coefficients of the degree-``n`` interpolant are below
        ``rtol / 100`` of ``2^k`` [Pa] (the series has reached its tolerance or the map's
        noise floor, about ``1e-10`` relative for the ``lj93`` quadrature)."""
        c = _cheb_coefficients(self._values(k, n))
        return bool(np.max(np.abs(c[-3:])) <= 1e-2 * self.rtol * 2.0**k)

    def _cheb(self, k: int, n: int) -> Callable[[float], float] | None:
        if n == 0:
            return None
        c = _cheb_coefficients(self._values(k, n))
        mid, half = (k + 0.5) * math.log(2.0), 0.5 * math.log(2.0)

        def p_att(p: float) -> float:
            t = (math.log(p) - mid) / half  # [-1, 1] on the octave
            return float(np.polynomial.chebyshev.chebval(t, c))

        return p_att


def key(k: int, j: int) -> tuple[int, int]:
    """The cache key of node ``j`` of octave ``k``: an octave's upper end is the next
    octave's lower end ``(k + 1, NMAX)``."""
    return (k + 1, NMAX) if j == 0 else (k, j)


def node_p(k: int, j: int) -> float:
    """Pressure [Pa] of node ``j`` (of :data:`NMAX`) of octave ``k``: ``2^k`` at ``j = NMAX``,
    ``2^(k+1)`` at ``j = 0`` (exact powers of two), ``exp`` of the Lobatto point between."""
    if j == NMAX:
        return 2.0**k
    if j == 0:
        return 2.0 ** (k + 1)
    return math.exp((k + 0.5 + 0.5 * math.cos(math.pi * j / NMAX)) * math.log(2.0))


def _cheb_coefficients(values: Array) -> Array:
    """Chebyshev coefficients of the interpolant through values at ``cos(pi j / n)``."""
    n = values.size - 1
    j = np.arange(n + 1)
    w = np.where((j == 0) | (j == n), 0.5, 1.0)
    c = (2.0 / n) * np.cos(np.pi * np.outer(j, j) / n) @ (w * values)
    c[0] *= 0.5
    c[n] *= 0.5
    return c


def root_in_octave(p_att: Callable[[float], float], p0: float, k: int, rtol: float) -> float:
    """Largest ``p`` [Pa] in ``[2^k, 2^(k+1)]`` with ``p - p_att(p) = p0`` (Brent's method;
    ``g(2^k) < 0 <= g(2^(k+1))``)."""
    lo, hi = 2.0**k, 2.0 ** (k + 1)

    def g(p: float) -> float:
        return p - p0 - p_att(p)

    if g(lo) >= 0:  # the lower end at p0 itself (p_att = 0 there)
        return lo
    if g(hi) < 0:  # the upper end is the root (g = 0 there, the interpolant's rounding)
        return hi
    return float(brentq(g, lo, hi, xtol=1e-300, rtol=max(rtol, 4 * np.finfo(float).eps)))


def near_pull_off(amap: AttractionMap, p0: float) -> float:
    """The largest root ``p_rep`` [Pa] of a tensile ``p0`` [Pa] whose scan found no sign change
    on the powers of two: near pull-off, ``h(p) = p - p_att(p)`` dips below ``p0`` only between
    two of them. ``h`` is minimised (bounded Brent in ``ln p``, exact map) around the scanned
    power of two with the least ``h``; below ``p0`` there, the root is bracketed between the
    minimum and the next power of two above it, where ``h > p0`` (scanned).

    Raises
    ------
    ValueError
        ``min h >= p0``: the load is beyond pull-off (the message gives ``-min h``, the
        pull-off stress this search found).
    """
    from scipy.optimize import minimize_scalar

    def h(p: float) -> float:
        return p - float(amap.exact(np.array([p]))[0][0])

    scanned = [k for (k, j) in amap.values if j == NMAX]
    k_min = min(scanned, key=lambda k: 2.0**k - amap.values[(k, NMAX)])
    lo, hi = math.log(2.0 ** (k_min - 1)), math.log(2.0 ** (k_min + 1))
    res = minimize_scalar(
        lambda x: h(math.exp(x)), bounds=(lo, hi), method="bounded", options={"xatol": 1e-4}
    )
    p_min, h_min = math.exp(float(res.x)), float(res.fun)
    if not h_min < p0:
        raise ValueError(
            _beyond(p0, amap.law, amap.work, amap.rng) + f" (pull-off about {-h_min:.4g} Pa)"
        )
    top = math.exp(hi)
    return float(
        brentq(
            lambda p: h(p) - p0,
            p_min,
            top,
            xtol=1e-300,
            rtol=max(amap.rtol, 4 * np.finfo(float).eps),
        )
    )


def _beyond(p0: float, law: str, work: float, rng: float) -> str:
    return (
        f"load.p0 = {p0:g} Pa is beyond the DMT pull-off: no repulsive pressure "
        f"p_rep > 0 [Pa] balances p0 + p_att(p_rep) for law {law!r} "
        f"(work_of_adhesion = {work:g} J/m^2, range = {rng:g} m); allowed range: "
        "p0 above the pull-off stress"
    )


def solve_loads(amap: AttractionMap, p0: Array) -> dict[str, Array]:
    """Largest roots ``p_rep`` [Pa] of ``p_rep - p_att(p_rep) = p0`` for all loads ``p0`` [Pa].

    Returns the columns of :class:`~.dmt.DMTState` (``p_rep``, ``residual``, ``iterations``,
    ``mean_gap``, ``mass_error``, ``area``, ``discretization_error``), one entry per load.
    ``iterations`` counts the exact evaluations of ``p_att`` the load's root rests on (the
    scan down to its octave, the octave's interpolant, the check at the root; evaluations
    shared with other loads included: the count does not depend on them).

    Raises
    ------
    ValueError
        A load beyond pull-off (or ``p0 <= 0`` without adhesion).
    """
    p0 = np.asarray(p0, dtype=float)
    if amap.work == 0.0:
        if np.any(p0 <= 0):
            q = float(p0[p0 <= 0][0])
            raise ValueError(f"load.p0 = {q:g} Pa: the DMT contact needs p_rep > 0 Pa")
        k, slope = np.zeros(p0.size, dtype=np.int64), np.ones(p0.size)
        p_rep, cost = p0.copy(), np.zeros(p0.size, dtype=np.int64)
    else:
        k, used = amap.octaves(p0)
        lost = k == LOST
        cheb = amap.interpolant([int(x) for x in k[~lost]])
        cost = np.array(
            [
                len(u if ki == LOST else u | amap.nodes(int(ki)))
                for u, ki in zip(used, k, strict=True)
            ],
            dtype=np.int64,
        )
        p_rep, slope = np.full(p0.size, np.nan), np.full(p0.size, np.nan)
        for i in np.nonzero(lost)[0]:
            n0 = amap.evaluations
            p_rep[i] = near_pull_off(amap, float(p0[i]))  # Brent on the exact map
            slope[i] = np.inf  # no interpolant: the root is exact, not checked again
            cost[i] += amap.evaluations - n0
        for i, (q, ki) in enumerate(zip(p0, k, strict=True)):
            if lost[i]:
                continue
            f = cheb[int(ki)]
            if f is not None:
                p_rep[i] = root_in_octave(f, q, int(ki), amap.rtol)
                slope[i] = _slope(f, p_rep[i])
    ok = np.isfinite(p_rep)
    cols = [np.full(p0.size, np.nan) for _ in range(4)]  # p_att, mass error, mean gap, area
    for c, v in zip(cols, amap.exact(p_rep[ok]), strict=True):
        c[ok] = v
    cost += ok
    # error of p_rep estimated from the exact residual (Newton step on the interpolant)
    x_err = np.abs(p_rep - p0 - cols[0]) / np.maximum(np.abs(slope), 1e-300)
    for i in np.nonzero(~(x_err <= amap.rtol * p_rep))[0]:
        n0 = amap.evaluations
        p_rep[i] = root_in_octave(
            lambda p: float(amap.exact(np.array([p]))[0][0]), p0[i], int(k[i]), amap.rtol
        )
        for c, v in zip(cols, amap.exact(p_rep[i : i + 1]), strict=True):
            c[i] = v[0]
        cost[i] += amap.evaluations - n0
    p_att, mass, gap, area = cols
    disc = np.zeros(p0.size)
    if amap.work > 0:
        coarse = amap.exact(p_rep, coarse=True)[0]
        disc = np.abs(coarse - p_att) / np.maximum(p_att, 1e-300)
    return {
        "p_rep": p_rep,
        "residual": np.abs(p_rep - p0 - p_att) / np.maximum(np.abs(p0), p_rep),
        "iterations": cost,
        "mean_gap": gap,
        "mass_error": mass,
        "area": area,
        "discretization_error": disc,
    }


def _slope(p_att: Callable[[float], float] | None, p: float) -> float:
    """``d(p - p_att)/dp`` [1] of the interpolant at ``p`` [Pa] (central difference)."""
    if p_att is None:
        return float("nan")
    h = 1e-4 * p
    return 1.0 - (p_att(p + h) - p_att(p - h)) / (2.0 * h)
