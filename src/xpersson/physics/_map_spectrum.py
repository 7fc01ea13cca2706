"""The isotropic PSD of a measured height map or line scan, keeping the map's own roughness.

Pure numpy, SI units (heights and lengths in m, wavevectors in 1/m, C in m^4, Persson's
convention). The estimator (docs: "From a measured surface"):

1. **Rings of modes** (:func:`map_rings`, periodic maps): the discrete Fourier transform gives
   each wavevector ``k`` of the map the variance ``v_k = |h_k|^2`` (``sum v_k`` is the map's
   variance, Parseval) and the mean-square gradient ``|k|^2 v_k`` (the spectral derivative).
   The modes are grouped into logarithmic rings starting at the smallest ``|k|`` (``q_L =
   2 pi / L``); empty rings are merged into the ring below.
2. **The table** (:func:`table_from_rings`): one node at the log-centre of each ring, plus the
   ring system's two ends (``q_L`` and the largest ``|k|`` with power); the values are set so
   that the table's integral ``2 pi int q C dq`` over every ring equals the ring's variance
   (fixed-point iteration), then multiplied by a power law ``a (q / q_g)^b`` so that the
   table's mean-square height and gradient, integrated as the engine integrates them
   (piecewise power law), equal the map's exactly.

The map's variance and slope are kept to round-off; what the table shows in each ring is the
mean variance density of the ring's modes (unbiased for an isotropic surface, with the
periodogram's scatter: relative error ``1/sqrt(modes)`` per ring). The first ring (the |k| = 1
modes, four of them) keeps its whole variance on ``[q_L, q_L 10^(1/ppd)]``, so its C is higher
than a continuum estimate would put there; its slope share is exact within the tilt.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import brentq

from ._spectrum import _TWO_PI_SQ, profile_factor
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
    """

    edges: NDArray[np.float64]
    var: NDArray[np.float64]
    modes: NDArray[np.int64]
    h2: float
    s2: float


def _ring_index(k: NDArray[np.float64], k0: float, ppd: int) -> NDArray[np.intp]:
    return np.floor(ppd * np.log10(k / k0) + 1e-9).astype(np.intp)


def _rings_of_modes(k: NDArray[np.float64], v: NDArray[np.float64], ppd: int) -> Rings:
    """Rings of the modes ``k`` [1/m] with variances ``v`` [m^2] (zero-power tail cut)."""
    keep = k > 0
    k, v = k[keep], v[keep]
    total = float(v.sum())
    if not total > 0:
        raise ValueError("the heights are constant (no roughness)")
    powered = v > ROUND_OFF * total
    k_top = float(k[powered].max())
    inside = k <= k_top
    k, v = k[inside], v[inside]
    k0 = float(k.min())
    idx = _ring_index(k, k0, ppd)
    used = np.unique(idx)
    var = np.bincount(np.searchsorted(used, idx), weights=v)
    modes = np.bincount(np.searchsorted(used, idx))
    ring = np.searchsorted(used, idx)
    k_lo = np.full(used.size, np.inf)
    k_hi = np.zeros(used.size)
    np.minimum.at(k_lo, ring, k)
    np.maximum.at(k_hi, ring, k)
    if used.size > 1 and k_hi[-1] == k_lo[-1]:  # one shell alone on top: merge it below
        var[-2] += var[-1]
        modes[-2] += modes[-1]
        k_hi[-2] = k_hi[-1]
        var, modes, k_lo, k_hi = var[:-1], modes[:-1], k_lo[:-1], k_hi[:-1]
    # edges in the middle (log) of the gaps between the rings' modes; the ends at the modes
    edges = np.concatenate(([k0], np.sqrt(k_hi[:-1] * k_lo[1:]), [k_top]))
    return Rings(edges, var, modes.astype(np.int64), float(v.sum()), float((k**2 * v).sum()))


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
    hk = np.fft.rfft2(h - h.mean()) / h.size
    v = np.abs(hk) ** 2
    v[:, 1:] *= 2.0  # the rfft's half plane: every column but q_y = 0 (and Nyquist) twice
    if ny % 2 == 0:
        v[:, -1] /= 2.0
    kx = 2 * np.pi * np.fft.fftfreq(nx, sizes[0] / nx)
    ky = 2 * np.pi * np.fft.rfftfreq(ny, sizes[1] / ny)
    k = np.hypot(kx[:, None], ky[None, :])
    return _rings_of_modes(k.ravel(), v.ravel(), ppd)


