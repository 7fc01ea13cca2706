"""The implicit half of a Crank-Nicolson (theta) step, shared by both finite-volume integrators.

A theta step of ``M dR/dtau = L R`` solves ``(M - theta dt L) R_new = (M + (1 - theta) dt L) R``:
the right-hand side is built by each integrator in its own (conservative) form, and the
tridiagonal system is solved here, by one LAPACK ``dgtsv`` call for all right-hand sides
(columns) or for all loads of a batch (their systems concatenated).  Used by the moving-wall
march (:mod:`._moving`, ``cn``) and by :func:`~xpersson.engine.solve_sourced`
(:mod:`._sourced`), whose constant operator ``I - theta dt L`` is built by
:func:`implicit_operator`.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.linalg.lapack import dgtsv

__all__ = ["implicit_operator", "tridiagonal_solve"]  # (and _gtsv: the compiled source)

Array = NDArray[np.float64]


def tridiagonal_solve(dl: Array, d: Array, du: Array, rhs: Array) -> int:
    """Solve the tridiagonal system ``(dl, d, du) x = rhs`` in place of ``rhs`` (LAPACK
    ``dgtsv``, Gaussian elimination with partial pivoting).

    Parameters
    ----------
    dl, d, du : ndarray
        Sub-diagonal ``(n - 1,)``, diagonal ``(n,)`` and super-diagonal ``(n - 1,)``
        (overwritten by the factorisation).
    rhs : ndarray, (n,) or (n, k)
        Right-hand side(s); holds the solution on return.

    Returns
    -------
    int
        LAPACK's ``info``: 0 on success, ``i > 0`` when the ``i``-th pivot is exactly zero
        (the system is singular; ``rhs`` then holds no solution), ``< 0`` for an invalid
        argument.  The caller decides what a failure means.
    """
    _, _, _, sol, info = dgtsv(dl, d, du, rhs, 1, 1, 1, 1)
    if sol is not rhs:  # the LAPACK wrapper made a (Fortran-ordered) copy
        rhs[...] = sol
    return info  # type: ignore[no-any-return]


def implicit_operator(
    theta_dt: float, lo: Array, diag: Array, up: Array
) -> tuple[Array, Array, Array]:
    """Diagonals of ``I - theta_dt L`` for ``L`` with rows ``lo_j R_{j-1} + diag_j R_j +
    up_j R_{j+1}`` (``lo[0]`` and ``up[-1]`` unused); ``theta_dt`` [Pa^2]."""
    return -theta_dt * lo[1:], 1.0 - theta_dt * diag, -theta_dt * up[:-1]


def _gtsv(dl: Any, d: Any, du: Any, b: Any, i0: int = 0) -> int:  # pragma: no cover - compiled
    """LAPACK ``dgtsv`` for one right-hand side, in place (``dl``, ``d``, ``du``, ``b`` of
    lengths ``n - 1, n, n - 1, n``): its ``info`` (0, or the index of a zero pivot);
    ``i0``: the rows before it already eliminated without interchanges."""
    n = d.shape[0]
    for i in range(i0, n - 1):
        if abs(d[i]) >= abs(dl[i]):  # no row interchange
            if d[i] == 0.0:
                return i + 1
            fact = dl[i] / d[i]
            d[i + 1] = d[i + 1] - fact * du[i]
            b[i + 1] = b[i + 1] - fact * b[i]
            if i < n - 2:
                dl[i] = 0.0
        else:  # interchange rows i and i + 1
            fact = d[i] / dl[i]
            d[i] = dl[i]
            temp = d[i + 1]
            d[i + 1] = du[i] - fact * temp
            if i < n - 2:
                dl[i] = du[i + 1]
                du[i + 1] = -fact * dl[i]
            du[i] = temp
            temp = b[i]
            b[i] = b[i + 1]
            b[i + 1] = temp - fact * b[i + 1]
    if d[n - 1] == 0.0:
        return n
    b[n - 1] = b[n - 1] / d[n - 1]
    if n > 1:
        b[n - 2] = (b[n - 2] - du[n - 2] * b[n - 1]) / d[n - 2]
    for i in range(n - 3, -1, -1):
        b[i] = (b[i] - du[i] * b[i + 1] - dl[i] * b[i + 2]) / d[i]
    return 0
