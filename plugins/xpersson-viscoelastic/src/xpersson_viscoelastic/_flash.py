"""Opt-in, approximate flash temperature T(q) (physics.md §4.5, structure only).

The frictional heat produced at the longer length scales q' < q warms the rubber that the
scale q sees. With the building blocks of §4.5 (uniform flux J on a half-space for a contact
time t_c: surface rise 2 (J/k) sqrt(D t_c / pi)), the flux per unit *real* contact area at
scale q', J = p0 v dmu / P = v dL / 2 (the area cancels: ``dmu = P dL / (2 p0)``), and
``t_c = r / v`` with ``r = pi / q'`` (half a wavelength), the increments add to

    T(q) = T0 + (1/k) int_{q_L}^{q} sqrt(D v / q') dL(q'; T(q'))

with ``dL = q'^3 C(q') int cos(phi) Im E(q' v a_T(T(q')) cos phi) dphi dq' / (1 - nu^2)``.
This is a Volterra equation in ``T(q)`` (independent of the load, with S = 1 and without the
heat of the contact shear term), solved on the Gauss-Legendre nodes in ``ln q`` by damped
fixed-point iteration. Approximate: Persson's kernel (J. Phys.: Condens. Matter 18, 7789
(2006)) was not available to check against; use for trends, not as an oracle.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from xpersson.cache import Cache

from ._modulus import ModulusModel
from ._shift import ShiftLaw

__all__ = ["FlashProfile", "flash_profile", "solve_flash"]

_FLASH = Cache(
    "viscoelastic.flash",
    scope="spectrum",
    maxsize=8,
    doc="the solved flash-temperature profile of a spectrum, modulus and sliding",
)

Array = NDArray[np.float64]


@dataclass(frozen=True)
class FlashProfile:
    """Solved flash temperature: ``T(q) = T0 + int_{ln q_L}^{ln q} dens d(ln q')``.

    ``dens`` (``dT/d ln q`` [K]) is known at the Gauss-Legendre nodes of panels in ``ln q``;
    :meth:`__call__` integrates its polynomial interpolant, so ``T(q)`` is accurate to the
    quadrature's order at any ``q``.

    Attributes
    ----------
    T0 : float
        Bulk temperature [K].
    log_edges : ndarray
        Panel edges in ``ln q`` (``q`` in 1/m).
    dens : ndarray, (n_panel, n)
        ``dT / d ln q`` [K] at the nodes.
    iterations : int
        Fixed-point iterations used.
    converged : bool
        Whether the last update was below the tolerance.
    """

    T0: float
    log_edges: Array
    dens: Array
    iterations: int
    converged: bool

    def __call__(self, q: Any) -> Array:
        """Temperature [K] at wavevectors ``q`` [1/m] (clamped to ``[q_L, q_1]``)."""
        from ._gauss import spectral_rule as _rule

        n = self.dens.shape[-1]
        x_nodes, w, _ = _rule(n)
        e = self.log_edges
        half = 0.5 * (e[1:] - e[:-1])
        cum = np.concatenate([[0.0], np.cumsum(half * (self.dens @ w))])
        s = np.clip(np.log(np.asarray(q, dtype=float)), e[0], e[-1])
        m = np.clip(np.searchsorted(e, s, side="right") - 1, 0, e.size - 2)
        x = (s - 0.5 * (e[m] + e[m + 1])) / half[m]
        # int_{-1}^{x} l_j: Legendre coefficients of the Lagrange basis, integrated
        L = np.polynomial.legendre
        C = np.linalg.inv(L.legvander(x_nodes, n - 1))
        Vint = np.stack([L.legval(x, L.legint(np.eye(n)[k], lbnd=-1)) for k in range(n)], -1)
        part = half[m] * np.sum((Vint @ C) * self.dens[m], axis=-1)
        return self.T0 + cum[m] + part


def solve_flash(
    psd: Any,
    model: ModulusModel,
    shift: ShiftLaw,
    nu: float,
    v: float,
    T0: float,
    conductivity: float,
    diffusivity: float,
    *,
    panels_per_decade: int = 8,
    nodes: int = 8,
    tol: float = 1e-6,
    maxiter: int = 200,
) -> FlashProfile:
    """Solve the flash-temperature Volterra equation (module docstring).

    Parameters
    ----------
    psd : PowerSpectrum
        Roughness spectrum (m^4, 1/m).
    model : ModulusModel
        Modulus at the shift law's reference temperature.
    shift : ShiftLaw
        ``a_T(T)``.
    nu : float
        Poisson ratio [1].
    v : float
        Sliding speed [m/s].
    T0 : float
        Bulk rubber temperature [K].
    conductivity : float
        Thermal conductivity ``k`` [W/(m K)].
    diffusivity : float
        Thermal diffusivity ``D`` [m^2/s].
    tol : float
        Stopping rule: max change of ``T`` between iterations [K].
    """
    from ._gauss import spectral_rule as _rule
    from .kernel import _nodes, panel_edges

    fnu = 1.0 - nu * nu
    edges = panel_edges(psd, [float(psd.q_1)], panels_per_decade)
    qn, _, _, half = _nodes(edges, nodes)
    _, wgl, Q = _rule(nodes)
    q3C = qn**3 * np.asarray(psd.C(qn), dtype=float)
    # heat weight per unit loss density: sqrt(D v / q) / k, integrand in ln q
    weight = np.sqrt(diffusivity * v / qn) / conductivity * q3C * qn / fnu
    T = np.full(qn.shape, float(T0))
    dens = np.zeros(qn.shape)
    converged, it = v == 0.0, 0
    while not converged and it < maxiter:
        it += 1
        shift.check(T)
        _, loss = model.parts(v * shift.aT(T) * qn)
        dens = weight * loss  # dT/d ln q
        within = half[:, None] * (dens @ Q.T)
        ends = np.sum(half[:, None] * wgl * dens, axis=-1)
        before = np.concatenate([[0.0], np.cumsum(ends)[:-1]])
        T_new = T0 + before[:, None] + within
        step = float(np.max(np.abs(T_new - T)))
        T = 0.5 * (T + T_new) if it > 20 else T_new  # damp slow cases
        converged = step <= tol
    if it:  # the density of the converged temperatures
        dens = weight * model.parts(v * shift.aT(T) * qn)[1]
    return FlashProfile(float(T0), np.log(edges), dens, it, bool(converged))


def flash_profile(
    psd: Any,
    model: ModulusModel,
    shift: ShiftLaw,
    nu: float,
    v: float,
    T0: float,
    conductivity: float,
    diffusivity: float,
) -> FlashProfile:
    """:func:`solve_flash` once per content of its arguments (``"viscoelastic.flash"``).

    Raises
    ------
    RuntimeError
        When the fixed point does not converge.
    """
    args = (psd, model, shift, nu, v, T0, conductivity, diffusivity)
    prof = _FLASH.get(args, lambda: solve_flash(*args))
    if not prof.converged:
        raise RuntimeError(
            f"flash temperature: the fixed point did not converge in {prof.iterations} "
            "iterations; lower the sliding speed or raise thermal_conductivity"
        )
    return prof