def profile_rings(heights: NDArray[np.float64], length: float, ppd: int) -> Rings:
    """Rings of an isotropic surface seen through a periodic line scan (2-D, Persson).

    The scan's 1-D periodogram (JJP convention, ``C1D``) is binned in rings; each ring's 2-D
    density is ``C_iso = C1D / (K(H) q (2 pi)^2)`` with the local Hurst exponent of the binned
    ``C1D`` (:func:`~xpersson.physics.psd.profile_factor`: the inverse of the Abel-type
    relation ``C1D(q_x) = int dq_y C_iso(|q|)``, exact for a power law), and the whole
    is normalised to the scan's variance and to twice its mean-square profile slope (an
    isotropic surface's 2-D gradient).

    Parameters
    ----------
    heights : ndarray
        ``(n,)`` heights [m] of a periodic line scan.
    length : float
        Scan length [m].
    ppd : int
        Rings per decade of wavevector.
    """
    h = np.asarray(heights, float)
    n = h.size
    hk = np.fft.rfft(h - h.mean()) / n
    v = np.abs(hk) ** 2
    v[1:] *= 2.0
    if n % 2 == 0:
        v[-1] /= 2.0
    k = 2 * np.pi * np.fft.rfftfreq(n, length / n)
    r1 = _rings_of_modes(k, v, ppd)
    dk = 2 * np.pi / length
    width = np.maximum(np.diff(r1.edges), dk)
    c1d = np.pi * r1.var / width  # JJP: h^2 = (1/pi) int C1D dq
    centre = np.sqrt(r1.edges[:-1] * r1.edges[1:])
    if centre.size > 2:
        slope = np.gradient(np.log(c1d), np.log(centre), edge_order=1)
    else:
        slope = np.full(centre.size, -2.0)
    h_loc = np.clip(-(1.0 + slope) / 2.0, 0.0, 1.0)
    c_iso = c1d / (profile_factor(h_loc) * centre) / _TWO_PI_SQ
    var = c_iso * np.pi * (r1.edges[1:] ** 2 - r1.edges[:-1] ** 2)
    return Rings(r1.edges, var, r1.modes, r1.h2, 2.0 * r1.s2)


def _ring_integrals(table: Tabulated, edges: NDArray[np.float64]) -> NDArray[np.float64]:
    run = np.asarray(table.running_moment(1.0, edges), float)
    return 2.0 * np.pi * np.diff(run)


def _nodes_values(rings: Rings, centre_C: NDArray[np.float64]) -> tuple[NDArray, NDArray]:
    """Nodes (edges' ends and ring centres) and values (ends extrapolated log-log)."""
    e = rings.edges
    centre = np.sqrt(e[:-1] * e[1:])
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
    rings: Rings, iterations: int = 200, rtol: float = 1e-10
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """A piecewise power-law table (Persson, SI) that keeps every ring's variance and the
    whole map's mean-square height and gradient.

    Parameters
    ----------
    rings : Rings
        From :func:`map_rings` or :func:`profile_rings`.
    iterations, rtol
        Of the fixed-point iteration on the ring integrals.

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
    return q, _tilt(Tabulated(q, C), rings.h2, rings.s2)


def _tilt(table: Tabulated, h2: float, s2: float) -> NDArray[np.float64]:
    """``C a (q/q_g)^b``: the table's ``2 pi m_1 = h2`` and ``2 pi m_3 = s2`` exactly."""
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
        overlap, ``log C`` is the weighted mean of the scans that cover the point (each
        interpolated log-log on its own band).
    """
    lo = min(float(t[0][0]) for t in tables)
    hi = max(float(t[0][-1]) for t in tables)
    n = max(2, int(math.ceil(ppd * math.log10(hi / lo))) + 1)
    q = np.geomspace(lo, hi, n)
    num = np.zeros(n)
    den = np.zeros(n)
    for tq, tc, tw in tables:
        inside = (q >= tq[0] * (1 - 1e-12)) & (q <= tq[-1] * (1 + 1e-12))
        lq = np.log(np.clip(q[inside], tq[0], tq[-1]))
        w = np.interp(lq, np.log(tq), tw)
        num[inside] += w * np.interp(lq, np.log(tq), np.log(tc))
        den[inside] += w
    if np.any(den == 0):
        gap = q[den == 0]
        raise ValueError(
            f"the scans leave a gap in wavevector: no scan covers {gap[0]:.4g} to {gap[-1]:.4g} 1/m"
        )
    return q, np.exp(num / den)
