"""The isotropic PSD of a measured height map or line scan, keeping the map's own roughness.

Pure numpy, SI units (heights and lengths in m, wavevectors in 1/m, C in m^4, Persson's
convention). The estimator (docs: "From a measured surface"):

1. **Rings of modes** (:func:`map_rings`, periodic maps): the discrete Fourier transform gives
   each wavevector ``k`` of the map the variance ``v_k = |h_k|^2`` (``sum v_k`` is the map's
   variance, Parseval) and the mean-square gradient ``|k|^2 v_k`` (the spectral derivative).
   The modes are grouped into logarithmic rings of ``|k|``; each mode owns the cell
   ``(2 pi)^2 / A`` of wavevector space (``A`` the map's area), and a ring of ``M`` modes is
   the annulus of area ``M (2 pi)^2 / A`` (equal measure, the mean's own cell a disk at the
   centre). The PSD of a ring is then its mean variance density, unbiased for an isotropic
   surface even where the rings hold a handful of modes; the table starts at the mean's cell,
   ``q_0 = 2 pi / sqrt(pi A)`` (0.56 times ``2 pi / L`` for a square map), where the cells of
   the ``|k| = 2 pi / L`` modes begin.
2. **The table** (:func:`table_from_rings`): one node at the log-centre of each ring, plus the
   ring system's two ends; the values are set so that the table's integral
   ``2 pi int q C dq`` over every ring equals the ring's variance (fixed-point iteration),
   then multiplied by a power law ``a (q / q_g)^b`` so that the table's mean-square height and
   gradient, integrated as the engine integrates them (piecewise power law), equal the map's
   exactly (``b`` is a few 1e-3: the modes' ``|k|^2`` within a ring).

The map's variance and slope are kept to round-off; each ring's variance to a few 1e-3; the
scatter of a measured ring is the periodogram's, ``1 / sqrt(modes)`` relative.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ._tabulated import Tabulated

__all__ = ["Rings", "map_rings", "profile_rings", "table_from_rings", "combine_tables"]

#: A mode (or trailing ring) whose share of the variance is below this is FFT round-off.
ROUND_OFF = 1e-20


@dataclass(frozen=True)
class Rings:
    """Logarithmic rings of wavevectors and the variance each carries.

    Attributes
    ----------
    edges : ndarray
        Ring edges [1/m], ``n + 1`` values, strictly increasing; ``edges[0]`` is the smallest
        wavevector, ``edges[-1]`` the largest with power.
    var : ndarray
        Variance of the heights in each ring [m^2] (> 0).
    modes : ndarray
        Number of Fourier modes in each ring (0 where the ring comes from a binned PSD).
    h2, s2 : float
        The whole map's mean-square height [m^2] and mean-square (2-D) gradient [1].
    centre : ndarray or None
        Where each ring's PSD is placed [1/m]: the geometric mean of its modes' ``|k|``
        (kept inside the ring); ``None``: the ring's log-centre.
    """

    edges: NDArray[np.float64]
    var: NDArray[np.float64]
    modes: NDArray[np.int64]
    h2: float
    s2: float
    centre: NDArray[np.float64] | None = None


def _ring_index(k: NDArray[np.float64], k0: float, ppd: int) -> NDArray[np.intp]:
    return np.floor(ppd * np.log10(k / k0) + 1e-9).astype(np.intp)


def _cell_edge(count: NDArray[np.float64], cell: float, dim: int) -> NDArray[np.float64]:
    """The wavevector [1/m] enclosing ``count`` modes (the mean included), each owning the
    measure ``cell`` of wavevector space: ``pi q^2 = count cell`` (2-D), ``q = (count - 1/2)
    cell`` (1-D: ``+k`` and ``-k`` each own ``cell``, half the spacing of the modes)."""
    if dim == 2:
        return np.sqrt(count * cell / np.pi)
    return count * cell


def _rings_of_modes(
    k: NDArray[np.float64], v: NDArray[np.float64], ppd: int, cell: float, dim: int
) -> Rings:
    """Rings of the modes ``k`` [1/m] with variances ``v`` [m^2] (zero-power tail cut).

    Each ring holds the modes whose ``|k|`` falls in one logarithmic bin; its edges are the
    wavevectors enclosing as many cells as there are modes below (equal measure), so that the
    mean variance density of a ring, ``var / (modes cell)``, is the ring's PSD.
    """
    keep = k > 0
    k, v = k[keep], v[keep]
    total = float(v.sum())
    if not total > 0:
        raise ValueError("the heights are constant (no roughness)")
    k_top = float(k[v > ROUND_OFF * total].max())
    inside = k <= k_top
    k, v = k[inside], v[inside]
    idx = _ring_index(k, float(k.min()), ppd)
    used, ring = np.unique(idx, return_inverse=True)
    var = np.bincount(ring, weights=v)
    modes = np.bincount(ring)
    below = np.concatenate(([1.0], 1.0 + np.cumsum(modes)))  # the mean's own cell first
    edges = _cell_edge(below, cell, dim)
    centre = np.exp(np.bincount(ring, weights=np.log(k)) / modes)
    centre = np.clip(centre, edges[:-1] * 1.001, edges[1:] / 1.001)
    s2 = float((k**2 * v).sum())
    return Rings(edges, var, modes.astype(np.int64), float(v.sum()), s2, centre)


def map_rings(heights: NDArray[np.float64], sizes: tuple[float, float], ppd: int) -> Rings:
    """Rings of a periodic height map (mean removed; Parseval and the spectral gradient).

    Parameters
    ----------
    heights : ndarray
        ``(nx, ny)`` heights [m] of a periodic map.
    sizes : tuple of float
        Physical sizes ``(Lx, Ly)`` [m].
    ppd : int
        Rings per decade of wavevector.
    """
    h = np.asarray(heights, float)
    nx, ny = h.shape
    v = np.abs(np.fft.fft2(h - h.mean()) / h.size) ** 2
    kx = 2 * np.pi * np.fft.fftfreq(nx, sizes[0] / nx)
    ky = 2 * np.pi * np.fft.fftfreq(ny, sizes[1] / ny)
    k = np.hypot(kx[:, None], ky[None, :])
    cell = (2 * np.pi) ** 2 / (sizes[0] * sizes[1])
    return _rings_of_modes(k.ravel(), v.ravel(), ppd, cell, 2)


def profile_rings(heights: NDArray[np.float64], length: float, ppd: int) -> Rings:
    """Rings of an isotropic surface seen through a periodic line scan (2-D, Persson).

    The scan's variance in the band ``a <= |q_x| < b`` is the isotropic PSD integrated over
    the strip ``a <= |q_x| < b`` of the plane (the Abel-type relation between the 1-D and the
    2-D spectrum). With a constant PSD on each ring, this is a triangular linear system
    (the areas of annulus-strip intersections, in closed form), solved for non-negative ring
    densities (``scipy.optimize.nnls``). The totals are the scan's variance and twice its
    mean-square profile slope (an isotropic surface's mean-square 2-D gradient).

    Parameters
    ----------
    heights : ndarray
        ``(n,)`` heights [m] of a periodic line scan, or ``(m, n)``: ``m`` parallel scans
        (their periodograms averaged).
    length : float
        Scan length [m].
    ppd : int
        Rings per decade of wavevector.
    """
    h = np.atleast_2d(np.asarray(heights, float))
    n = h.shape[1]
    v = np.mean(np.abs(np.fft.fft(h - h.mean(axis=1, keepdims=True), axis=1) / n) ** 2, axis=0)
    k = np.abs(2 * np.pi * np.fft.fftfreq(n, length / n))
    r1 = _rings_of_modes(k, v, ppd, np.pi / length, 1)
    from scipy.optimize import nnls  # noqa: PLC0415 - scipy.optimize only for line scans

    e = r1.edges
    area = np.pi * (e[1:] ** 2 - e[:-1] ** 2)
    density = nnls(_strip_areas(e) / area, r1.var / r1.var.sum())[0] * r1.var.sum()
    if not np.any(density > 0):
        raise ValueError("the line scan's spectrum has no isotropic counterpart")
    keep = density > 0  # rings the inversion leaves empty: merged into the ring below
    keep[0] = True
    var = np.add.reduceat(density, np.flatnonzero(keep))
    edges = np.append(e[:-1][keep], e[-1])
    var = np.maximum(var, ROUND_OFF * var.sum())
    modes = np.add.reduceat(r1.modes, np.flatnonzero(keep))
    return Rings(edges, var, modes, r1.h2, 2.0 * r1.s2)


def _disk_strip(x: NDArray[np.float64], r: NDArray[np.float64]) -> NDArray[np.float64]:
    """Area of ``{|q| < r, |q_x| < x}`` (element-wise, ``x, r >= 0``)."""
    t = np.minimum(x, r)
    return 2.0 * (t * np.sqrt(np.maximum(r**2 - t**2, 0.0)) + r**2 * np.arcsin(t / r))


def _strip_areas(e: NDArray[np.float64]) -> NDArray[np.float64]:
    """``A[i, j]``: area of the annulus ``e[j] <= |q| < e[j+1]`` within the strips
    ``e[i] <= |q_x| < e[i+1]`` (both signs of ``q_x``, all ``q_y``) [1/m^2]."""
    a, b = e[:-1, None], e[1:, None]
    lo, hi = e[None, :-1], e[None, 1:]
    return _disk_strip(b, hi) - _disk_strip(a, hi) - _disk_strip(b, lo) + _disk_strip(a, lo)


def _ring_integrals(table: Tabulated, edges: NDArray[np.float64]) -> NDArray[np.float64]:
    run = np.asarray(table.running_moment(1.0, edges), float)
    return 2.0 * np.pi * np.diff(run)


def _nodes_values(rings: Rings, centre_C: NDArray[np.float64]) -> tuple[NDArray, NDArray]:
    """Nodes (edges' ends and ring centres) and values (ends extrapolated log-log)."""
    e = rings.edges
    centre = np.sqrt(e[:-1] * e[1:]) if rings.centre is None else rings.centre
    q = np.concatenate(([e[0]], centre, [e[-1]]))
    lc = np.log(centre_C)
    if centre.size > 1:
        lq = np.log(centre)
        lo = lc[0] + np.clip((lc[1] - lc[0]) / (lq[1] - lq[0]), -8, 4) * (math.log(e[0]) - lq[0])
        hi = lc[-1] + np.clip((lc[-1] - lc[-2]) / (lq[-1] - lq[-2]), -8, 4) * (
            math.log(e[-1]) - lq[-1]
        )
    else:
        lo = hi = lc[0]
    return q, np.exp(np.concatenate(([lo], lc, [hi])))


def table_from_rings(
    rings: Rings, iterations: int = 200, rtol: float = 1e-10, low_end: bool = False
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """A piecewise power-law table (Persson, SI) that keeps every ring's variance and the
    whole map's mean-square height and gradient.

    Parameters
    ----------
    rings : Rings
        From :func:`map_rings` or :func:`profile_rings`.
    iterations, rtol
        Of the fixed-point iteration on the ring integrals.
    low_end : bool
        Match the totals with an amplitude and the first ring's own factor instead of the
        power-law tilt (a line scan: its first ring, ``q < 3 pi / L``, carries the
        difference between the isotropic surface's variance and the profile's, which misses
        the modes with ``|q_x| < pi / L``; the shape above is kept).

    Returns
    -------
    q, C : ndarray
        Nodes [1/m] (``q[0] = edges[0]``, ``q[-1] = edges[-1]``) and values [m^4].
    """
    e, var = rings.edges, rings.var
    area = np.pi * (e[1:] ** 2 - e[:-1] ** 2)
    c = var / area
    for _ in range(iterations):
        q, C = _nodes_values(rings, c)
        got = _ring_integrals(Tabulated(q, C), e)
        ratio = var / got
        c = c * ratio
        if np.max(np.abs(ratio - 1.0)) < rtol:
            break
    q, C = _nodes_values(rings, c)
    if low_end:
        fitted = _low_end(q, C, rings.h2, rings.s2)
        if fitted is not None:
            return q, fitted
    return q, _tilt(Tabulated(q, C), rings.h2, rings.s2)


def _low_end(
    q: NDArray[np.float64], C: NDArray[np.float64], h2: float, s2: float
) -> NDArray[np.float64] | None:
    """``C`` scaled by ``a`` with its first ring (two nodes) by a further ``f``: the mean-square
    gradient ``s2`` [1] and height ``h2`` [m^2] exactly, the shape above the first ring kept.
    ``None`` when no ``f`` in (1e-6, 1e6) does it."""
    from scipy.optimize import brentq  # noqa: PLC0415 - only when a map is read

    first = np.zeros(q.size, bool)
    first[:2] = True

    def scaled(log_f: float) -> NDArray[np.float64]:
        out = np.where(first, C * math.exp(log_f), C)
        table = Tabulated(q, out)
        return np.asarray(out * s2 / (2 * np.pi * table.moment(3.0)), float)

    def gap(log_f: float) -> float:
        return math.log(2 * np.pi * Tabulated(q, scaled(log_f)).moment(1.0) / h2)

    lo, hi = math.log(1e-6), math.log(1e6)
    if not gap(lo) < 0 < gap(hi):
        return None
    return scaled(brentq(gap, lo, hi, xtol=1e-12))


def _tilt(table: Tabulated, h2: float, s2: float) -> NDArray[np.float64]:
    """``C a (q/q_g)^b``: the table's ``2 pi m_1 = h2`` and ``2 pi m_3 = s2`` exactly."""
    from scipy.optimize import brentq  # noqa: PLC0415 - only when a map is read

    q, C = table.q_table, table.C_table
    qg = math.sqrt(q[0] * q[-1])
    target = math.log(s2 / h2) - 2.0 * math.log(qg)

    def gap(b: float) -> float:
        return math.log(table.moment(3.0 + b) / table.moment(1.0 + b)) - 2 * math.log(qg) - target

    b = brentq(gap, -2.0, 2.0, xtol=1e-14) if gap(-2.0) * gap(2.0) < 0 else 0.0
    a = h2 / (2.0 * np.pi * table.moment(1.0 + b) * qg ** (-b))
    return np.asarray(C * a * (q / qg) ** b, float)


def combine_tables(
    tables: list[tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]],
    ppd: int,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """One table from several scans' tables of one surface.

    Parameters
    ----------
    tables : list of (q, C, weight)
        Each scan's nodes [1/m], values [m^4] and the weight of each node (its ring's number
        of Fourier modes; the scatter of a ring average falls as ``1 / sqrt(modes)``).
    ppd : int
        Nodes per decade of the combined table.

    Returns
    -------
    q, C : ndarray
        On a log grid from the smallest to the largest wavevector of all scans; where bands
        overlap, the scan with the most modes at that wavevector (the better-resolved
        estimate: the larger scan, up to the end of its band) gives ``C``, interpolated
        log-log on its own nodes.
    """
    lo = min(float(t[0][0]) for t in tables)
    hi = max(float(t[0][-1]) for t in tables)
    n = max(2, int(math.ceil(ppd * math.log10(hi / lo))) + 1)
    q = np.geomspace(lo, hi, n)
    best = np.zeros(n)
    out = np.full(n, np.nan)
    for tq, tc, tw in tables:
        inside = (q >= tq[0] * (1 - 1e-12)) & (q <= tq[-1] * (1 + 1e-12))
        lq = np.log(np.clip(q[inside], tq[0], tq[-1]))
        w = np.interp(lq, np.log(tq), tw)
        wins = w > best[inside]
        idx = np.flatnonzero(inside)[wins]
        out[idx] = np.exp(np.interp(lq[wins], np.log(tq), np.log(tc)))
        best[idx] = w[wins]
    if np.any(np.isnan(out)):
        gap = q[np.isnan(out)]
        raise ValueError(
            f"the scans leave a gap in wavevector: no scan covers {gap[0]:.4g} to {gap[-1]:.4g} 1/m"
        )
    return q, out
