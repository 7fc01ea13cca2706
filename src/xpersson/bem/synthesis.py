"""Periodic Gaussian surfaces with a given isotropic power spectrum (Persson's convention).

Persson's spectrum ``C(q)`` [m^4] is normalised so that ``<h^2> = int d^2q C(q)`` (it is the
Fourier transform of the height autocorrelation divided by ``(2 pi)^2``). On a periodic cell
of side ``L`` the wavevectors are ``q = 2 pi k / L`` (``k`` integer pairs), each occupying an
area ``(2 pi / L)^2`` of the ``q`` plane, so the Fourier amplitude ``a_k`` of the mode ``k``
(``h(x) = sum_k a_k exp(i q.x)``) has the variance ``<|a_k|^2> = C(|q|) (2 pi / L)^2`` and
``<h^2> = sum_k C(|q_k|) (2 pi / L)^2 -> int d^2q C(q)``. The phases are those of a white
real noise field, so the map is real and Gaussian.

A macroscopic shape (a sphere, a cylinder, a wavy profile) is added by the caller to the
synthesised map: :func:`xpersson.bem.solve` takes any height map.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

__all__ = [
    "wavenumbers",
    "synthesise",
    "map_moments",
    "discrete_moments",
    "spectrum_moments",
]

Spectrum = Callable[[np.ndarray], np.ndarray]


def wavenumbers(L: float, n: int) -> np.ndarray:
    """Moduli ``|q|`` [1/m] of the FFT modes of an ``n x n`` periodic cell of side ``L`` [m].

    Returns an ``(n, n)`` array in numpy's FFT order (``q = 0`` at ``[0, 0]``).
    """
    q = 2.0 * math.pi * np.fft.fftfreq(n, d=L / n)
    return np.hypot(q[:, None], q[None, :])


def _band(L: float, n: int, q_min: float | None, q_max: float | None) -> tuple[float, float]:
    if not (L > 0 and math.isfinite(L)):
        raise ValueError(f"L [m] must be a finite positive cell side; got {L!r}")
    if n < 4 or n % 2:
        raise ValueError(f"n [1] must be an even grid size >= 4; got {n!r}")
    lo = 2.0 * math.pi / L if q_min is None else float(q_min)
    hi = math.pi * n / L if q_max is None else float(q_max)
    if not 0 < lo <= hi:
        raise ValueError(f"need 0 < q_min <= q_max [1/m]; got q_min={lo!r}, q_max={hi!r}")
    return lo, hi


def _amplitude(psd: Spectrum, L: float, n: int, lo: float, hi: float) -> np.ndarray:
    """Standard deviation of each FFT amplitude [m]: ``sqrt(C(q)) 2 pi / L`` in the band."""
    qq = wavenumbers(L, n)
    keep = (qq >= lo * (1 - 1e-12)) & (qq <= hi * (1 + 1e-12))
    c = np.zeros_like(qq)
    c[keep] = np.asarray(psd(qq[keep]), dtype=float)
    if np.any(~np.isfinite(c)) or np.any(c < 0):
        raise ValueError("psd(q) [m^4] must be finite and >= 0 on the synthesised band")
    return np.sqrt(c) * (2.0 * math.pi / L)


def synthesise(
    psd: Spectrum,
    L: float,
    n: int,
    *,
    seed: int = 0,
    realisations: int = 1,
    q_min: float | None = None,
    q_max: float | None = None,
    first: int = 0,
) -> np.ndarray:
    """Periodic Gaussian height maps with Persson's spectrum ``psd`` [m].

    Parameters
    ----------
    psd
        ``C(q)`` [m^4] as a function of ``q`` [1/m] (numpy array in, array out), Persson's
        normalisation ``<h^2> = int d^2q C(q)``; e.g. the ``psd`` of a resolved scene.
    L
        Side of the square periodic cell [m].
    n
        Grid points per side (even).
    seed
        Base seed: realisation ``i`` is drawn from ``numpy.random.default_rng([seed, i])``, so
        it is the same map whatever ``realisations`` is.
    realisations
        Number of independent maps.
    q_min, q_max
        Band of kept wavevectors [1/m] (default: ``2 pi / L`` to the Nyquist ``pi n / L``);
        the mean height (``q = 0``) is always zero.
    first
        Index of the first realisation drawn (``realisations`` maps from ``first`` on: the
        map ``i`` is the same as in a call from 0).

    Returns
    -------
    numpy.ndarray
        Heights [m], shape ``(realisations, n, n)``, each with zero mean.
    """
    lo, hi = _band(L, n, q_min, q_max)
    if realisations < 1:
        raise ValueError(f"realisations [1] must be >= 1; got {realisations!r}")
    amp = _amplitude(psd, L, n, lo, hi)
    out = np.empty((realisations, n, n))
    for k, i in enumerate(range(int(first), int(first) + realisations)):
        white = np.random.default_rng([int(seed), i]).standard_normal((n, n))
        # fft2 of unit white noise: <|W_k|^2> = n^2; h = n^2 ifft2(a) = sum_k a_k e^{iqx}
        out[k] = np.fft.ifft2(np.fft.fft2(white) / n * amp).real * n * n
    return out


def map_moments(h: np.ndarray, L: float) -> tuple[float, float]:
    """Root-mean-square height [m] and 2-D rms slope [1] of a periodic map on a cell ``L``.

    The slope is spectral (exact for a band-limited periodic map).
    """
    h = np.asarray(h, dtype=float)
    n = h.shape[-1]
    q = 2.0 * math.pi * np.fft.fftfreq(n, d=L / n)
    fh = np.fft.fft2(h - h.mean(axis=(-2, -1), keepdims=True))
    power = np.abs(fh) ** 2 / n**4
    h_rms = math.sqrt(float(power.sum(axis=(-2, -1)).mean()))
    q2 = q[:, None] ** 2 + q[None, :] ** 2
    slope = math.sqrt(float((power * q2).sum(axis=(-2, -1)).mean()))
    return h_rms, slope


def discrete_moments(
    psd: Spectrum, L: float, n: int, q_min: float | None = None, q_max: float | None = None
) -> tuple[float, float]:
    """Expected rms height [m] and rms slope [1] of :func:`synthesise`'s maps (lattice sums)."""
    lo, hi = _band(L, n, q_min, q_max)
    var = _amplitude(psd, L, n, lo, hi) ** 2
    qq = wavenumbers(L, n)
    return math.sqrt(float(var.sum())), math.sqrt(float((var * qq**2).sum()))


def spectrum_moments(
    psd: Spectrum, q_min: float, q_max: float, points: int = 4001
) -> tuple[float, float]:
    """Continuum rms height [m] and rms slope [1] of ``psd`` on ``q_min <= q <= q_max``.

    ``h_rms^2 = 2 pi int q C(q) dq`` and ``h'_rms^2 = 2 pi int q^3 C(q) dq`` (trapezoid in
    ``ln q``).
    """
    q = np.geomspace(q_min, q_max, points)
    c = np.asarray(psd(q), dtype=float)
    lnq = np.log(q)
    h2 = 2.0 * math.pi * np.trapezoid(q**2 * c, lnq)
    s2 = 2.0 * math.pi * np.trapezoid(q**4 * c, lnq)
    return math.sqrt(h2), math.sqrt(s2)
