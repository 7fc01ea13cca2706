"""Quantities derived from boundary-element states, named as the theory names them.

* ``contact_stiffness`` ``K = -dp0/du`` [Pa/m] from two neighbouring loads (:func:`stiffness`);
* conductances by Barber's analogy ``g = c K`` (:func:`electrical_factor`,
  :func:`thermal_factor`) and, independently, by a direct conduction solve on a contact map
  (:func:`conductance_direct`);
* ``gap_pdf``: the continuous part of the gap distribution on given bins (:func:`gap_pdf`);
* adhesive loading paths under displacement control and the area and pull-off read from the
  stable retraction branch (:func:`adhesive_path`, :func:`retraction_branch`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from .solve import BemState, GapSolver

__all__ = [
    "stiffness",
    "electrical_factor",
    "thermal_factor",
    "conductance_direct",
    "gap_pdf",
    "adhesive_path",
    "retraction_branch",
    "APPROACH",
    "APPROACH_DEEP",
    "RETRACT_FINE",
    "RETRACT_STEP",
]

#: Approach of an adhesive path: mean gaps [h_rms].
APPROACH = (2.4, 1.4, 0.9, 0.6)
#: Further approach steps [h_rms] taken while the mean stress is below the largest load asked.
APPROACH_DEEP = (0.45, 0.3, 0.2, 0.12, 0.06)
#: Retraction: ``count`` fine steps of ``size`` [h_rms], then :data:`RETRACT_STEP` steps.
RETRACT_FINE = (0.03, 10)
RETRACT_STEP = 0.1


def stiffness(p_lo: float, p_hi: float, u_lo: float, u_hi: float) -> float:
    """Normal contact stiffness per nominal area ``K = -(p_hi - p_lo)/(u_hi - u_lo)`` [Pa/m].

    ``p`` [Pa] are two neighbouring mean pressures and ``u`` [m] their mean gaps (a central
    difference when the two loads bracket the load of interest).
    """
    du = u_hi - u_lo
    return -(p_hi - p_lo) / du if du != 0 else math.inf


def electrical_factor(rho_1: float, rho_2: float, E_star: float) -> float:
    """Barber's constant ``c = 2 / ((rho_1 + rho_2) E*)`` [S m^-1 Pa^-1]: ``g = c K``.

    ``rho_1``, ``rho_2``: resistivities [ohm m]; ``E_star``: contact modulus [Pa].
    """
    return 2.0 / ((rho_1 + rho_2) * E_star)


def thermal_factor(k_1: float, k_2: float, E_star: float) -> float:
    """Barber's constant ``c = 2 k_s / E*`` with ``k_s = k_1 k_2 / (k_1 + k_2)`` [W K^-1 Pa^-1].

    ``k_1``, ``k_2``: thermal conductivities [W m^-1 K^-1]; ``E_star``: contact modulus [Pa].
    """
    return 2.0 * (k_1 * k_2 / (k_1 + k_2)) / E_star


def conductance_direct(contact: np.ndarray, L: float, rho_sum: float, rtol: float = 1e-10) -> float:
    """Constriction conductance per nominal area [S m^-2] of a periodic contact map, solved.

    Unit potential jump on the contact points, no current elsewhere; the jump of the surface
    potential is ``(rho_1 + rho_2) j_q / |q|`` (each half-space ``rho j_q / |q|``), its mean
    the jump of the far fields, so ``g = mean(j)``. Conjugate gradients on the contact points
    (numpy FFT, scipy CG), independent of the stiffness and of the contact solver: Barber's
    analogy says ``g = c K``.

    Parameters
    ----------
    contact
        Boolean ``(n, n)`` contact map.
    L
        Cell side [m].
    rho_sum
        ``rho_1 + rho_2`` [ohm m].
    rtol
        Relative tolerance of the conjugate gradients; non-convergence raises RuntimeError.
    """
    from scipy.sparse.linalg import LinearOperator, cg

    n = contact.shape[0]
    q = 2 * np.pi * np.fft.fftfreq(n, d=L / n)
    qn = np.hypot(q[:, None], q[None, :])
    kern = np.where(qn > 0, rho_sum / np.where(qn > 0, qn, 1.0), 0.0)
    idx = np.flatnonzero(np.asarray(contact).ravel())

    def apply(x: np.ndarray) -> np.ndarray:
        j = np.zeros(n * n)
        j[idx] = x
        v = np.fft.ifft2(kern * np.fft.fft2(j.reshape(n, n))).real.ravel()
        return v[idx]

    op = LinearOperator((idx.size, idx.size), matvec=apply, dtype=float)
    x, info = cg(op, np.ones(idx.size), rtol=rtol, maxiter=5000)
    if info != 0:
        raise RuntimeError(f"conduction CG did not converge (info = {info})")
    return float(x.sum()) / (n * n)


def gap_pdf(gap: np.ndarray, contact: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """Continuous part of the gap density [1/m] on ``edges`` [m]: the non-contact points.

    Normalised by the whole cell, so that ``sum(pdf * diff(edges)) + area_fraction = 1`` when
    the edges span every gap (the theory's ``gap_pdf`` and ``gap_contact_weight``).
    """
    g = np.asarray(gap)[~np.asarray(contact, dtype=bool)]
    counts, _ = np.histogram(g, bins=edges)
    return counts / (np.asarray(gap).size * np.diff(edges))


def adhesive_path(
    heights: np.ndarray,
    L: float,
    E_star: float,
    work: float,
    rho: float,
    *,
    p_max: float | None = None,
    strict: bool = True,
    max_gap: float = 4.0,
    h_rms: float | None = None,
    keep_fields: bool = False,
) -> dict[str, list[BemState]]:
    """Approach, then retraction to pull-off, under displacement control (exponential law).

    Mean gaps are in units of the map's rms height: :data:`APPROACH`, then while the mean
    stress stays below ``p_max`` [Pa] :data:`APPROACH_DEEP`; retraction in
    :data:`RETRACT_FINE` then :data:`RETRACT_STEP` steps until no contact is left, the mean
    stress has stayed above a tenth of its most tensile value for three steps after it (past
    the pull-off), or the mean gap exceeds ``max_gap`` h_rms. ``work`` [J/m^2], ``rho`` [m] as in
    :func:`~xpersson.bem.solve_gaps`. One solver carries the state along the whole path.
    ``h_rms`` [m]: the unit of the gap steps (default: the map's own rms height);
    ``keep_fields``: keep each state's maps. With ``strict=False`` a non-converged state is
    kept, flagged and NaN (the retraction then goes on to its next step).

    Returns
    -------
    dict
        ``{"approach": [...], "retract": [...]}`` lists of :class:`BemState`.
    """
    h_rms = float(np.std(heights)) if h_rms is None else h_rms
    gaps = [g * h_rms for g in APPROACH]
    if p_max is not None:
        gaps += [g * h_rms for g in APPROACH_DEEP]
    path = GapSolver(heights, L, E_star, work=work, rho=rho, strict=strict, keep_fields=keep_fields)
    approach: list[BemState] = []
    for g in gaps:
        if len(approach) >= len(APPROACH) and p_max is not None and approach[-1].p0 > p_max:
            break
        approach.append(path.at(g))
    retract = [approach[-1]]
    g, step = gaps[len(approach) - 1] / h_rms, 0
    while True:
        step += 1
        g = round(g + (RETRACT_FINE[0] if step <= RETRACT_FINE[1] else RETRACT_STEP), 10)
        st = path.at(g * h_rms)
        retract.append(st)
        if (st.converged and st.area_fraction == 0.0) or g > max_gap or _past(retract):
            break
    return {"approach": approach, "retract": retract}


def _past(retract: list[BemState], after: int = 3) -> bool:
    """Whether the last ``after`` states are past the most tensile one and below a tenth of
    it: the stable branch ended (pull-off) and the rest is not used."""
    p = np.array([s.p0 for s in retract], dtype=float)
    if not np.isfinite(p).any() or p.size <= after:
        return False
    i = int(np.nanargmin(p))
    tail = p[-after:]
    return i < p.size - after and bool(np.all(np.nan_to_num(tail, nan=0.0) > 0.1 * p[i]))


def retraction_branch(retract: Sequence[BemState], loads: np.ndarray) -> tuple[np.ndarray, float]:
    """Contact area at ``loads`` [Pa] on the stable retraction branch, and the pull-off [Pa].

    Load control follows the running minimum of the mean stress along the retraction (each
    new record is a stable state; snap-off saw-teeth in between are skipped). Loads outside
    the branch are NaN. The pull-off is the most tensile mean stress (>= 0).
    """
    p = np.array([s.p0 for s in retract])
    a = np.array([s.area_fraction for s in retract])
    pull = max(-float(np.nanmin(p)), 0.0)
    keep = [0]
    for i in range(1, p.size):
        if p[i] < p[keep[-1]]:
            keep.append(i)
    ps, as_ = p[keep][::-1], a[keep][::-1]
    loads = np.asarray(loads, dtype=float)
    out = np.full(loads.shape, np.nan)
    ok = (loads >= ps[0]) & (loads <= ps[-1])
    out[ok] = np.interp(loads[ok], ps, as_)
    return out, pull
