"""The frozen, SI-only view of a resolved scene that plugins compute with."""

from __future__ import annotations

from collections.abc import Callable, Hashable, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..cache import Cache

__all__ = ["SceneContext", "DiffusionClock"]


@dataclass(frozen=True)
class SceneContext:
    """Everything a plugin may read: SI floats and numpy arrays, no pint, no xarray.

    Attributes
    ----------
    psd : object
        The numerical power spectrum (``C(q)`` in m^4, Persson convention; ``q_L``, ``q_1`` in
        1/m): the coefficient's and the boundary's. An analysis reads the solve's spectrum from
        the Dataset instead (:func:`xpersson.plugins.stored.spectrum_of`, the same numbers bit
        for bit), which is all an archive reopened later carries.
    E : float
        Young's modulus of the elastic solid [Pa].
    nu : float
        Poisson ratio [1].
    E_star : float
        Contact modulus E / (1 - nu^2) [Pa].
    p0 : numpy.ndarray
        Nominal pressures, shape ``(n_load,)`` [Pa].
    zeta : numpy.ndarray
        Output magnifications, increasing, ``zeta[0] == 1`` [1].
    p : numpy.ndarray or None
        Pressure grid where the PDF is wanted [Pa]; ``None`` when the scene does not ask for P.
    rtol, atol : float
        Requested accuracy of the contact area (relative, absolute).
    method : str or type
        Engine method (``"auto"`` picks exact paths where they exist).
    options : Mapping
        Free-form solver options.
    coefficient, boundary : Plugin or None
        The scene's coefficient and boundary instances (set for analyses, which read their
        declarations: traits, area variables, ``variance_factor``); ``None`` elsewhere.
    solve_at : Callable or None
        For analyses: ``solve_at(zeta, loads=None) -> {name: array (n_sel, n_zeta)}`` evaluates
        the *same* solve (coefficient, walls, engine, boundary interpretation) at other
        magnifications for the loads with indices ``loads`` (default all), returning
        ``area_fraction``, ``non_contact_fraction``, ``diffusion_time`` (n_zeta,),
        ``effective_diffusion_time`` and the boundary's variables. Analyses that integrate over
        zeta use it to sample the area curve densely where the output grid is too coarse. An
        analysis that already has tau(zeta) [Pa^2] there (a block's stacked call) passes it as
        ``tau=`` (used where the coefficient's effective tau is tau for every load).
    clock : DiffusionClock or None
        The run's diffusion clock for the same loads, the one :meth:`Boundary.walls` received:
        set by the pipeline for :meth:`Boundary.interpret` (whose signature has no clock), so a
        boundary reads it from the context instead of keeping it on ``self`` between calls;
        ``None`` in every other call.
    """

    psd: Any
    E: float
    nu: float
    E_star: float
    p0: np.ndarray
    zeta: np.ndarray
    p: np.ndarray | None = None
    rtol: float = 1e-6
    atol: float = 1e-12
    method: Any = "auto"
    options: Mapping[str, Any] = field(default_factory=dict)
    coefficient: Any = None
    boundary: Any = None
    solve_at: Callable[..., Mapping[str, np.ndarray]] | None = field(
        default=None, compare=False, repr=False
    )
    clock: DiffusionClock | None = field(default=None, compare=False, repr=False)

    @property
    def q_L(self) -> float:
        """Lower cut-off wavevector [1/m]."""
        return float(self.psd.q_L)

    @property
    def zeta_max(self) -> float:
        """Largest output magnification [1]."""
        return float(self.zeta[-1])

    @property
    def q(self) -> np.ndarray:
        """Wavevectors of the output magnifications [1/m]."""
        return self.zeta * self.q_L


_CLOCK_NODES = Cache(
    "plugins.clock_nodes",
    scope="spectrum",
    maxsize=64,
    doc="a diffusion clock's inverse tables, by the clock's content key (DiffusionClock.key)",
)


