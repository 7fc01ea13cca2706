"""A table-driven ``erf`` for the gap kernels (private): 3-4x cheaper than scipy's, |error| < 2e-13.

``erf`` on ``[0, 6]`` is interpolated by piecewise cubic Hermite polynomials on nodes spaced
``h = 1/512`` with the exact values (scipy's ``erf``) and the exact derivative
``2/sqrt(pi) exp(-x^2)`` at the nodes; the interpolant is continuous with a continuous slope.
The interpolation error is at most ``h^4/384 max|erf''''| = h^4/384 * 4.405 = 1.67e-13``
(``erf'''' = -2/sqrt(pi) (8x^3 - 12x) exp(-x^2)``, largest at ``x = 0.5246``); the table values'
and the evaluation's round-off add a few units of 1.1e-16. Beyond ``|x| >= 6`` the result is
exactly ``sign(x)`` (as scipy's: ``erf`` rounds to 1 from ``x = 5.9216``); odd symmetry holds
exactly. Each piece's exact cubic is increasing (its slope stays within 1 % of ``erf'``), so the
interpolant is non-decreasing up to the round-off of its evaluation (one unit in the last place).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray
from scipy.special import erf as _scipy_erf

__all__ = ["ERF_ERROR", "fast_erf"]

#: Nodes per unit of ``x`` (a power of 2: ``|x| * _N`` and its fractional part are exact).
_N = 512
#: ``|x|`` from which ``fast_erf`` returns ``sign(x)`` exactly.
_X_ONE = 6.0
#: Bound on ``|fast_erf(x) - erf(x)|`` (interpolation 1.67e-13 plus round-off), absolute.
ERF_ERROR = 2e-13


def _table() -> tuple[NDArray[np.float64], ...]:
    """Hermite coefficients ``c0..c3`` per piece in the local coordinate ``f in [0, 1)``.

    Piece ``i`` covers ``x in [i h, (i + 1) h)``; an extra last piece ``(1, 0, 0, 0)`` gives
    exactly 1 at (and, after clipping, beyond) ``x = 6``.
    """
    n = int(_X_ONE * _N)
    x = np.arange(n + 1) / _N
    y = _scipy_erf(x)
    m = (2.0 / math.sqrt(math.pi) / _N) * np.exp(-x * x)  # slope per unit of f
    dy = np.diff(y)
    c0 = np.append(y[:-1], 1.0)
    c1 = np.append(m[:-1], 0.0)
    c2 = np.append(3.0 * dy - 2.0 * m[:-1] - m[1:], 0.0)
    c3 = np.append(m[:-1] + m[1:] - 2.0 * dy, 0.0)
    return c0, c1, c2, c3


_C0, _C1, _C2, _C3 = _table()


def fast_erf(x: NDArray[np.float64], out: NDArray[np.float64] | None = None) -> NDArray[np.float64]:
    """``erf(x)`` [1] to within :data:`ERF_ERROR` absolute, elementwise (NaN stays NaN).

    Parameters
    ----------
    x : ndarray of float64
        Arguments [1], any shape.
    out : ndarray, optional
        Where to write the result (same shape as ``x``; may be ``x`` itself).

    Returns
    -------
    ndarray
        ``erf(x)``; exactly ``sign(x)`` for ``|x| >= 6``, exactly odd, ``-0.0`` kept.
    """
    x = np.asarray(x, dtype=float)
    t = np.abs(x)
    t *= float(_N)  # exact (power of 2)
    nan = np.isnan(t) if math.isnan(np.add.reduce(t, axis=None)) else None  # rare path
    np.fmin(t, _X_ONE * _N, out=t)  # NaN -> the last piece (put back below)
    i = t.astype(np.intp)  # = floor(t), t >= 0
    t -= i  # fractional part f in [0, 1): exact
    p = np.take(_C3, i)
    p *= t
    p += np.take(_C2, i)
    p *= t
    p += np.take(_C1, i)
    p *= t
    p += np.take(_C0, i)
    res = np.copysign(p, x, out=out)
    if nan is not None:
        res[nan] = np.nan
    return res
