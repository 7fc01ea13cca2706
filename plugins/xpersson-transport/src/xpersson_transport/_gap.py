"""The gas part of the thermal conductance over the solved contact's gap distribution.

The gap distribution is the closed form of physics.md §5.5a (Almqvist et al. 2011), which
``xpersson-interface``'s ``gap_pdf`` samples on a *linear* grid of separations. The integrand
``kappa_g / (u + Lambda)`` weighs the smallest gaps most, and there the distribution has structure
on every scale down to the finest roughness's rms height (the area detaching at the last
magnifications). A linear grid of a few hundred points cannot resolve that, which overestimated
the gas conductance of the heat-sink example 1.5-3x at 1-10 MPa. So this module builds the same
distribution (:func:`xpersson.plugins.solved.solved_curve` on the solved Dataset, then
:func:`xpersson.physics.detachment` and the exact cumulative mass
:func:`xpersson.physics.gap_cdf`). It then integrates

    int_0^inf rho(u) / (u + Lambda) du = int_0^inf F(u) / (u + Lambda)^2 du

(``F`` = detached mass in ``[0, u]``, by parts) on a geometric grid that reaches far below
``Lambda`` and the finest rms height, with ``F`` piecewise linear and each piece integrated
exactly. ``F`` is monotone and bounded, so unresolved narrow bins only shift their mass by
less than one grid ratio.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from xpersson import physics
from xpersson.plugins.solved import solved_curve

__all__ = ["gas_from_cdf", "gap_cdf_grid"]


def gas_from_cdf(
    u: ArrayLike, cdf: ArrayLike, kappa_gas: float, jump: float
) -> NDArray[np.float64]:
    """``kappa_g int_0^inf F(u) / (u + Lambda)^2 du`` with ``F`` piecewise linear on ``u``.

    Parameters
    ----------
    u : array_like, shape (n,)
        Increasing separations starting at 0 [m].
    cdf : array_like, shape (..., n)
        Cumulative detached mass ``F(u) = int_0^u rho`` [1] (``F(0) = 0``); held constant
        beyond ``u[-1]``.
    kappa_gas : float
        Gas thermal conductivity [W m-1 K-1] (0: vacuum, result 0).
    jump : float
        Temperature-jump length ``Lambda >= 0`` [m].

    Returns
    -------
    ndarray, shape (...)
        Conductance per nominal area [W m-2 K-1]; ``inf`` when ``Lambda = 0`` and ``F`` rises
        from ``u = 0`` (the continuum form's logarithmic divergence).
    """
    u = np.asarray(u, dtype=float)
    F = np.asarray(cdf, dtype=float)
    if kappa_gas == 0.0:
        return np.zeros(F.shape[:-1])
    b = u[:-1] + jump
    du = np.diff(u)
    F0, F1 = F[..., :-1], F[..., 1:]
    s = (F1 - F0) / du
    with np.errstate(divide="ignore", invalid="ignore"):
        # int_0^du (F0 + s t)/(b + t)^2 dt = F0 du/(b (b+du)) - s du/(b+du) + s ln(1 + du/b)
        first = np.where(F0 == 0.0, 0.0, F0 * du / (b * (b + du)))
        log_term = np.where(b > 0, np.log1p(du / np.where(b > 0, b, 1.0)), np.inf)
        second = np.where(s == 0.0, 0.0, s * (log_term - du / (b + du)))
    tail = F[..., -1] / (u[-1] + jump)
    return kappa_gas * ((first + second).sum(axis=-1) + tail)


def _edges(zeta: NDArray[np.float64], n_bins: int) -> NDArray[np.float64]:
    """Bin edges geometric in ``zeta - 1`` (as ``gap_pdf`` bins the detached area)."""
    z_max = float(zeta[-1])
    if z_max <= 1.0:
        return zeta
    inner = 1.0 + np.geomspace(1e-9, z_max - 1.0, n_bins)
    return np.unique(np.concatenate(([1.0], inner[inner < z_max], [z_max])))


def gap_cdf_grid(
    ctx: Any,
    ds: Any,
    *,
    s_factor: str = "closure",
    gamma: float | None = None,
    zeta_per_decade: int = 40,
    n_bins: int = 80,
    jump: float = 0.0,
    u_per_decade: int = 100,
    separation: str = "pressure",
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The solved contact's gap distribution as ``(u, F)`` on a geometric grid.

    Parameters
    ----------
    ctx, ds
        The analysis's context and solved Dataset.
    s_factor, gamma, zeta_per_decade, n_bins
        As ``gap_pdf`` of ``xpersson-interface`` (same defaults).
    jump : float
        The gas's ``Lambda`` [m]; the grid starts 1e-3 below ``min(Lambda, h_min)``.
    u_per_decade : int
        Grid points per decade of separation.
    separation : {"pressure", "almqvist"}
        The detaching area's mean separation, as ``gap_pdf``'s parameter of that name.

    Returns
    -------
    u : ndarray, shape (n_u,)
        ``0`` and a geometric grid up to ``max u(p0) + 20 h_rms`` [m].
    F : ndarray, shape (n_load, n_u)
        Detached mass in ``[0, u]`` [1] (the contact weight excluded).
    """
    s = solved_curve(ctx, ds, s_factor, gamma, zeta_per_decade)
    sc = physics.SolvedContact(s.psd, s.E_star, s.p0, *s.curve)  # the Dataset's spectrum, E*
    det = sc.detachment(_edges(s.zeta, n_bins), separation)
    h_pos = det.h[det.h > 0]
    small = min(h_pos.min() if h_pos.size else det.h_rms, jump if jump > 0 else np.inf)
    lo = max(1e-3 * small, 1e-18)
    # bins detaching at vanishing area near zeta = 1 may sit at huge u1: the grid ends at the
    # largest mean gap plus 20 rms heights (mass beyond: < the Gaussian tail), held constant after
    hi = float(np.max(det.ubar[:, 0], initial=0.0)) + 20.0 * det.h_rms
    n = max(2, int(np.ceil(u_per_decade * np.log10(hi / lo))) + 1)
    u = np.concatenate(([0.0], np.geomspace(lo, hi, n)))
    return u, physics.gap_cdf(det, u)
