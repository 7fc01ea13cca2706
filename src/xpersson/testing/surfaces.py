"""Synthetic periodic height maps with a prescribed isotropic spectrum, for tests, benchmarks
and examples of measured-surface input (SI units, Persson's convention)."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

__all__ = ["rolled_off", "synthetic_map"]


def rolled_off(
    H: float, q_L: float, q_r: float, q_s: float | None = None, sharp: bool = True
) -> Callable[[NDArray[np.float64]], NDArray[np.float64]]:
    """An unnormalised self-affine PSD shape [m^4]: flat below ``q_r``, ``(q/q_r)^(-2(1+H))``
    above (``sharp``), or ``(1 + (q/q_r)^2)^(-(1+H))`` (a smooth roll-off); zero below
    ``q_L`` (the mean) and above ``q_s`` (a band limit; ``None``: none)."""

    def shape(q: NDArray[np.float64]) -> NDArray[np.float64]:
        q = np.asarray(q, float)
        if sharp:
            c = np.where(q < q_r, 1.0, (np.maximum(q, q_r) / q_r) ** (-2.0 * (1.0 + H)))
        else:
            c = (1.0 + (q / q_r) ** 2) ** (-(1.0 + H))
        c = np.where(q < q_L * (1 - 1e-9), 0.0, c)
        return np.where(q > q_s, 0.0, c) if q_s is not None else c

    return shape


def synthetic_map(
    n: int,
    size: float,
    psd: Callable[[NDArray[np.float64]], NDArray[np.float64]],
    h_rms: float | None = None,
    seed: int = 0,
) -> NDArray[np.float64]:
    """A periodic ``n x n`` map [m] of side ``size`` [m] whose every Fourier mode has the
    variance ``psd(|k|) (2 pi / size)^2`` (unit amplitudes, random phases; ``psd`` in m^4,
    Persson's convention), scaled to ``h_rms`` [m] when given.

    The map's ring-averaged spectrum is then ``psd`` itself (up to the scale), without the
    periodogram's scatter, so estimators can be checked to a fraction of a percent.
    """
    k = 2 * np.pi * np.fft.fftfreq(n, size / n)
    amp = np.sqrt(psd(np.hypot(k[:, None], k[None, :]))) * (2 * np.pi / size) * n * n
    amp[0, 0] = 0.0
    phi = 2 * np.pi * np.random.default_rng(seed).random((n, n))
    flip = (-np.arange(n)) % n
    phase = np.exp(1j * (phi - phi[np.ix_(flip, flip)]))  # Hermitian: a real map
    h = np.real(np.fft.ifft2(amp * phase))
    return np.asarray(h if h_rms is None else h * (h_rms / h.std()), float)
