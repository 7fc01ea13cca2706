"""Quadrature over wavevectors for the nested Persson integrals (pure numpy, SI units).

The mean-separation integrand contains ``w(q) = [pi int_{q_a}^{q} q'^3 C dq']^(-1/2)``, which
diverges like ``(q - q_a)^(-1/2)`` at the lower cut-off ``q_a``. :func:`q_rule` returns nodes and
weights of a composite Gauss-Legendre rule that is exact for that singularity:

* on ``[q_a, q_b]`` (``q_b = min(1.5 q_a, next PSD breakpoint)``) the substitution
  ``q = q_a + s^2`` removes the square-root singularity; geometrically graded panels in ``s``
  towards ``s = 0`` also resolve the logarithmic behaviour of ``E1((w p / E*)^2)`` at low load;
* on ``[q_b, q_1]`` panels uniform in ``ln q`` split at every PSD breakpoint (kinks of ``C``).

The rule depends only on the spectrum and ``q_a``, so it is built once and reused for every load.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

__all__ = ["QRule", "q_rule", "gauss_legendre"]


@lru_cache(maxsize=16)
def gauss_legendre(n: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Gauss-Legendre nodes and weights on ``[0, 1]`` (``n`` points)."""
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (x + 1.0), 0.5 * w


def _panels(edges: NDArray[np.float64], n: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Composite Gauss-Legendre nodes/weights on consecutive intervals ``edges``."""
    x, w = gauss_legendre(n)
    a, b = edges[:-1, None], edges[1:, None]
    return (a + (b - a) * x).ravel(), ((b - a) * w).ravel()


@dataclass(frozen=True)
class QRule:
    """Quadrature rule ``int_{q_a}^{q_1} F(q) dq ~ sum(weights * F(q))`` plus cached PSD data.

    Attributes
    ----------
    q : ndarray
        Nodes [1/m], strictly inside ``(q_a, q_1)``.
    weights : ndarray
        Weights [1/m].
    C : ndarray
        ``C(q)`` at the nodes [m^4].
    w : ndarray
        ``w(q) = [pi int_{q_a}^{q} q'^3 C dq']^(-1/2)`` at the nodes [1].
    q_a : float
        Lower limit [1/m].
    """

    q: NDArray[np.float64]
    weights: NDArray[np.float64]
    C: NDArray[np.float64]
    w: NDArray[np.float64]
    q_a: float


def q_rule(
    psd: object,
    q_a: float | None = None,
    *,
    n_s_panels: int = 36,
    grading: float = 0.5,
    panels_per_decade: int = 6,
    order: int = 10,
) -> QRule:
    """Build the quadrature rule on ``[q_a, q_1]`` for spectrum ``psd``.

    Parameters
    ----------
    psd : PowerSpectrum
        Spectrum with ``C(q)`` [m^4], ``I3(q)``, ``q_L``, ``q_1`` [1/m] and ``nodes()``.
    q_a : float, optional
        Lower limit [1/m] (default ``psd.q_L``); ``q_a = zeta q_L`` gives the spectrum seen at
        magnification ``zeta`` (roughness on larger scales removed).
    n_s_panels : int
        Number of geometrically graded panels in ``s = sqrt(q - q_a)``.
    grading : float
        Ratio of consecutive ``s``-panel edges (``0 < grading < 1``).
    panels_per_decade : int
        Gauss-Legendre panels per decade of ``q`` above ``q_b``.
    order : int
        Gauss-Legendre points per panel.

    Returns
    -------
    QRule
        Nodes, weights and ``C``, ``w`` at the nodes. Empty when ``q_a >= q_1``.
    """
    q_L, q_1 = float(psd.q_L), float(psd.q_1)
    qa = q_L if q_a is None else max(float(q_a), q_L)
    if qa >= q_1 * (1.0 - 1e-14):
        e = np.zeros(0)
        return QRule(e, e, e, e, qa)
    nodes = np.asarray(psd.nodes(), dtype=float)
    inner = nodes[(nodes > qa * (1.0 + 1e-12)) & (nodes < q_1)]
    q_b = min(1.5 * qa, inner[0] if inner.size else q_1, q_1)
    # --- singular part: q = q_a + s^2, geometric panels towards s = 0
    s_b = np.sqrt(q_b - qa)
    s_edges = np.concatenate(([0.0], s_b * grading ** np.arange(n_s_panels, -1, -1)))
    s, ws = _panels(s_edges, order)
    q_s = qa + s * s
    w_s = 2.0 * s * ws
    # --- regular part: uniform panels in ln q between breakpoints
    brk = np.unique(np.concatenate(([q_b], inner[inner > q_b], [q_1])))
    parts_q, parts_w = [q_s], [w_s]
    for lo, hi in zip(brk[:-1], brk[1:], strict=True):
        if hi <= lo * (1.0 + 1e-14):
            continue
        m = max(1, int(np.ceil(panels_per_decade * np.log10(hi / lo))))
        t, wt = _panels(np.linspace(np.log(lo), np.log(hi), m + 1), order)
        qt = np.exp(t)
        parts_q.append(qt)
        parts_w.append(wt * qt)
    q = np.concatenate(parts_q)
    weights = np.concatenate(parts_w)
    C = np.asarray(psd.C(q), dtype=float)
    dI3 = np.asarray(psd.I3(q), dtype=float) - float(psd.I3(qa))
    # near q_a the difference of running integrals loses digits (and q_a + s^2 rounds to q_a):
    # use dq = s^2 directly with the midpoint value of q^3 C (relative error (dq/q_a)^2)
    dq = s * s
    small = np.zeros(q.size, dtype=bool)
    small[: s.size] = dq < 1e-6 * qa
    if np.any(small):
        qm = qa + 0.5 * dq[small[: s.size]]
        dI3[small] = dq[small[: s.size]] * qm**3 * np.asarray(psd.C(qm), dtype=float)
    dI3 = np.maximum(dI3, np.finfo(float).tiny)
    w = 1.0 / np.sqrt(np.pi * dI3)
    return QRule(q, weights, C, w, qa)
