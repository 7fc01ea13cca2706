"""Vectorised numerical kernels of the sliding viscoelastic contact (physics.md §4.2).

Everything here is numpy in SI units, vectorised over sliding speeds ``v`` [m/s] and shift
factors ``a_T`` [1] (temperatures), and shared by the coefficient plugin, the friction analysis
and the benchmark:

* diffusion time ``tau(zeta; v, T) = (pi/4) int_{q_L}^{zeta q_L} q^3 C(q) <|E(q v a_T cos phi)|^2>
  dq / (1 - nu^2)^2`` [Pa^2] (``G = tau / p0^2``);
* cumulative loss integral ``L(zeta; v, T) = int_{q_L}^{zeta q_L} q^3 C(q) int_0^2pi cos(phi)
  Im E(q v a_T cos phi) dphi dq / (1 - nu^2)`` [Pa];
* friction ``mu_visc = (1 / (2 p0)) int P(q) S(q) dL`` (:func:`friction_integral`, the one
  home of the formula); the stand-alone curve ``friction_curve`` (Persson01 area) is built on
  these in :mod:`._curve`.

The q-integrals use Gauss-Legendre rules in ``ln q`` on panels whose edges contain the PSD
breakpoints, the requested magnifications and a log grid of ``panels_per_decade``; within a
panel the integrands are analytic, so 8 nodes per quarter decade give ~1e-14 relative. The
``E_r^2 I3(q)`` part of ``tau`` is taken from the spectrum's exact moment, so ``v = 0``
reproduces the elastic diffusion time with ``E = E_r`` to round-off.

``friction_curve`` grades its panels towards ``q_L`` where needed (issue 22): when the
contact area of a stiff rubber (fast, cold, no roll-off plateau) falls from 1 to ``~1/sqrt(pi G)``
just above ``q_L``, ``P ~ (q - q_L)^(-1/2)`` and most of ``mu_visc`` comes from there. The first
panel then ends where ``G <= 1e-3`` (:func:`first_panel_width`), the panels up to ``2 q_L`` are
two per decade of ``q - q_L`` with Gauss-Legendre in ``ln(q - q_L)`` (:func:`graded_edges`), and
``tau`` is integrated spectrally in full (no ``I3(q)``, which loses digits where ``q - q_L`` is
near the round-off of ``q``). Verified against an independent quad reference to ~1e-9 over
``v`` from 1e-9 to 1e3 m/s, WLF temperatures, ``H`` from 0.3 to 1, with and without plateau
(``benchmarks/verify_friction.py``).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from xpersson.cache import memoize
from xpersson.physics import closure_S

from ._gauss import spectral_rule as _rule
from ._modulus import ModulusModel
from ._panels import grouped_sums, reduced_ok
from ._stencil import interval_weights

__all__ = [
    "panel_edges",
    "graded_edges",
    "diffusion_time",
    "coefficient_f",
    "loss_integral",
    "friction_integral",
    "stieltjes_increments",
    "first_panel_width",
]

Array = NDArray[np.float64]
PANELS_PER_DECADE = 4
NODES = 8


def panel_edges(psd: Any, q: ArrayLike, panels_per_decade: int = PANELS_PER_DECADE) -> Array:
    """Panel edges [1/m] from ``q_L`` to ``max(q)``: a log grid, the PSD breakpoints, ``q``.

    ``q`` [1/m] may have any shape (a scalar, the 2-D magnifications of a boundary's clock);
    the edges are always 1-D and sorted.
    """
    q = np.asarray(q, dtype=float).ravel()
    q_L = float(psd.q_L)
    q_hi = max(float(np.max(q)), q_L) if q.size else q_L
    n = max(1, int(np.ceil(panels_per_decade * np.log10(q_hi / q_L) - 1e-9)))
    grid = np.geomspace(q_L, q_hi, n + 1) if q_hi > q_L else np.array([q_L])
    nodes = np.asarray(psd.nodes(), dtype=float)
    inner = nodes[(nodes > q_L) & (nodes < q_hi)]
    edges = np.unique(np.concatenate([grid, inner, np.clip(q, q_L, q_hi), [q_L]]))
    return edges


def _nodes(edges: Array, n: int, q_L: float | None = None) -> tuple[Array, Array, Array, Array]:
    """GL nodes q (n_panel, n), weights ``dq`` (n_panel, n), ``dq/du`` at the nodes and the
    panels' half-widths in ``u``.

    The variable ``u`` is ``ln q`` on every panel, except with ``q_L`` given (graded panels of
    :func:`graded_edges`): ``ln(q - q_L)`` on panels inside ``(q_L, 2 q_L]`` and ``q`` itself on
    the first panel ``[q_L, q_L (1 + d0)]``. Near ``q_L`` the contact area of a stiff rubber drops
    like ``(q - q_L)^(-1/2)``; in ``ln(q - q_L)`` that drop is smooth.
    """
    x, w, _ = _rule(n)
    if q_L is None:  # ln q everywhere
        s = np.log(edges)
        mid, half = 0.5 * (s[1:] + s[:-1]), 0.5 * (s[1:] - s[:-1])
        qn = np.exp(mid[:, None] + half[:, None] * x)
        return qn, half[:, None] * w * qn, qn, half
    a, b = edges[:-1], edges[1:]
    kind = np.zeros(a.size, dtype=int)  # 0: ln q, 1: ln(q - q_L), 2: q
    kind[(a > q_L) & (b <= 2.0 * q_L)] = 1
    kind[(a <= q_L) & (b <= 2.0 * q_L)] = 2
    with np.errstate(divide="ignore"):
        lo = np.select([kind == 1, kind == 2], [np.log(a - q_L), a], np.log(a))
        hi = np.select([kind == 1, kind == 2], [np.log(b - q_L), b], np.log(b))
    mid, half = 0.5 * (hi + lo), 0.5 * (hi - lo)
    u = mid[:, None] + half[:, None] * x
    k = kind[:, None]
    with np.errstate(over="ignore"):
        eu = np.exp(np.where(k == 2, 0.0, u))
    qn = np.select([k == 1, k == 2], [q_L + eu, u], eu)
    jac = np.select([k == 1, k == 2], [eu, np.ones_like(u)], qn)
    return qn, half[:, None] * w * jac, jac, half


def graded_edges(
    psd: Any, q_hi: float, d0: float, panels_per_decade: int = PANELS_PER_DECADE
) -> Array:
    """Panel edges [1/m] from ``q_L`` to ``q_hi``, graded towards ``q_L``.

    ``q - q_L = q_L t 10^(-k/2)`` (two per decade of ``q - q_L``, ``t = min(1, q_hi/q_L - 1)``)
    down to ``<= q_L d0``, then the log grid and PSD breakpoints of :func:`panel_edges` above
    ``q_L (1 + t)``. ``d0`` [1] is the relative width of the first panel (where the area is
    still ~1); ``d0 >= t`` gives :func:`panel_edges`.
    """
    edges = panel_edges(psd, [q_hi], panels_per_decade)
    q_L = float(psd.q_L)
    top = min(1.0, q_hi / q_L - 1.0)
    if d0 >= top:
        return edges
    n = int(np.ceil(2.0 * np.log10(top / d0)))
    ladder = q_L * (1.0 + top * np.logspace(-n / 2.0, 0.0, n + 1))
    keep = edges[(edges >= ladder[-1]) | (edges == q_L)]
    inner = edges[(edges > q_L) & (edges < ladder[-1]) & np.isin(edges, psd.nodes())]
    return np.unique(np.concatenate([keep, ladder, inner]))


def _omega_scale(v: ArrayLike, aT: Any) -> Array:
    if callable(aT):  # a_T(q) (flash temperature): scalar v only
        return np.asarray(v, dtype=float)
    return np.asarray(v, dtype=float) * np.asarray(aT, dtype=float)


def _w(v: ArrayLike, aT: Any, q: Array) -> Array:
    """``w = q v a_T`` with shape ``broadcast(v, aT).shape + q.shape``; ``aT`` may be a
    callable ``a_T(q)`` (then ``v`` must be a scalar)."""
    if callable(aT):
        return float(v) * np.asarray(aT(q), dtype=float) * q
    scale = _omega_scale(v, aT)
    return scale.reshape(scale.shape + (1,) * q.ndim) * q


def _cumulative_at(
    psd: Any,
    model: ModulusModel,
    zeta: ArrayLike,
    v: ArrayLike,
    aT: Any,
    which: str,
    n: int,
    ppd: int,
    keep: dict[Any, Any] | None = None,
) -> Array:
    """int_{q_L}^{zeta q_L} q^3 C(q) X(q scale) dq at ``zeta``; shape ``scale.shape + zeta``.

    Panels narrower than the ``panels_per_decade`` grid (a dense ``zeta``) get the reduced
    node counts of :mod:`~xpersson_viscoelastic._panels` (Prony models).

    ``X`` is ``mean_sq - E_r^2`` (``which="tau"``) or ``loss`` (``which="loss"``); ``"both"``
    gives the two stacked on a leading axis of 2. ``zeta`` may have any shape (a scalar gives
    ``scale.shape``). ``keep`` (with ``"both"``) receives the panel edges (``"edges"``) and,
    per node count ``m``, ``(panels, excess, loss)`` at the nodes (for reuse, not recomputed).
    """
    z = np.asarray(zeta, dtype=float)
    q = z * float(psd.q_L)
    scale = _omega_scale(v, aT)
    edges = panel_edges(psd, q, ppd)
    kinks = model.breakpoints()
    if kinks.size and scale.ndim == 0 and not callable(aT) and float(scale) > 0:
        # tabulated models: split the q panels where q v a_T crosses a table frequency
        qk = kinks / float(scale)
        qk = qk[(qk > edges[0]) & (qk < edges[-1])]
        edges = np.unique(np.concatenate([edges, qk]))
    if edges.size < 2:
        return np.zeros(((2,) if which == "both" else ()) + scale.shape + z.shape)
    if keep is not None:
        keep["edges"] = edges

    def sums(sel: Any, qn: Array, wq: Array) -> Array:
        base = qn**3 * np.asarray(psd.C(qn), dtype=float) * wq  # (n_panel, n)
        w = _w(v, aT, qn)  # (..., n_panel, n)
        if which == "both":  # (excess, loss) from one pass: each what the single call gives
            got = model.parts(w)
            if keep is not None:
                keep[int(qn.shape[-1])] = (sel, *got)
            return np.stack([np.sum(X * base, axis=-1) for X in got])
        X = model.excess_mean_sq(w) if which == "tau" else model.angular(w)[1]
        return np.sum(X * base, axis=-1)

    # narrow panels (dense grids) with fewer nodes where that stays at round-off (_panels)
    panel = grouped_sums(edges[:-1], edges[1:], n, sums, reduced_ok(model, aT))
    lead = panel.shape[:-1]  # scale.shape, (2,) + scale.shape for "both"
    cum = np.concatenate([np.zeros(lead + (1,)), np.cumsum(panel, axis=-1)], axis=-1)
    idx = np.searchsorted(edges, np.clip(q, edges[0], edges[-1]))
    return cum[..., idx].reshape(lead + z.shape)


def _checked_nu(nu: float) -> float:
    if not -1.0 < nu <= 0.5:
        raise ValueError(f"nu must lie in (-1, 0.5], got {nu!r}")
    return 1.0 - nu * nu


def diffusion_time(
    psd: Any,
    model: ModulusModel,
    nu: float,
    zeta: ArrayLike,
    v: ArrayLike = 0.0,
    aT: ArrayLike = 1.0,
    *,
    nodes: int = NODES,
    panels_per_decade: int = PANELS_PER_DECADE,
) -> Array:
    """Diffusion time ``tau(zeta; v, a_T)`` [Pa^2] of the sliding contact.

    Parameters
    ----------
    psd : PowerSpectrum
        Roughness spectrum (``C`` in m^4, ``I3``, ``nodes``, ``q_L`` [1/m]).
    model : ModulusModel
        Modulus at the reference temperature.
    nu : float
        Poisson ratio [1].
    zeta : array_like
        Magnifications [1], >= 1.
    v, aT : array_like
        Sliding speed [m/s] and shift factor [1], broadcast together (shape ``S``); ``aT``
        may also be a callable ``a_T(q)`` of the wavevector [1/m] (flash temperature; then
        ``v`` is a scalar).

    Returns
    -------
    ndarray, shape ``S + zeta.shape``
        Any ``zeta`` shape (scalar, 1-D, the 2-D arrays a boundary's clock passes) is kept.
    """
    f = _checked_nu(nu)
    z = np.asarray(zeta, dtype=float)
    exact = model.E_r**2 * np.asarray(psd.I3(z * float(psd.q_L)), dtype=float)
    rest = _cumulative_at(psd, model, z, v, aT, "tau", nodes, panels_per_decade)
    return (np.pi / 4.0) * (exact + rest) / (f * f)


def coefficient_f(
    psd: Any,
    model: ModulusModel,
    nu: float,
    zeta: ArrayLike,
    v: ArrayLike = 0.0,
    aT: ArrayLike = 1.0,
) -> Array:
    """Diffusion coefficient ``f = d tau / d zeta = (pi/4) q_L q^3 C(q) <|E|^2> / (1-nu^2)^2``
    [Pa^2] at ``zeta`` (shape ``broadcast(v, aT).shape + zeta.shape``, any ``zeta`` shape)."""
    f = _checked_nu(nu)
    z = np.asarray(zeta, dtype=float)
    q = z * float(psd.q_L)
    mean_sq, _ = model.angular(_w(v, aT, q))
    return (np.pi / 4.0) * float(psd.q_L) * q**3 * np.asarray(psd.C(q)) * mean_sq / (f * f)


def angular_averages(
    psd: Any,
    model: ModulusModel,
    nu: float,
    zeta: ArrayLike,
    v: ArrayLike = 0.0,
    aT: ArrayLike = 1.0,
) -> tuple[Array, Array]:
    """``(sqrt(<|E|^2>) / (1 - nu^2) [Pa], int cos(phi) Im E dphi / (1 - nu^2) [Pa])`` at
    the scales ``q = zeta q_L`` (shape ``broadcast(v, aT).shape + zeta.shape``)."""
    f = _checked_nu(nu)
    q = np.asarray(zeta, dtype=float) * float(psd.q_L)
    mean_sq, loss = model.angular(_w(v, aT, q))
    return np.sqrt(mean_sq) / f, loss / f


def loss_integral(
    psd: Any,
    model: ModulusModel,
    nu: float,
    zeta: ArrayLike,
    v: ArrayLike = 0.0,
    aT: ArrayLike = 1.0,
    *,
    nodes: int = NODES,
    panels_per_decade: int = PANELS_PER_DECADE,
) -> Array:
    """Cumulative loss integral ``L(zeta; v, a_T)`` [Pa] (see the module docstring)."""
    f = _checked_nu(nu)
    return _cumulative_at(psd, model, zeta, v, aT, "loss", nodes, panels_per_decade) / f


def friction_integral(increments: ArrayLike, p0: ArrayLike) -> Array:
    """``mu = (1 / (2 p0)) int P S dL``, cumulative along the last axis [1].

    The one home of Persson's viscoelastic friction formula
    ``mu_visc = (1/2) int dq q^3 C P S int dphi cos(phi) Im E / ((1 - nu^2) p0)``, written with
    the cumulative loss integral ``L`` [Pa] as ``(1/(2 p0)) int P S dL``.

    Parameters
    ----------
    increments : array_like
        Pieces of ``int P S dL`` [Pa] (quadrature terms ``g_i dL_i`` or per-interval integrals
        from :func:`stieltjes_increments`), along the last axis.
    p0 : array_like
        Nominal pressure(s) [Pa], broadcast against ``increments[..., 0]``.
    """
    inc = np.asarray(increments, dtype=float)
    p0 = np.asarray(p0, dtype=float)
    return np.cumsum(inc, axis=-1) / (2.0 * p0[..., None])


@memoize("viscoelastic.cubic_weights", scope="process", maxsize=32)
def _cubic_weights(x: Array) -> tuple[Array, Array]:
    """Per-interval weights ``W[i, a, b] = int_{x_i}^{x_i+1} l_a(x) l_b'(x) dx`` of the
    4-point Lagrange basis of the stencil ``s_i .. s_i + 3`` (``s_i = clip(i - 1, 0, n - 4)``)
    (:func:`._stencil.interval_weights`; dense grids of a few hundred points in microseconds).
    """
    xs = np.asarray(x)
    n = xs.size
    start = np.clip(np.arange(n - 1) - 1, 0, n - 4)
    return interval_weights(xs, np.arange(n - 1), start), start


def stieltjes_increments(
    g: ArrayLike, L: ArrayLike, x: ArrayLike, weights: tuple[Array, Array] | None = None
) -> Array:
    """``int_{x_i}^{x_{i+1}} g dL`` per interval, from values on a grid ``x`` (last axis).

    ``g`` and ``L`` are both interpolated by cubics in ``x`` (4-point stencils; fourth order
    where they are smooth; trapezoid in ``L`` for fewer than four points). Exactly zero where
    ``L`` is constant on a stencil, so ``E'' = 0`` gives zero friction exactly. For ``g >= 0``
    and non-decreasing ``L`` the pieces are non-negative: an interval where the cubic rule
    would give a negative piece falls back to the trapezoid ``(g_i + g_i+1)/2 (L_i+1 - L_i)``.

    Parameters
    ----------
    g : array_like, (..., n)
        Integrand values (e.g. ``P S``).
    L : array_like, (..., n)
        Cumulative measure (e.g. the loss integral [Pa]).
    x : array_like, (n,)
        Strictly increasing grid (e.g. ``ln zeta``).
    weights : tuple, optional
        ``(W, start)`` of ``x`` computed already (:func:`._stencil.stacked_weights`).
    """
    g = np.asarray(g, dtype=float)
    L = np.asarray(L, dtype=float)
    xs = np.asarray(x, dtype=float)
    trap = 0.5 * (g[..., 1:] + g[..., :-1]) * np.diff(L, axis=-1)
    if xs.size < 4:
        return trap
    W, start = weights or _cubic_weights(np.asarray(xs, dtype=float))
    idx = start[:, None] + np.arange(4)  # (n - 1, 4)
    # sum_a g_a sum_b W_ab L_b: two short contractions (a three-operand einsum is ~9x slower)
    WL = np.sum(W * L[..., idx][..., None, :], axis=-1)
    cubic = np.sum(g[..., idx] * WL, axis=-1)
    return np.where((cubic < 0) & (trap >= 0), trap, cubic)


def _area_factor(A: Array, correction: str, gamma: float) -> Array:
    if correction == "none":
        return A
    if correction == "s_factor":
        return A * closure_S("yp08", A, gamma)
    raise ValueError(f"correction must be 'none' or 's_factor', got {correction!r}")


def first_panel_width(
    psd: Any, model: ModulusModel, fnu: float, p0: float, scale: ArrayLike, q_hi: float
) -> float:
    """Relative width ``d0`` [1] of the first friction panel ``[q_L, q_L (1 + d0)]``.

    Chosen so that ``G(q_L (1 + d0)) <= 1e-3`` (area ~1 across the panel) for every
    ``scale = v a_T`` [m/s] at the smallest load ``p0`` [Pa], from a bound of ``dG/dzeta`` on
    ``[q_L, 2 q_L]`` (``fnu = 1 - nu^2``). ``>= 1`` means no grading is needed.
    """
    q_L = float(psd.q_L)
    qs = np.minimum(q_L * np.array([1.0, 1.25, 1.5, 1.75, 2.0]), q_hi)
    w = np.ravel(np.asarray(scale, dtype=float))[:, None] * qs
    mean_sq = np.max(np.asarray(model.angular(w)[0]), axis=0)
    dens = np.max(qs**3 * np.asarray(psd.C(qs), dtype=float) * mean_sq)
    slope = 2.0 * (np.pi / 4.0) * q_L * dens / (fnu * p0) ** 2  # dG/dzeta, with margin 2
    return float(min(1.0, 1e-3 / slope)) if slope > 0 else 1.0
