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

__all__ = [
    "implicit_operator",
    "tridiagonal_solve",
]  # (and _gtsv, _factor, _solve_factor: compiled)

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


def _gtsv(dl: Any, d: Any, du: Any, b: Any) -> int:  # pragma: no cover - compiled
    """LAPACK ``dgtsv`` for one right-hand side, in place (``dl``, ``d``, ``du``, ``b`` of
    lengths ``n - 1, n, n - 1, n``): its ``info`` (0, or the index of a zero pivot: ``b`` is
    then not solved). The elimination of the matrix (:func:`_factor`), then the right-hand
    side's (:func:`_solve_factor`): dgtsv's operations, each in its order."""
    n = d.shape[0]
    fact, swap = np.empty(n), np.empty(n, np.bool_)
    info = _factor(dl, d, du, fact, swap)
    if info == 0 and n == 1:
        b[0] = b[0] / d[0]
    elif info == 0:
        _solve_factor(dl, d, du, fact, swap, b, dl, d, du, fact, swap, False)
    return info


def _factor(dl: Any, d: Any, du: Any, fact: Any, swap: Any) -> int:  # pragma: no cover
    """dgtsv's elimination of the matrix alone, in place: the factor ``fact[i]`` of every
    row and whether rows ``i`` and ``i + 1`` were interchanged (``swap[i]``); ``dl`` becomes
    the second super-diagonal (0 where no interchange), ``d``, ``du`` the triangular factor.
    Returns ``info`` (0, or the index of the first zero pivot). The running pivot stays in a
    register (the same operations as a pass through memory, without its latency)."""
    n = d.shape[0]
    di = d[0]
    for i in range(n - 1):
        if abs(di) >= abs(dl[i]):  # no row interchange
            if di == 0.0:
                return i + 1
            f = dl[i] / di
            di = d[i + 1] - f * du[i]
            swap[i] = False
            if i < n - 2:
                dl[i] = 0.0
        else:  # interchange rows i and i + 1
            f = di / dl[i]
            d[i] = dl[i]
            temp = d[i + 1]
            di = du[i] - f * temp
            if i < n - 2:
                dl[i] = du[i + 1]
                du[i + 1] = -f * dl[i]
            du[i] = temp
            swap[i] = True
        fact[i] = f
        d[i + 1] = di
    return n if di == 0.0 else 0


def _solve_factor(  # noqa: PLR0913, C901 - two systems in one loop, dgtsv's order
    dl: Any, d: Any, du: Any, fact: Any, swap: Any, b: Any,
    dl2: Any, d2: Any, du2: Any, fact2: Any, swap2: Any, nxt: bool,
) -> int:  # fmt: skip  # pragma: no cover - compiled
    """Solve the system eliminated by :func:`_factor` (``dl``, ``d``, ``du``, ``fact``,
    ``swap``; ``n >= 2`` rows) for ``b`` in place, as dgtsv does (the forward pass, then the
    back substitution), and, when ``nxt``, eliminate the next system (``dl2``, ``d2``,
    ``du2`` into ``fact2``, ``swap2``, as :func:`_factor`) in the same loop; returns the next
    system's ``info`` (0 without ``nxt``; at its first zero pivot the elimination stops).

    Each system is dgtsv's operations in its order, so the results are its bits; what
    changes is the time: the back substitution's chain (a division per row) and the next
    elimination's (another) are independent, and run side by side. One operation is left
    out where it cannot change a bit: ``x - dl[i] * b[i + 2]`` is ``x`` when ``dl[i] = +0``
    (no interchange), ``b[i + 2]`` is finite and ``x != 0`` (the sign of a zero ``x`` may
    change)."""
    n = b.shape[0]
    bi = b[0]
    for i in range(n - 1):
        if swap[i]:
            b[i] = b[i + 1]
            bi = bi - fact[i] * b[i + 1]
        else:
            bi = b[i + 1] - fact[i] * bi
        b[i + 1] = bi
    x1 = bi / d[n - 1]
    b[n - 1] = x1
    x0 = (b[n - 2] - du[n - 2] * x1) / d[n - 2]
    b[n - 2] = x0
    info, di = 0, d2[0]
    for t in range(n - 2):
        i = n - 3 - t
        x = b[i] - du[i] * x0
        if swap[i] or x == 0.0 or not x1 - x1 == 0.0:
            x = x - dl[i] * x1
        x = x / d[i]
        b[i] = x
        x1, x0 = x0, x
        if nxt:  # row t of the next elimination (it stops at a zero pivot)
            if abs(di) >= abs(dl2[t]):
                if di == 0.0:
                    info, nxt = t + 1, False
                    continue
                f = dl2[t] / di
                di = d2[t + 1] - f * du2[t]
                swap2[t] = False
                dl2[t] = 0.0
            else:
                f = di / dl2[t]
                d2[t] = dl2[t]
                temp = d2[t + 1]
                di = du2[t] - f * temp
                dl2[t] = du2[t + 1]
                du2[t + 1] = -f * dl2[t]
                du2[t] = temp
                swap2[t] = True
            fact2[t] = f
            d2[t + 1] = di
    if not nxt:
        return info
    t = n - 2  # the last row of the next elimination (no second super-diagonal)
    if abs(di) >= abs(dl2[t]):
        if di == 0.0:
            return t + 1
        f = dl2[t] / di
        di = d2[t + 1] - f * du2[t]
        swap2[t] = False
    else:
        f = di / dl2[t]
        d2[t] = dl2[t]
        temp = d2[t + 1]
        di = du2[t] - f * temp
        du2[t] = temp
        swap2[t] = True
    fact2[t] = f
    d2[t + 1] = di
    return n if di == 0.0 else 0
