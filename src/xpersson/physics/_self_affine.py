"""The self-affine spectrum with roll-off (:cite:p:`persson2005,jacobs2017`): C ~ q^(-2(1+H)) above
q_r."""

from __future__ import annotations

import math

import numpy as np

from ._spectrum import PowerSpectrum, _segment_integral

__all__ = ["SelfAffineRollOff"]


class SelfAffineRollOff(PowerSpectrum):
    """Self-affine PSD with roll-off (:cite:p:`persson2005,jacobs2017`, Persson convention).

    .. math::

        C(q) = \\begin{cases} C_r & q_L \\le q < q_r \\\\
                              C_r (q/q_r)^{-2(1+H)} & q_r \\le q \\le q_1 \\\\
                              0 & \\text{otherwise} \\end{cases}

    Parameters
    ----------
    C_r : float
        Plateau value [m^4] (power-law prefactor ``C0 = C_r q_r^(2+2H)``).
    H : float
        Hurst exponent, ``0 < H <= 1`` (``H = 1`` uses the logarithmic forms).
    q_L : float
        Lower cut-off [1/m].
    q_r : float
        Roll-off wavevector [1/m], ``q_L <= q_r <= q_1`` (``q_r = q_L``: no plateau).
    q_1 : float
        Upper cut-off [1/m], ``q_1 > q_L``.
    """

    def __init__(self, C_r: float, H: float, q_L: float, q_r: float, q_1: float) -> None:
        C_r, H, q_L, q_r, q_1 = _checked(C_r, H, q_L, q_r, q_1)
        self.C_r = C_r
        self.H = H
        self.q_r = q_r
        nodes, expo = _layout(H, q_L, q_r, q_1)
        self._set_segments(nodes, [C_r] * len(expo), expo)

    @property
    def C0(self) -> float:
        """Power-law prefactor ``C0 = C_r q_r^(2+2H)`` [m^(2-2H)] so that ``C = C0 q^(-2-2H)``."""
        return self.C_r * self.q_r ** (2.0 + 2.0 * self.H)

    @classmethod
    def from_h_rms(
        cls, h_rms: float, H: float, q_L: float, q_r: float, q_1: float
    ) -> SelfAffineRollOff:
        """Build from the rms height [m]: ``C_r = h_rms^2 / (2 pi m_1[C_r = 1])``."""
        if not h_rms > 0:
            raise ValueError("from_h_rms: h_rms must be > 0")
        return cls(h_rms**2 / (2.0 * np.pi * _unit_moment(1.0, H, q_L, q_r, q_1)), H, q_L, q_r, q_1)

    @classmethod
    def from_rms_slope(
        cls, slope: float, H: float, q_L: float, q_r: float, q_1: float
    ) -> SelfAffineRollOff:
        """Build from the rms 2-D gradient (dimensionless): ``C_r = slope^2/(2 pi m_3[C_r=1])``."""
        if not slope > 0:
            raise ValueError("from_rms_slope: slope must be > 0")
        m_3 = _unit_moment(3.0, H, q_L, q_r, q_1)
        return cls(slope**2 / (2.0 * np.pi * m_3), H, q_L, q_r, q_1)

    def __repr__(self) -> str:
        return (
            f"SelfAffineRollOff(C_r={self.C_r:.6g}, H={self.H:g}, q_L={self.q_L:.6g}, "
            f"q_r={self.q_r:.6g}, q_1={self.q_1:.6g})"
        )


def _checked(
    C_r: float, H: float, q_L: float, q_r: float, q_1: float
) -> tuple[float, float, float, float, float]:
    """The parameters of :class:`SelfAffineRollOff` as floats, checked (ValueError naming the
    one out of range)."""
    C_r, H, q_L, q_r, q_1 = (float(v) for v in (C_r, H, q_L, q_r, q_1))
    if not all(map(math.isfinite, (C_r, H, q_L, q_r, q_1))):
        raise ValueError("SelfAffineRollOff: all parameters must be finite")
    if not 0.0 < H <= 1.0:
        raise ValueError(f"SelfAffineRollOff: Hurst exponent H={H} must satisfy 0 < H <= 1")
    if not q_L > 0.0:
        raise ValueError("SelfAffineRollOff: q_L must be > 0")
    if not q_1 > q_L:
        raise ValueError("SelfAffineRollOff: q_1 must be > q_L")
    if not q_L <= q_r <= q_1:
        raise ValueError("SelfAffineRollOff: q_r must satisfy q_L <= q_r <= q_1")
    if not C_r > 0.0:
        raise ValueError("SelfAffineRollOff: C_r must be > 0")
    return C_r, H, q_L, q_r, q_1


def _layout(H: float, q_L: float, q_r: float, q_1: float) -> tuple[list[float], list[float]]:
    """Breakpoints [1/m] and log-log exponents of the segments: the plateau (where
    ``q_r > q_L``), then the tail ``-2(1 + H)`` (where ``q_1 > q_r``)."""
    nodes, expo = [q_L], []
    if q_r > q_L:
        nodes.append(q_r)
        expo.append(0.0)
    if q_1 > q_r:
        nodes.append(q_1)
        expo.append(-2.0 * (1.0 + H))
    return nodes, expo


def _unit_moment(k: float, H: float, q_L: float, q_r: float, q_1: float) -> float:
    """The full moment ``int q^k C dq`` of the spectrum with ``C_r = 1`` (checked parameters),
    the same floats as ``SelfAffineRollOff(1, ...).moment(k)`` without building it."""
    _, H, q_L, q_r, q_1 = _checked(1.0, H, q_L, q_r, q_1)
    nodes, expo = _layout(H, q_L, q_r, q_1)
    q, e = np.asarray(nodes, dtype=float), np.asarray(expo, dtype=float)
    return float(np.sum(_segment_integral(q[:-1], q[1:], np.ones(e.size), e, float(k))))
