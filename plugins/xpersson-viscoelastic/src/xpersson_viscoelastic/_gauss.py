"""The n-point Gauss-Legendre rule with its spectral integration matrix, shared by the panel
quadratures of the kernel, the flash-temperature integrals and the graded output grids."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from xpersson.cache import memoize

Array = NDArray[np.float64]

__all__ = ["spectral_rule"]


@memoize("viscoelastic.spectral_rule", scope="process", maxsize=8)
def spectral_rule(n: int) -> tuple[Array, Array, Array]:
    """Gauss-Legendre nodes/weights on [-1, 1] and the spectral integration matrix
    ``Q[i, j] = int_{-1}^{x_i} l_j(x) dx`` (l_j the Lagrange basis on the nodes)."""
    x, w = np.polynomial.legendre.leggauss(n)
    V = np.polynomial.legendre.legvander(x, n - 1)  # V[i, k] = P_k(x_i)
    Vint = np.empty_like(V)
    for k in range(n):
        c = np.zeros(n)
        c[k] = 1.0
        Vint[:, k] = np.polynomial.legendre.legval(x, np.polynomial.legendre.legint(c, lbnd=-1))
    return x, w, Vint @ np.linalg.inv(V)