@dataclass(frozen=True)
class DiffusionClock:
    """Maps between magnification zeta and diffusion time tau.

    Attributes
    ----------
    tau_fn : Callable
        tau(zeta) = int_1^zeta f dzeta [Pa^2], increasing.
    f : Callable
        f(zeta) [Pa^2].
    zeta_max : float
        Largest magnification of interest [1].
    kinks : tuple of float, optional
        Magnifications where ``f`` is known to have a kink (e.g. the spectrum's nodes q/q_L);
        the inverse's table includes them, so that its start is accurate enough for a single
        Newton step. Only a hint: any zeta works without.
    key : hashable, optional
        A content key of the functions ``tau_fn`` and ``f`` (:func:`xpersson.cache.content_key`
        of what they depend on: equal keys, equal functions), given by whoever knows it (the
        pipeline, from :meth:`~xpersson.plugins.Coefficient.clock_key`). With a key, the
        inverse's tables are shared by the clocks of later solves (a ``"spectrum"`` cache) and
        tables derived from the clock may be keyed on it; ``None``: nothing is shared.
    """

    tau_fn: Callable[[np.ndarray], np.ndarray]
    f: Callable[[np.ndarray], np.ndarray]
    zeta_max: float
    kinks: tuple[float, ...] = ()
    key: Hashable | None = field(default=None, compare=False)
    _tables: list = field(init=False, repr=False, compare=False, default_factory=list)
    _last: list = field(init=False, repr=False, compare=False, default_factory=list)

    @property
    def _table(self) -> tuple[np.ndarray, np.ndarray]:
        """(zeta, tau) nodes of the inverse, tabulated on first use (elastic walls never ask)."""
        return self._nodes()[:2]

    def _nodes(self) -> tuple[np.ndarray, ...]:
        """(zeta, tau) at the nodes of the inverse and the cubic start's tables (see
        :meth:`_start`), computed on first use (shared by equal :attr:`key`)."""
        if not self._tables:
            if self.key is None:
                self._tables.append(self._build_nodes())
            else:
                key = (self.key, self.zeta_max, self.kinks)
                self._tables.append(_CLOCK_NODES.get(key, self._build_nodes))
        return self._tables[0]

    def _build_nodes(self) -> tuple[Any, ...]:
        """The tables of :meth:`_nodes`."""
        # 100 nodes per decade, 50 more log-spaced in zeta - 1 up to zeta = 2 (where
        # log(zeta - 1) is the natural variable) and the declared kinks of f: the cubic
        # start is then within ~1e-7 (one Newton step) for piecewise power-law spectra
        n = max(64, int(100 * np.log10(max(self.zeta_max, 10.0))))
        z_end = max(self.zeta_max, 1.0 + 1e-12)
        z = np.exp(np.linspace(0.0, np.log(z_end), n))  # log-spaced (cheaper than geomspace)
        z[0], z[-1] = 1.0, z_end
        extra = [1.0 + np.logspace(-6.0, 0.0, 50)]
        if self.kinks:
            extra.append(np.asarray(self.kinks, dtype=float).ravel())
        extra = np.concatenate(extra)
        extra = extra[np.isfinite(extra) & (extra > 1.0) & (extra < z_end)]
        z = np.unique(np.concatenate([z, extra]))
        tau = np.asarray(self.tau_fn(z), dtype=float)
        f = np.asarray(self.f(z), dtype=float)
        with np.errstate(all="ignore"):
            # beyond the first node: log(zeta - 1) against log(tau), slopes d/d log tau;
            # per interval the cubic y0 + s (d0 + s (c2 + s c3)) in s = (u - u0) / h
            u = np.log(tau[1:])
            y = np.log(z[1:] - 1.0)
            m = tau[1:] / (f[1:] * (z[1:] - 1.0))
            h = np.diff(u)
            usable = bool(
                tau[1] > 0
                and np.all(h > 0)
                and np.all(np.isfinite(m))
                and np.all(np.isfinite(y))
                and f[0] > 0
            )
            d0, d1, dy = h * m[:-1], h * m[1:], np.diff(y)
            cubic = (u[:-1], 1.0 / h, y[:-1], d0, 3.0 * dy - 2.0 * d0 - d1, d0 + d1 - 2.0 * dy)
            # first interval (from tau = 0): the cubic in (tau, zeta) with slopes 1/f
            w = tau[1] - tau[0]
            first = (tau[0], tau[1], z[0], z[1], w / f[0], w / f[1])
        return z, tau, np.log(z), usable, u, cubic, first

    def tau_of_zeta(self, zeta: np.ndarray | float) -> np.ndarray:
        """Diffusion time [Pa^2] at magnification ``zeta`` [1]."""
        return np.asarray(self.tau_fn(np.asarray(zeta, dtype=float)), dtype=float)

    def zeta_of_tau(self, tau: np.ndarray | float) -> np.ndarray:
        """Magnification [1] reached at diffusion time ``tau`` [Pa^2] (monotone inverse).

        Started from a cubic Hermite interpolation of the tabulated relation (exact slopes
        1/f), then polished by Newton steps on tau(zeta) - tau = 0 with derivative f(zeta);
        relative accuracy ~1e-12.
        """
        t = np.asarray(tau, dtype=float)
        flat = t.ravel()
        # a wall's position, speed and the output times: often the same tau values again
        for raw, zr, _, _ in self._last:  # the very same times: no search
            if raw.shape == flat.shape and np.array_equal(raw, flat):
                return zr.reshape(t.shape).copy()
        ends = flat[[0, -1]] if flat.size else flat
        for _, _, ts, zs in self._last:  # a subset of earlier times
            # (its first and last time first: a level's new times fail there, and the whole
            # search cost ~0.7 ms per load on the plastic design's largest scene)
            if not ts.size:
                continue
            if not np.array_equal(ts[np.minimum(np.searchsorted(ts, ends), ts.size - 1)], ends):
                continue
            idx = np.minimum(np.searchsorted(ts, flat), ts.size - 1)
            if np.array_equal(ts[idx], flat):
                return zs[idx].reshape(t.shape)
        z = self._zeta_of_tau(t)
        order = np.argsort(flat, kind="stable")
        zf = z.ravel()
        self._last[:] = [(flat.copy(), zf.copy(), flat[order], zf[order]), *self._last[:2]]
        return z

    def _zeta_of_tau(self, t: np.ndarray) -> np.ndarray:
        nodes = self._nodes()
        zt, tt, logz = nodes[:3]
        inside = (t > tt[0]) & (t < tt[-1])
        if not np.any(inside):  # table end points (tau = 0: zeta = 1): nothing to polish
            return np.exp(np.interp(t, tt, logz))
        z = self._start(t, nodes)
        sel = None if inside.all() else np.flatnonzero(inside)  # tau = 0, table end: exact
        zi, ti = (z, t) if sel is None else (z.ravel()[sel], t.ravel()[sel])
        z_end = zt[-1]
        for _ in range(4):
            fz = np.asarray(self.f(zi), dtype=float)
            pos = fz > 0
            step = self.tau_of_zeta(zi) - ti
            if pos.all():
                step /= fz
            else:  # no Newton step where f = 0
                step = np.where(pos, step / np.where(pos, fz, 1.0), 0.0)
            zi = zi - step
            np.maximum(zi, 1.0, out=zi)
            np.minimum(zi, z_end, out=zi)
            rel = float(np.max(np.abs(step) / zi))
            # converged: Newton's quadratic regime. tau is C^1 with a Lipschitz derivative f
            # (also across kinks of f), so a relative step of 1e-7 leaves an error of order
            # (|f'| zeta / 2 f) 1e-14; a start farther off gives a larger step, and another
            if rel <= 1e-7:
                break
        if sel is None:
            return zi
        z = z.copy()
        z.ravel()[sel] = zi
        return z

    @staticmethod
    def _start(t: np.ndarray, nodes: tuple) -> np.ndarray:
        """Newton's start: cubic Hermite interpolation of the tabulated inverse with its exact
        slopes (d zeta / d tau = 1 / f), in (log tau, log(zeta - 1)) beyond the first node and in
        (tau, zeta) before it; log-linear interpolation where the table does not allow it
        (f = 0 somewhere, flat tau)."""
        zt, tt, logz, usable, u, cubic, first = nodes
        if not usable:
            return np.exp(np.interp(t, tt, logz))
        u0, inv_h, y0, d0, c2, c3 = cubic
        with np.errstate(all="ignore"):
            ut = np.log(t)
            k = np.searchsorted(u, ut)
            k -= 1
            np.maximum(k, 0, out=k)
            np.minimum(k, u0.size - 1, out=k)
            s = (ut - u0[k]) * inv_h[k]
            y = c3[k]
            y *= s
            y += c2[k]
            y *= s
            y += d0[k]
            y *= s
            y += y0[k]
            z = np.exp(y, out=y)
            z += 1.0
            low = t <= first[1]  # before the first node (and tau = 0)
            if low.any():
                t0, t1, z0, z1, g0, g1 = first
                z[low] = _hermite((t[low] - t0) / (t1 - t0), z0, z1, g0, g1)
        z[t >= tt[-1]] = zt[-1]  # the table's end (no extrapolation)
        np.maximum(z, 1.0, out=z)
        np.minimum(z, zt[-1], out=z)
        return z


def _hermite(s: np.ndarray, y0: Any, y1: Any, d0: Any, d1: Any) -> np.ndarray:
    """Cubic Hermite interpolant on [0, 1] (values y0, y1; slopes d0, d1 per unit s)."""
    s2 = s * s
    return y0 + s * d0 + s2 * (3 * (y1 - y0) - 2 * d0 - d1) + s2 * s * (2 * (y0 - y1) + d0 + d1)
