"""Attractive traction-gap laws and their integral over the gap distribution (physics.md §2.3).

Each law ``sigma(u) >= 0`` [Pa] (attraction positive, ``u`` [m] the gap measured from contact)
integrates to the work of adhesion, ``int_0^inf sigma du = dgamma`` [J/m^2]; ``dr`` [m] is its
range:

* ``dugdale``: ``sigma = dgamma/dr`` for ``u < dr``, 0 beyond;
* ``exponential``: ``sigma = (dgamma/dr) exp(-u/dr)``;
* ``lj93``: the 9-3 Lennard-Jones law with equilibrium distance ``dr``, ``s = dr/(dr + u)``:
  ``sigma = (8 dgamma/(3 dr)) (s^3 - s^9)`` (zero in contact, maximum ``1.026 dgamma/dr``).

The attraction acts in the gaps only (the continuous part ``rho(u)`` of the gap distribution,
``u > 0``); in the contact area the surfaces are at equilibrium and the interaction belongs to
the repulsive contact (DMT). The attractive nominal stress is ``p_att = int_0^inf sigma rho du``.
``rho`` is a sum of mirrored Gaussians (one per detachment bin, weight ``w``, centre ``u1``,
width ``h``): Dugdale and exponential laws are integrated bin by bin in closed form; every law
also has a composite Gauss-Legendre rule on geometric panels in ``u`` (the ``lj93`` path and a
cross-check), whose mass ``int rho du`` is compared with ``1 - A(zeta_max)`` as a quadrature
diagnostic. As ``dr -> 0`` at fixed ``dgamma`` every law concentrates at ``u = 0`` and
``p_att -> dgamma rho(0+)``; at fixed maximum traction (``dgamma ~ dr``) ``p_att -> 0``.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.special import erfc, erfcx

from xpersson.physics.interface import Detachment, gap_cdf

__all__ = ["LAWS", "traction", "max_traction", "attraction", "attraction_quadrature"]

Array = NDArray[np.float64]
LAWS = ("dugdale", "lj93", "exponential")
_LJ_PEAK = (8.0 / 3.0) * (2.0 / 3.0) / math.sqrt(3.0)  # max of (8/3)(s^3 - s^9): 1.0264
_GL_X, _GL_W = np.polynomial.legendre.leggauss(8)
_GL_X, _GL_W = 0.5 * (_GL_X + 1.0), 0.5 * _GL_W  # 8-point Gauss-Legendre on [0, 1]


def traction(law: str, u: ArrayLike, work: float, rng: float) -> Array:
    """Attractive traction ``sigma(u)`` [Pa] at gaps ``u`` [m] (``work`` J/m^2, ``rng`` m)."""
    u = np.asarray(u, dtype=float)
    scale = work / rng
    if law == "dugdale":
        return np.where((u >= 0) & (u < rng), scale, 0.0)
    if law == "exponential":
        return np.where(u >= 0, scale * np.exp(-np.maximum(u, 0.0) / rng), 0.0)
    if law == "lj93":
        s = rng / (rng + np.maximum(u, 0.0))
        return np.where(u >= 0, (8.0 / 3.0) * scale * (s**3 - s**9), 0.0)
    raise ValueError(f"boundary.law = {law!r}: must be one of {', '.join(LAWS)}")


def max_traction(law: str, work: float, rng: float) -> float:
    """Largest traction of the law [Pa]: an upper bound of ``p_att``."""
    return (_LJ_PEAK if law == "lj93" else 1.0) * work / rng


def _exp_bins(det: Detachment, rng: float) -> Array:
    """``int_0^inf exp(-u/rng) [N(u; u1, h) + N(u; -u1, h)] du`` per load and bin [1]."""
    m = det.u1
    h = np.maximum(det.h, 1e-300)[None, :]
    lam = rng
    a = (h / lam - m / h) / math.sqrt(2.0)
    b = (h / lam + m / h) / math.sqrt(2.0)
    with np.errstate(under="ignore", over="ignore"):
        gauss = np.exp(-0.5 * (m / h) ** 2)
        near = np.where(
            a >= 0,
            0.5 * gauss * erfcx(np.maximum(a, 0.0)),
            0.5 * np.exp(np.minimum(-m / lam + 0.5 * (h / lam) ** 2, 0.0)) * erfc(np.minimum(a, 0)),
        )
        mirror = 0.5 * gauss * erfcx(b)
    return near + mirror


def attraction(law: str, det: Detachment, work: float, rng: float) -> Array:
    """Attractive nominal stress ``p_att`` [Pa] per load (closed forms where they exist)."""
    scale = work / rng
    if law == "dugdale":
        return scale * gap_cdf(det, [rng])[:, 0]
    if law == "exponential":
        return scale * np.sum(det.weight * _exp_bins(det, rng), axis=1)
    return attraction_quadrature(law, det, work, rng)[0]


def attraction_quadrature(
    law: str, det: Detachment, work: float, rng: float, per_decade: int = 6, window: int = 12
) -> tuple[Array, Array]:
    """``p_att`` [Pa] by per-bin Gauss-Legendre rules, and the mass error of the rule [1].

    Bin ``k`` contributes ``w_k int_0^inf sigma(u) [N(u; u1, h) + N(u; -u1, h)] du``, integrated
    over its Gaussian window ``[max(0, u1 - 9h), u1 + 9h]`` (outside, the density is below
    ``e^-40``). The window's panels are the union of ``window`` equal panels (the Gaussian) and
    the law's panels ``{0} + rng * geomspace(1e-3, 1e4)`` (``per_decade`` per decade) clipped to
    the window, 8 Gauss-Legendre nodes each. Bins narrower than ``1e-9 rng`` are deltas.
    Bins of zero weight and panels of zero width (law edges clipped to the window) add nothing
    and are skipped (about 8x less work than the full ``(n_load, n_bin, n_panel, 8)`` array).

    Returns
    -------
    p_att : ndarray, (n_load,)
        Attractive stress [Pa].
    mass_error : ndarray, (n_load,)
        ``int rho du - (1 - A(zeta_max))`` on the same rule [1].
    """
    m = det.u1  # (n_load, n_bin)
    weight = np.broadcast_to(det.weight, m.shape)
    h_bin = np.broadcast_to(det.h[None, :], m.shape)
    delta = h_bin < 1e-9 * rng
    # bins of zero weight contribute nothing: only the others are integrated
    row, col = np.nonzero((weight != 0.0) & ~delta)
    val, mass = _window_integrals(law, m[row, col], h_bin[row, col], work, rng, per_decade, window)
    p_att = np.zeros(m.shape[0])
    mass_error = np.zeros(m.shape[0])
    np.add.at(p_att, row, weight[row, col] * val)
    np.add.at(mass_error, row, weight[row, col] * (mass - 1.0))
    drow, dcol = np.nonzero(delta & (weight != 0.0))
    with np.errstate(over="ignore", under="ignore"):
        np.add.at(p_att, drow, weight[drow, dcol] * _sigma(law, m[drow, dcol], work, rng))
    return p_att, mass_error


def _sigma(law: str, u: Array, work: float, rng: float) -> Array:
    """:func:`traction` [Pa] at gaps ``u >= 0`` [m] (products instead of powers for ``lj93``)."""
    if law != "lj93":
        return traction(law, u, work, rng)
    s = rng / (rng + u)
    s3 = s * s * s
    return (8.0 / 3.0) * (work / rng) * (s3 - s3 * s3 * s3)


def _window_integrals(
    law: str, m: Array, h: Array, work: float, rng: float, per_decade: int, window: int
) -> tuple[Array, Array]:
    """Per bin (centre ``m``, width ``h`` [m], 1-d): ``int sigma psi du`` [Pa] and
    ``int psi du`` [1] on the rule of :func:`attraction_quadrature`, its panels of zero width
    (law edges clipped to the window) skipped."""
    h = np.maximum(h, 1e-300)
    a = np.maximum(m - 9.0 * h, 0.0)
    b = m + 9.0 * h
    law_edges = np.concatenate(([0.0], rng * np.geomspace(1e-3, 1e4, 7 * per_decade + 1)))
    clipped = np.clip(law_edges, a[:, None], b[:, None])
    win = a[:, None] + (b - a)[:, None] * np.linspace(0.0, 1.0, window + 1)
    edges = np.sort(np.concatenate([clipped, win], axis=-1), axis=-1)
    lo, hi = edges[:, :-1], edges[:, 1:]
    pi, pj = np.nonzero(hi > lo)
    lo, width = lo[pi, pj][:, None], (hi - lo)[pi, pj][:, None]
    u = lo + width * _GL_X  # (n_panel, 8)
    hh, mm = h[pi][:, None], m[pi][:, None]
    with np.errstate(under="ignore", over="ignore"):
        psi = np.exp(-0.5 * ((u - mm) / hh) ** 2)
        # the mirror Gaussian at u >= 0 is below exp(-800) = 0.0 where u1 > 40 h: skipped
        near = np.nonzero(m[pi] < 40.0 * h[pi])[0]
        psi[near] += np.exp(-0.5 * ((u[near] + mm[near]) / hh[near]) ** 2)
        psi *= width * _GL_W / (math.sqrt(2.0 * math.pi) * hh)
    n = m.size
    mass = np.bincount(pi, weights=psi.sum(axis=1), minlength=n)
    val = np.bincount(pi, weights=(psi * _sigma(law, u, work, rng)).sum(axis=1), minlength=n)
    return val, mass
