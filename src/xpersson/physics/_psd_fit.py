"""A self-affine fit with roll-off to a measured PSD table, with uncertainties (SI units)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._self_affine import SelfAffineRollOff

__all__ = ["SelfAffineFit", "fit_self_affine"]


@dataclass(frozen=True)
class SelfAffineFit:
    """``C(q) = C_r`` below ``q_r``, ``C_r (q/q_r)^(-2(1+H))`` above (Persson, m^4).

    Attributes
    ----------
    H, H_err : float
        Hurst exponent and its standard error.
    q_r, q_r_err : float
        Roll-off wavevector [1/m] and its standard error (``q_r`` at the table's start: no
        roll-off seen).
    C_r, C_r_err : float
        Plateau value [m^4] and its standard error.
    h_rms, h_rms_err : float
        The fit's rms height over ``[q_L, q_1]`` [m] and its standard error.
    q_L, q_1 : float
        The fitted band [1/m].
    """

    H: float
    H_err: float
    q_r: float
    q_r_err: float
    C_r: float
    C_r_err: float
    h_rms: float
    h_rms_err: float
    q_L: float
    q_1: float

    def C(self, q: ArrayLike) -> NDArray[np.float64]:
        """The fitted PSD at ``q`` [1/m], in m^4."""
        return np.asarray(_model(np.log(np.asarray(q, float)), self._p()), float)

    def _p(self) -> NDArray[np.float64]:
        return np.array([math.log(self.C_r), self.H, math.log(self.q_r)])


def _model(lq: NDArray[np.float64], p: NDArray[np.float64]) -> NDArray[np.float64]:
    log_c, H, log_qr = p
    return np.exp(log_c - 2.0 * (1.0 + H) * np.maximum(lq - log_qr, 0.0))


def _h_rms(p: NDArray[np.float64], q_L: float, q_1: float) -> float:
    q_r = min(max(math.exp(p[2]), q_L), q_1 * (1 - 1e-9))
    H = min(max(p[1], 1e-3), 1.0)
    return SelfAffineRollOff(math.exp(p[0]), H, q_L, q_r, q_1).h_rms()


def fit_self_affine(q: ArrayLike, C: ArrayLike, weight: ArrayLike | None = None) -> SelfAffineFit:
    """Fit ``log C`` (least squares, weighted) with a self-affine PSD with roll-off.

    Parameters
    ----------
    q : array_like
        Wavevectors [1/m], increasing.
    C : array_like
        PSD [m^4] (> 0).
    weight : array_like, optional
        Weight of each point (e.g. its ring's number of modes); default: equal.

    Returns
    -------
    SelfAffineFit
        Standard errors from the Jacobian at the optimum (residual variance times
        ``(J^T W J)^-1``); ``h_rms_err`` propagated from them (the fit's H clipped to (0, 1]
        for the rms height).
    """
    from scipy.optimize import least_squares  # noqa: PLC0415 - only when a fit is asked for

    lq, lc = np.log(np.asarray(q, float)), np.log(np.asarray(C, float))
    w = np.ones_like(lq) if weight is None else np.asarray(weight, float)
    sw = np.sqrt(w / w.mean())
    upper = lq > lq[0] + 0.5 * (lq[-1] - lq[0])
    slope = np.polyfit(lq[upper], lc[upper], 1)[0] if upper.sum() >= 2 else -3.6
    p0 = np.array([lc[0], min(max(-slope / 2.0 - 1.0, -0.4), 1.9), lq[0]])
    lo, hi = [-np.inf, -0.49, lq[0]], [np.inf, 2.0, lq[-1]]
    p0 = np.clip(p0, np.add(lo, 1e-9), np.subtract(hi, 1e-9))

    def residual(p: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.asarray(sw * (np.log(_model(lq, p)) - lc), float)

    best = None
    for start in (p0, [lc[0], p0[1], 0.5 * (lq[0] + lq[-1])]):  # two starts: with, without
        res = least_squares(residual, np.clip(start, np.add(lo, 1e-9), np.subtract(hi, 1e-9)),
                            bounds=(lo, hi), x_scale=[1.0, 0.1, 1.0])  # fmt: skip
        if best is None or res.cost < best.cost:
            best = res
    assert best is not None
    p, J = best.x, best.jac
    dof = max(lq.size - 3, 1)
    s2 = 2.0 * best.cost / dof
    cov = np.linalg.pinv(J.T @ J) * s2
    err = np.sqrt(np.maximum(np.diag(cov), 0.0))
    q_L, q_1 = float(math.exp(lq[0])), float(math.exp(lq[-1]))
    h = _h_rms(p, q_L, q_1)
    grad = np.array(
        [(_h_rms(p + d, q_L, q_1) - _h_rms(p - d, q_L, q_1)) / (2 * d[i])
         for i, d in enumerate(np.diag([1e-6, 1e-6, 1e-6]))]
    )  # fmt: skip
    h_err = float(math.sqrt(max(grad @ cov @ grad, 0.0)))
    return SelfAffineFit(
        H=float(p[1]),
        H_err=float(err[1]),
        q_r=float(math.exp(p[2])),
        q_r_err=float(math.exp(p[2]) * err[2]),
        C_r=float(math.exp(p[0])),
        C_r_err=float(math.exp(p[0]) * err[0]),
        h_rms=h,
        h_rms_err=h_err,
        q_L=q_L,
        q_1=q_1,
    )
