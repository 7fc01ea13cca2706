"""SolvedContact: energy, mean gap, stiffness, detachment of one solved area curve."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..cache import Cache
from ._curve import (
    _Curve,
    _edges,
    _loads,
    _q_max,
    _q_rule,
    _QRule,
    _tau_c,
)
from ._energy import full_contact_energy
from ._gap_band import counted
from ._gap_distribution import Detachment
from ._percolation import critical_magnification
from ._phi import _Phi
from ._subgap import _h2, _sub_mean_gap, _sub_prep

__all__ = ["STEP_SHARE", "SolvedContact"]

#: Largest step of ``u1``'s difference quotient (:meth:`SolvedContact.separation_at`) as a
#: share of ``ln zeta_at``. Near ``zeta = 1`` the area falls on the scale of ``ln zeta`` itself
#: (steep spectra at low load: from 1 to ``a_c`` within ``ln zeta < 1e-3``), so a fixed step
#: of 1e-3 read a secant, not the derivative: 9-11 % too large at ``ln zeta_c = 6e-4 - 1e-3``
#: and 0.13 % at 1e-2 (held-out flat H = 0.87 4dec of ``benchmarks/summary.py --held-out
#: 4242``), against 0.7-2e-5 with a step of 1 % of ``ln zeta_c`` (the error of the fixed
#: step at ``ln zeta_c = 0.1``, where the two meet; ``benchmarks/leakage_junction_step.py``).
STEP_SHARE = 0.01

_Q_RULES = Cache(
    "physics.q_rule",
    scope="spectrum",
    maxsize=64,
    doc="quadrature rule over [q_L, q_hi] of the elastic energy and the mean gap",
)
_EDGE_PREP = Cache(
    "physics.edge_prep",
    scope="spectrum",
    maxsize=32,
    doc="sub-problem nodes and rms heights at the detachment bins' edges",
)


class SolvedContact:
    """The solved contact of every load: one area curve, every interface quantity (cached).

    The functions of this module are thin wrappers; build one :class:`SolvedContact` when
    several quantities of the same curve are needed (the curve's splines and ``Phi`` are built
    once).

    Parameters
    ----------
    psd : PowerSpectrum
        Roughness spectrum (m^4).
    E_star : float
        Contact modulus [Pa].
    p0 : array_like, (n_load,)
        Nominal pressures [Pa].
    zeta, area, s_factor, non_area
        The curve, as in :func:`elastic_energy` (``zeta`` may also be a prepared curve object).
    """

    def __init__(
        self,
        psd: object,
        E_star: float,
        p0: ArrayLike,
        zeta: ArrayLike | _Curve,
        area: ArrayLike | None = None,
        s_factor: ArrayLike | None = None,
        non_area: ArrayLike | None = None,
    ) -> None:
        self.psd = psd
        self.E_star = float(E_star)
        self.curve = zeta if isinstance(zeta, _Curve) else _Curve(zeta, area, s_factor, non_area)
        self.p0 = _loads(p0, self.curve.n_load)
        self.q_L = float(psd.q_L)  # type: ignore[attr-defined]
        self.q_hi = _q_max(psd, self.curve.zeta)
        self._phi: _Phi | None = None
        self._u: NDArray[np.float64] | None = None
        self._rule: _QRule | None = None

    def rows(self, sel: ArrayLike) -> SolvedContact:
        """The SolvedContact of some of the loads, its set-up sliced rather than built again.

        The curve's splines, ``Phi``'s node integrals and spline and the mean gap, where
        already built, are sliced to the rows ``sel`` (each load's rows are its own, so every
        quantity is that of a SolvedContact built for these loads alone, bit for bit);
        ``Phi``'s look-up table is built for them when first asked.

        Parameters
        ----------
        sel : array_like of int, (n_sel,)
            Indices of the loads kept, in the order wanted.

        Returns
        -------
        SolvedContact
            The contact of the loads ``p0[sel]`` [Pa] (same spectrum, ``E*`` and
            magnifications).
        """
        sel = np.asarray(sel, dtype=np.intp)
        out = object.__new__(SolvedContact)
        out.psd, out.E_star, out.q_L, out.q_hi = self.psd, self.E_star, self.q_L, self.q_hi
        out.curve, out.p0 = self.curve.rows(sel), self.p0[sel]
        out._phi = None if self._phi is None else self._phi.rows(sel)
        out._u = None if self._u is None else self._u[sel]
        out._rule = self._rule
        return out

    @property
    def phi(self) -> _Phi:
        if self._phi is None:
            self._phi = _Phi(self.psd, self.E_star, self.p0, self.curve)
        return self._phi

    @property
    def rule(self) -> _QRule:
        """The quadrature rule over ``[q_L, q_hi]`` of the energy and the mean gap (built once)."""
        if self._rule is None:
            key = (self.psd, self.q_L, self.q_hi)
            self._rule = _Q_RULES.get(key, lambda: _q_rule(self.psd, self.q_L, self.q_hi))
        return self._rule

    def elastic_energy(self) -> NDArray[np.float64]:
        """``U_el/A0`` [J/m^2], (n_load,) (see :func:`elastic_energy`)."""
        r = self.rule
        # row by row (einsum, not BLAS: a load's sum never depends on the others' count)
        deficit = np.einsum(
            "ij,j->i", self.curve.nf(np.log(r.q / self.q_L)), r.weights * r.q**2 * r.C
        )
        full = full_contact_energy(self.psd, self.E_star, self.q_L, self.q_hi)
        return full - 0.5 * math.pi * self.E_star * deficit

    def mean_gap(self) -> NDArray[np.float64]:
        """``u(p0)`` [m], (n_load,) (see :func:`mean_gap`)."""
        if self._u is None:
            r = self.rule
            vals = self.phi.at_tau(0.25 * np.pi * self.E_star**2 * r.dI3)
            # row by row (einsum, not BLAS: a load's sum never depends on the others' count)
            self._u = math.pi * np.einsum("ij,j->i", vals, r.weights * r.q**2 * r.C * r.w)
        return self._u.copy()

    def mean_gap_slope(self) -> NDArray[np.float64]:
        """``du/dp0`` [m/Pa], (n_load,) (see :func:`mean_gap_slope`)."""
        xg, wg = self.curve.stieltjes_nodes()
        q = np.exp(xg) * self.q_L
        g = _tau_c(self.psd, self.E_star, q) / q * wg
        dF = self.curve.dF_weighted(g)  # node sums of dF(xg) g
        return -4.0 / (self.E_star * self.p0**2) * np.sum(dF, axis=1)

    def contact_stiffness(self) -> NDArray[np.float64]:
        """``K = -dp0/du`` [Pa/m], (n_load,) (see :func:`contact_stiffness`)."""
        s = self.mean_gap_slope()
        with np.errstate(divide="ignore"):
            return np.where(s < 0, -1.0 / np.where(s < 0, s, -1.0), np.inf)

    def detachment(
        self,
        zeta_edges: ArrayLike | None = None,
        separation: str = "almqvist",
        *,
        negligible: float = 0.0,
    ) -> Detachment:
        """Detached-area bins (see :func:`detachment`).

        ``negligible`` > 0: the bins whose weight is below that fraction of the load's
        largest (those :func:`~xpersson.physics.gap_cdf` with the same ``negligible`` leaves
        out) get ``u1 = 0`` without computing it, and ``ubar`` is computed only at the edges
        that the other bins' ``u1`` reads (both with ``"almqvist"``, the upper one with
        ``"pressure"``; elsewhere not computed: 0 or another value; ``ubar[:, 0] = u(p0)``
        always); the weights and the other bins' ``u1`` are the same, bit for bit. Near full
        contact most edges carry such bins alone.

        ``separation`` chooses the mean separation ``u1`` of the area detaching in a bin:

        * ``"almqvist"`` (default): ``u1 = d(A u)/dA`` over the bin (Almqvist et al. 2011).
          Where the coarse scales are in full contact (high load, ``zeta`` near 1) ``dA``
          vanishes like
          ``exp(-1/(4G))`` while ``u(zeta)`` still falls (removing scales at fixed pressure
          lowers Persson's mean gap), so ``u1 ~ A (du/dzeta)_p / A'`` runs off to many
          ``h_rms``: a far tail with vanishing weight (docs/verification.md, "gap PDF").
        * ``"pressure"``: only the part of ``d(A u)/dA`` due to the rise of the pressure
          ``p0/A`` on the remaining contact, ``u1 = u + A (du/dA)_zeta`` (bounded by about
          ``u - p du/dp``). The other part, ``A (du/dzeta)_p``, is the fall of Persson's
          ``u(zeta)`` when scales are removed at fixed pressure: gap content of the region
          still in contact, not of the detaching area, and it is left out, so
          ``sum weight u1`` falls short of ``u(p0)`` by it. Against the GFMD gap histograms
          (xu2024-gfmd) this form is closer at 9 of 12 loads and has no far tail.
        """
        if separation not in ("almqvist", "pressure"):
            raise ValueError(f"separation must be 'almqvist' or 'pressure', got {separation!r}")
        cur, q_L, q_hi = self.curve, self.q_L, self.q_hi
        z, A, N = _edges(cur, zeta_edges)
        prep, h, h_rms = _EDGE_PREP.get(
            (self.psd, self.E_star, q_L, q_hi, z), lambda: self._edge_prep(z)
        )
        dA = N[:, 1:] - N[:, :-1]
        ok = dA > 0
        weight = np.where(ok, dA, 0.0)
        count, needed = ok, None
        if negligible > 0.0:  # the edges the bins that count read (not the first, nor the
            count = ok & counted(weight, negligible)  # last): the upper, and the lower with
            needed = np.zeros(A.shape, dtype=bool)  # "almqvist" ("pressure" reads u_next only)
            needed[:, 1:-1] = count[:, :-1]
            if separation == "almqvist":
                needed[:, 1:-1] |= count[:, 1:]
        ubar = _sub_mean_gap(
            self.psd, self.E_star, self.phi, None, A, q_hi, prep=prep, needed=needed
        )
        ubar[:, 0] = self.mean_gap()
        ubar[:, -1] = 0.0
        safe = np.where(ok, dA, 1.0)
        if separation == "almqvist":
            dAu = A[:, :-1] * ubar[:, :-1] - A[:, 1:] * ubar[:, 1:]
            u1 = np.where(count, dAu / safe, 0.0)
        else:
            u1 = self._pressure_part(z, A, ubar, dA, count, safe, prep)
        return Detachment(self.p0, z, A, ubar, weight, np.maximum(u1, 0.0), h, h_rms)

    def _edge_prep(self, z: NDArray[np.float64]) -> tuple[Any, NDArray[np.float64], float]:
        """What the bins of :meth:`detachment` take from the spectrum alone: the sub-problem
        nodes at every edge (:func:`_sub_prep`), the rms height of the roughness finer than
        each bin's centre and of the whole roughness [m]."""
        q_L, q_hi = self.q_L, self.q_hi
        prep = _sub_prep(self.psd, self.E_star, (z * q_L)[None, :], q_hi)
        h = np.sqrt(_h2(self.psd, np.sqrt(z[:-1] * z[1:]) * q_L, q_hi))
        return prep, h, float(np.sqrt(_h2(self.psd, q_L, q_hi)))

    def _pressure_part(self, z, A, ubar, dA, ok, safe, prep) -> NDArray[np.float64]:  # noqa: ANN001
        """``u1 = u + A (du/dA)_zeta`` of every bin: the pressure part of ``d(A u)/dA``.

        ``prep``: :func:`_sub_prep` at every edge (the upper cut-offs are its edges 1..).
        """
        # u at the bin's upper cut-off under the bin's *initial* pressure p0/A_k, needed in the
        # bins that detach area only; where A_k = A_k+1 (dA below the round-off of A: both 1
        # near full contact) it is u_next itself, the same look-ups and sums bit for bit
        u_next = ubar[:, 1:]
        same = A[:, :-1] == A[:, 1:]
        where = ok & ~same
        where[:, -1] = False  # (0 below: no scales left above the last edge)
        mixed = _sub_mean_gap(
            self.psd,
            self.E_star,
            self.phi,
            None,
            A[:, :-1],
            self.q_hi,
            where=where,
            prep=(prep[0][:, 1:], prep[1][:, 1:]),
        )
        np.copyto(mixed, u_next, where=same)
        mixed[:, -1] = 0.0  # no scales left above the last edge
        # A_k (u(z_k+1, A_k) - u(z_k+1, A_k+1)) / dA >= 0 stays finite as dA -> 0
        return np.where(ok, u_next + A[:, :-1] * (mixed - u_next) / safe, 0.0)

    def critical_magnification(self, a_c: float) -> NDArray[np.float64]:
        """Where the contact area crosses ``a_c`` (see :func:`critical_magnification`)."""
        return critical_magnification(self.curve.zeta, self.curve.area, a_c)

    def separation_at(self, zeta_at: ArrayLike, *, rel_step: float = 1e-3) -> NDArray[np.float64]:
        """``u1 = d(A u_zeta)/dA`` [m] at per-load ``zeta_at`` (see
        :func:`separation_of_detaching_area`; the step at most :data:`STEP_SHARE` of
        ``ln zeta_at``)."""
        cur = self.curve
        za = np.asarray(zeta_at, dtype=float).reshape(-1)
        ok = np.isfinite(za)
        out = np.full(self.p0.size, np.nan)
        if not ok.any():
            return out
        zc = np.where(ok, za, 2.0)
        down, up = np.full(zc.size, math.exp(-rel_step)), np.full(zc.size, math.exp(rel_step))
        near = zc < math.exp(rel_step / STEP_SHARE)  # near zeta = 1: a step of its own
        if near.any():
            h = np.maximum(STEP_SHARE * np.log(np.maximum(zc[near], 1.0)), 1e-12)
            down[near], up[near] = np.exp(-h), np.exp(h)
        zl = np.clip(zc * down, 1.0, cur.zeta[-1])
        zh = np.clip(zc * up, 1.0, cur.zeta[-1])
        xs = np.log(np.stack([zl, zh], axis=1))  # (n_load, 2)
        N = cur.non_area_at(xs)
        A = 1.0 - N
        u = _sub_mean_gap(
            self.psd, self.E_star, self.phi, np.exp(xs) * self.q_L, A, self.q_hi, spline=True
        )
        dA = N[:, 1] - N[:, 0]
        with np.errstate(divide="ignore", invalid="ignore"):
            u1 = (A[:, 0] * u[:, 0] - A[:, 1] * u[:, 1]) / dA
        out[ok] = np.maximum(u1[ok], 0.0)
        return out
