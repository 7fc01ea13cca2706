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

import numpy as np
from numpy.typing import NDArray
from scipy.linalg.lapack import dgtsv

__all__ = ["implicit_operator", "tridiagonal_solve"]

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
