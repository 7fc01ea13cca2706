"""A finite body on a rough flat: the self-consistent nominal pressure (numpy in, numpy out).

A smooth body of undeformed gap ``h(r)`` (``h(0) = 0``) is pressed by a load ``L`` on a
nominally flat rough half-space. The rough interface acts as a nonlinear spring: at every point
of the nominal contact the mean interfacial separation is Persson's ``u(p)`` of the local
nominal pressure (Persson 2007, "Relation between interfacial separation and load"; the
interface plugin's ``mean_gap``), and the real contact area is ``A/A0(p)``. The macroscopic
deformation is that of an elastic half-space of contact modulus ``E*`` (Johnson 1985). The
nominal pressure ``p(r) >= 0`` and the rigid-body approach ``delta`` of the mean planes solve

    u(p(r)) = h(r) - delta + w[p](r)     for every r of the grid,
    int p dA = L,

with ``w[p]`` the surface displacement of the half-space: the axisymmetric Boussinesq kernel
(uniform pressure on a disk, Johnson 1985 §3.4, elliptic integrals) for a body of revolution
(``L`` the force [N]), the plane-strain kernel ``-(2/(pi E*)) int p(s) ln(|x - s|/R) ds`` for
a line contact (``L`` the force per length [N/m]; a 2-D approach needs a datum: the displacement
is referred to the distance ``R``). This is Greenwood & Tripp's (1967) rough sphere with
Persson's ``u(p)`` in place of their asperity model.

Discretisation: the pressure is constant on ``n`` uniform cells of ``[0, r_max]`` (rings, or
strips mirrored about ``x = 0``), the gap equation is collocated at the cell centres, and
Newton's method solves for ``s = ln p`` and ``delta`` (bordered by the load balance). ``u`` is
linear in ``ln p`` at small ``p`` (the asymptotic separation), so the equations stay smooth where
the pressure vanishes.

Validity: small slopes (the contact radius well below ``R``), ``E*`` the contact modulus of the
pair, a nominal contact much larger than the roll-off wavelength of the roughness (each point
sees the whole spectrum), and Persson's ``u(p)`` where its asymptotic separation holds.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..cache import memoize

__all__ = [
    "BodySolution",
    "Separation",
    "force_radius",
    "hertz_cylinder",
    "hertz_sphere",
    "kernel",
    "solve_body",
    "start_at_area",
]

FloatArray = NDArray[np.float64]


def hertz_sphere(force: float, R: float, E_star: float) -> tuple[float, float, float]:
    """Hertz: ``(a, delta, p_max)`` = radius [m], approach [m], peak pressure [Pa] of a sphere
    of radius ``R`` [m] under ``force`` [N] (Johnson 1985, eq. 4.22-4.23)."""
    a = (3.0 * force * R / (4.0 * E_star)) ** (1.0 / 3.0)
    return a, a * a / R, 3.0 * force / (2.0 * math.pi * a * a)


def hertz_cylinder(load: float, R: float, E_star: float) -> tuple[float, float, float]:
    """Hertz line contact: ``(b, delta, p_max)``: half-width [m], approach [m] with the datum at
    the distance ``R`` (``delta = (P/(pi E*)) (2 ln(2R/b) + 1)``) and peak pressure [Pa] under
    ``load`` [N/m] (Johnson 1985, eq. 4.45)."""
    b = math.sqrt(4.0 * load * R / (math.pi * E_star))
    delta = load / (math.pi * E_star) * (2.0 * math.log(2.0 * R / b) + 1.0)
    return b, delta, 2.0 * load / (math.pi * b)


def _ring_g(r: FloatArray, a: FloatArray) -> FloatArray:
    """``(pi E*/(4 p)) w`` [m]: displacement at radius ``r`` of a unit pressure on a disk of
    radius ``a`` (times pi/4), by the elliptic integrals of Johnson 1985 eq. 3.38/3.39."""
    from scipy.special import ellipe, ellipk

    r, a = np.broadcast_arrays(np.asarray(r, float), np.asarray(a, float))
    out = np.zeros(r.shape)
    inside = (r < a) & (a > 0)
    outside = (r > a) & (a > 0)
    out[inside] = a[inside] * ellipe((r[inside] / a[inside]) ** 2)
    m = (a[outside] / r[outside]) ** 2
    out[outside] = r[outside] * (ellipe(m) - (1.0 - m) * ellipk(m))
    return out


@memoize("physics.body_kernel", scope="process", maxsize=16)
def kernel(symmetry: str, n: int) -> FloatArray:
    """Dimensionless influence matrix of ``n`` uniform cells: ``w_i = (h/E*) sum_j K_ij p_j``
    at the cell centres (``h`` the cell width [m]).

    ``"axisymmetric"``: rings ``[j h, (j+1) h]``; ``"plane"``: strips mirrored about 0, with
    ``ln|x - s|`` (add ``-(4/pi) ln(h/R)`` to every entry for the datum at distance ``R``).
    """
    xi = np.arange(n, dtype=float)[:, None] + 0.5
    j = np.arange(n, dtype=float)[None, :]
    if symmetry == "axisymmetric":
        return 4.0 / math.pi * (_ring_g(xi, j + 1.0) - _ring_g(xi, j))

    def F(t: FloatArray) -> FloatArray:  # int ln|t| dt
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(t == 0.0, 0.0, t * np.log(np.abs(t)) - t)

    s = F(xi - j) - F(xi - j - 1.0) + F(xi + j + 1.0) - F(xi + j)
    return -2.0 / math.pi * s


def cell_areas(symmetry: str, n: int, h: float) -> FloatArray:
    """Area of each cell [m^2] (rings) or its width on both sides of 0 [m] (strips)."""
    e = np.arange(n + 1, dtype=float) * h
    if symmetry == "axisymmetric":
        return math.pi * np.diff(e * e)
    return np.full(n, 2.0 * h)


@dataclass(frozen=True)
class Separation:
    """The rough interface as the body sees it: ``u``, ``du/dln p`` and ``A/A0`` against ``p``.

    Built from a solve over a pressure grid ``p`` [Pa] (increasing): ``u`` [m] by cubic Hermite
    interpolation in ``ln p`` with the solved slopes, extended linearly in ``ln p`` outside the
    grid (the asymptotic separation below it); the area by monotone interpolation of
    ``ln A`` in ``ln p``, ``A`` proportional to ``p`` below the grid and at most 1 above it.
    """

    p: FloatArray
    u: FloatArray
    dudlnp: FloatArray
    area: FloatArray

    def __post_init__(self) -> None:
        from scipy.interpolate import PchipInterpolator

        x = np.log(self.p)  # the interpolants, built once (an object's own lazily built fields)
        object.__setattr__(self, "_x", x)
        ln_area = np.log(np.maximum(self.area, 1e-300))
        object.__setattr__(self, "_ln_area", PchipInterpolator(x, ln_area))
        # the Hermite cubics in powers of (s - x_i), with the lines below and above the grid as
        # the first and last pieces: piece j holds s in (x_{j-1}, x_j]
        h = np.diff(x)
        y0, y1, m0, m1 = self.u[:-1], self.u[1:], self.dudlnp[:-1], self.dudlnp[1:]
        c2 = (3.0 * (y1 - y0) / h - 2.0 * m0 - m1) / h
        c3 = (m0 + m1 - 2.0 * (y1 - y0) / h) / (h * h)
        zero = np.zeros(1)
        coef = np.stack(
            [
                np.concatenate([self.u[:1], y0, self.u[-1:]]),
                np.concatenate([self.dudlnp[:1], m0, self.dudlnp[-1:]]),
                np.concatenate([zero, c2, zero]),
                np.concatenate([zero, c3, zero]),
            ]
        )
        object.__setattr__(self, "_coef", coef)
        object.__setattr__(self, "_origin", np.concatenate([x[:1], x[:-1], x[-1:]]))

    def __call__(self, s: FloatArray) -> tuple[FloatArray, FloatArray]:
        """``(u, du/ds)`` at ``s = ln p`` (finite)."""
        x = self._x  # type: ignore[attr-defined]
        j = np.searchsorted(x, s)
        c0, c1, c2, c3 = self._coef[:, j]  # type: ignore[attr-defined]
        t = s - self._origin[j]  # type: ignore[attr-defined]
        u = ((c3 * t + c2) * t + c1) * t + c0
        return u, (3.0 * c3 * t + 2.0 * c2) * t + c1

    def area_fraction(self, p: FloatArray) -> FloatArray:
        """``A/A0`` [1] at nominal pressures ``p`` [Pa] (0 where ``p = 0``)."""
        x = self._x  # type: ignore[attr-defined]
        p = np.asarray(p, float)
        with np.errstate(divide="ignore"):
            s = np.log(p)
        inner = np.exp(self._ln_area(np.clip(s, x[0], x[-1])))  # type: ignore[attr-defined]
        below = self.area[0] * p / self.p[0]
        return np.minimum(np.where(s < x[0], below, inner), 1.0)


def start_at_area(
    p: FloatArray, u: FloatArray, dudlnp: FloatArray, area: FloatArray, threshold: float
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """The arrays of a :class:`Separation` from the pressure where ``A/A0 = threshold`` on.

    ``p`` [Pa] increasing, ``u`` [m], ``dudlnp`` [m] and ``area`` [1] at ``p``. The pressure
    ``p*`` where the area crosses ``threshold`` is found on the power law between the two
    solved nodes around it, and ``u``, ``du/dln p`` there on :class:`Separation`'s Hermite
    cubic: the start of the continuation below it does not depend on where the solved
    pressure grid has a node (starting at the node above moved it by up to one grid step in
    ``ln p``). The arrays unchanged when the first area is already at least ``threshold``.
    """
    if area[0] >= threshold:
        return p, u, dudlnp, area
    j = int(np.searchsorted(area, threshold))  # first node at or above the threshold
    if j >= p.size:
        raise ValueError(f"the solved area fraction stays below {threshold:g}")
    x0, x1 = math.log(p[j - 1]), math.log(p[j])
    a0, a1 = math.log(max(area[j - 1], 1e-300)), math.log(area[j])
    s = x0 + (math.log(threshold) - a0) * (x1 - x0) / (a1 - a0)
    h, t = x1 - x0, (s - x0) / (x1 - x0)
    h00, h10, h01, h11 = (
        2 * t**3 - 3 * t**2 + 1,
        t**3 - 2 * t**2 + t,
        -2 * t**3 + 3 * t**2,
        t**3 - t**2,
    )
    y0, y1, m0, m1 = u[j - 1], u[j], dudlnp[j - 1], dudlnp[j]
    u_s = h00 * y0 + h10 * h * m0 + h01 * y1 + h11 * h * m1
    du_s = ((6 * t * t - 6 * t) * (y0 - y1) / h + (3 * t * t - 4 * t + 1) * m0
            + (3 * t * t - 2 * t) * m1)  # fmt: skip
    keep = np.log(p) > s + 1e-12
    return (
        np.concatenate([[math.exp(s)], p[keep]]),
        np.concatenate([[u_s], u[keep]]),
        np.concatenate([[du_s], dudlnp[keep]]),
        np.concatenate([[threshold], area[keep]]),
    )


@dataclass(frozen=True)
class BodySolution:
    """The solved nominal pressure on one grid.

    Attributes
    ----------
    r : ndarray
        Cell centres [m]; ``edges`` the cell edges [m]; ``cell`` the cell areas [m^2] (or
        widths [m] of a line contact).
    p : ndarray
        Nominal pressure per cell [Pa].
    delta : float
        Approach of the mean planes [m].
    stiffness : float
        ``dL/d delta`` [N/m] (or [Pa] per unit length of a line contact).
    residual : float
        Largest gap residual relative to ``scale`` [1].
    iterations : int
        Newton iterations.
    converged : bool
        Whether the residuals fell below the tolerance (else Newton stalled, or ran out of
        iterations, at ``residual``: the last iterate is returned).
    """

    r: FloatArray
    edges: FloatArray
    cell: FloatArray
    p: FloatArray
    delta: float
    stiffness: float
    residual: float
    iterations: int
    converged: bool = True


def force_radius(sols: list[BodySolution], fraction: float, symmetry: str) -> FloatArray:
    """Radius [m] inside which ``fraction`` of the load acts (linear in the cell's area), one
    per solution (solutions of one grid size)."""
    cum = np.cumsum([sol.p * sol.cell for sol in sols], axis=1)
    cum = np.concatenate([np.zeros((cum.shape[0], 1)), cum], axis=1)
    target = fraction * cum[:, -1]
    k = np.clip(np.sum(cum < target[:, None], axis=1) - 1, 0, cum.shape[1] - 2)
    rows = np.arange(cum.shape[0])
    t = (target - cum[rows, k]) / np.maximum(cum[rows, k + 1] - cum[rows, k], 1e-300)
    edges = np.array([sol.edges for sol in sols])
    e0, e1 = edges[rows, k], edges[rows, k + 1]
    if symmetry == "axisymmetric":
        return np.sqrt(e0 * e0 + t * (e1 * e1 - e0 * e0))
    return e0 + t * (e1 - e0)


def solve_body(
    symmetry: str,
    profile: Callable[[FloatArray], FloatArray],
    load: ArrayLike,
    E_star: float,
    sep: Separation,
    r_max: ArrayLike,
    n: int,
    *,
    scale: ArrayLike,
    guess: Callable[[FloatArray], FloatArray],
    datum: float = 1.0,
    tol: float = 1e-10,
    max_iter: int = 200,
) -> list[BodySolution]:
    """Solve the gap equation and the load balance of one or more loads (batched).

    Parameters
    ----------
    symmetry : {"axisymmetric", "plane"}
    profile : callable
        ``h(r)`` [m] (elementwise).
    load : float or array_like
        Forces [N] (axisymmetric) or forces per length [N/m] (plane), one per body.
    E_star : float
        Contact modulus [Pa].
    sep : Separation
        The interface ``u(p)``.
    r_max : float or array_like
        Outer radius of each body's grid [m] (``n`` uniform cells on ``[0, r_max]``).
    n : int
        Cells.
    scale : float or array_like
        Length [m] each gap residual is measured in (the smooth approach).
    guess : callable
        Starting pressure [Pa] at radii [m], shape ``(n_load, n)`` (positive).
    datum : float
        Plane contact: the distance ``R`` [m] of the displacement datum.
    tol : float
        Newton stops when the gap residual is below ``tol * scale`` and the load balance
        below ``tol``.

    Returns
    -------
    list of BodySolution
        One per load; one whose Newton iteration stalled or ran out of iterations carries
        ``converged = False`` and its residual (the last iterate).
    """
    loads = np.atleast_1d(np.asarray(load, float))
    m = loads.size
    h = np.broadcast_to(np.asarray(r_max, float), (m,)) / n
    scales = np.broadcast_to(np.asarray(scale, float), (m,)).copy()
    edges = np.arange(n + 1, dtype=float)[None, :] * h[:, None]
    r = edges[:, :-1] + 0.5 * h[:, None]
    cell = (
        cell_areas(symmetry, n, 1.0)[None, :]
        * (h * h if symmetry == "axisymmetric" else h)[:, None]
    )
    sys = _System(kernel(symmetry, n), h / E_star, np.asarray(profile(r), float), scales)
    if symmetry == "plane":
        sys.shift = -(4.0 / math.pi) * np.log(h / datum) * (h / E_star)
    sys.weights = cell / loads[:, None]
    sys.sep = sep
    s = np.log(np.maximum(guess(r), 1e-300))
    s_max = np.log(loads / cell.min(axis=1))[:, None]  # the whole load on the smallest cell
    s = np.minimum(s, s_max)
    p = np.exp(s)
    delta = np.sum((sys.hr + sys.Kp(p, slice(None)) - sep(s)[0]) * sys.weights * p, axis=1)
    with np.errstate(over="ignore", invalid="ignore"):  # a rejected trial step may overflow
        s, delta, g, dd, iters, converged = _newton(sys, s, delta, tol, max_iter, s_max)
    p = np.exp(s)
    stiffness = loads / dd  # dL/d delta: d delta per relative load dL/L, at the last iterate
    residual = np.max(np.abs(g[:, :n]), axis=1)
    return [
        BodySolution(
            r[k],
            edges[k],
            cell[k],
            p[k],
            float(delta[k]),
            float(stiffness[k]),
            float(residual[k]),
            int(iters[k]),
            bool(converged[k]),
        )  # fmt: skip
        for k in range(m)
    ]


class _System:
    """The discretised equations of a batch of bodies (rows ``k`` of every array)."""

    def __init__(self, K0: FloatArray, c: FloatArray, hr: FloatArray, scale: FloatArray) -> None:
        self.K0, self.c, self.hr, self.scale = K0, c, hr, scale
        self.shift: FloatArray | None = None  # plane: the datum's constant, per body [m/Pa]
        self.weights = np.empty(0)
        self.sep: Separation | None = None

    def Kp(self, p: FloatArray, k: Any) -> FloatArray:
        """Displacements [m] of pressures ``p`` of bodies ``k``."""
        out = (p @ self.K0.T) * self.c[k][:, None]
        if self.shift is not None:
            out = out + self.shift[k][:, None] * p.sum(axis=1)[:, None]
        return out

    def resid(self, s: FloatArray, delta: FloatArray, k: Any) -> tuple[FloatArray, FloatArray]:
        """Scaled gap residuals and the load balance ``(len(k), n + 1)``, and ``du/ds``."""
        assert self.sep is not None
        p = np.exp(s)
        u, du = self.sep(s)
        g = (u - self.Kp(p, k) + delta[:, None] - self.hr[k]) / self.scale[k][:, None]
        return np.concatenate([g, np.sum(self.weights[k] * p, axis=1)[:, None] - 1.0], 1), du

    def jacobian(self, s: FloatArray, du: FloatArray, k: Any) -> FloatArray:
        """``d(resid)/d(s, delta)``, ``(len(k), n + 1, n + 1)`` (built in place: one pass over
        the ``n x n`` block)."""
        m, n = s.shape
        p = np.exp(s)
        inv = 1.0 / self.scale[k]
        J = np.empty((m, n + 1, n + 1))
        block = J[:, :n, :n]
        np.multiply(self.K0[None, :, :], (-(self.c[k] * inv)[:, None] * p)[:, None, :], out=block)
        if self.shift is not None:
            block -= (self.shift[k] * inv)[:, None, None] * p[:, None, :]
        J[:, np.arange(n), np.arange(n)] += du * inv[:, None]
        J[:, :n, n] = inv[:, None]
        J[:, n, :n] = self.weights[k] * p
        J[:, n, n] = 0.0
        return J


#: Newton iterations without a decrease of a body's ``|g|^2`` after which it stops (stalled).
STALL = 3


def _newton(
    sys: _System, s: FloatArray, delta: FloatArray, tol: float, max_iter: int, s_max: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, NDArray[np.int64], NDArray[np.bool_]]:
    """Newton's method on ``(ln p, delta)`` of every body, with a backtracking line search on
    ``|g|^2`` per body; converged bodies drop out of the batch, and so do bodies whose
    ``|g|^2`` has not decreased in :data:`STALL` iterations (the Newton direction no longer
    descends: the line search takes vanishing steps) or after ``max_iter`` iterations, with
    ``converged`` False.

    Each step's factorisation also gives the approach per relative load (the load balance
    perturbed by 1, the gaps held): ``d delta / (dL/L)`` at the last step's start (its relative
    change to the converged point is of the order of that step), returned in place of ``du/ds``
    (the stiffness without another solve).
    """
    m, n = s.shape
    everyone = np.arange(m)
    g, du = sys.resid(s, delta, everyone)
    iters = np.zeros(m, dtype=np.int64)
    dd = np.full(m, np.nan)
    converged = np.zeros(m, dtype=bool)
    best = np.sum(g * g, axis=1)
    flat = np.zeros(m, dtype=np.int64)  # iterations since the merit last fell
    active = everyone  # one step at least: its factorisation gives the stiffness
    for it in range(1, max_iter + 1):
        rhs = np.zeros((active.size, n + 1, 2))
        rhs[:, :, 0], rhs[:, n, 1] = -g[active], 1.0
        sol = np.linalg.solve(sys.jacobian(s[active], du[active], active), rhs)
        dd[active] = sol[:, n, 1]
        _line_search(sys, (s, delta, g, du), active, sol[..., 0], s_max)
        iters[active] = it
        done = _done(g[active], tol)
        converged[active[done]] = True
        merit = np.sum(g[active] ** 2, axis=1)
        fell = merit < best[active]
        best[active] = np.minimum(merit, best[active])
        flat[active] = np.where(fell, 0, flat[active] + 1)
        active = active[~done & (flat[active] < STALL)]
        if active.size == 0:
            break
    return s, delta, g, dd, iters, converged


def _line_search(
    sys: _System, state: tuple[FloatArray, ...], active: NDArray[np.int64], step: FloatArray,
    s_max: FloatArray,
) -> None:  # fmt: skip
    """Backtrack the Newton ``step`` of bodies ``active`` on ``|g|^2``; ``state = (s, delta,
    g, du)`` updated in place."""
    s, delta, g, du = state
    n = s.shape[1]
    merit = np.sum(g[active] ** 2, axis=1)
    lam = np.ones(active.size)
    todo = np.arange(active.size)  # positions in active still searching
    while todo.size:
        k = active[todo]
        s_new = np.minimum(s[k] + lam[todo, None] * step[todo, :n], s_max[k])
        d_new = delta[k] + lam[todo] * step[todo, n]
        g_new, du_new = sys.resid(s_new, d_new, k)
        trial = np.sum(g_new**2, axis=1)
        ok = (np.isfinite(trial) & (trial <= (1 - 1e-4 * lam[todo]) * merit[todo])) | (
            lam[todo] < 1e-6
        )
        kk = k[ok]
        s[kk], delta[kk], g[kk], du[kk] = s_new[ok], d_new[ok], g_new[ok], du_new[ok]
        lam[todo[~ok]] *= 0.5
        todo = todo[~ok]


def _done(g: FloatArray, tol: float) -> NDArray[np.bool_]:
    """Bodies whose gap residual and load balance are below ``tol``."""
    return (np.max(np.abs(g[:, :-1]), axis=1) < tol) & (np.abs(g[:, -1]) < tol)
