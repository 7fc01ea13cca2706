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

import numpy as np
from numpy.typing import NDArray

from ..cache import memoize

__all__ = [
    "BodySolution",
    "Separation",
    "force_radius",
    "hertz_cylinder",
    "hertz_sphere",
    "kernel",
    "solve_body",
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

    def __call__(self, s: FloatArray) -> tuple[FloatArray, FloatArray]:
        """``(u, du/ds)`` at ``s = ln p``."""
        x = self._x  # type: ignore[attr-defined]
        i = np.clip(np.searchsorted(x, s) - 1, 0, x.size - 2)
        h = x[i + 1] - x[i]
        t = np.clip((s - x[i]) / h, 0.0, 1.0)
        y0, y1, m0, m1 = self.u[i], self.u[i + 1], self.dudlnp[i] * h, self.dudlnp[i + 1] * h
        t2, t3 = t * t, t * t * t
        u = (2 * t3 - 3 * t2 + 1) * y0 + (t3 - 2 * t2 + t) * m0 + (-2 * t3 + 3 * t2) * y1
        u = u + (t3 - t2) * m1
        du = ((6 * t2 - 6 * t) * (y0 - y1) + (3 * t2 - 4 * t + 1) * m0 + (3 * t2 - 2 * t) * m1) / h
        lo, hi = s < x[0], s > x[-1]
        u = np.where(lo, self.u[0] + self.dudlnp[0] * (s - x[0]), u)
        du = np.where(lo, self.dudlnp[0], du)
        u = np.where(hi, self.u[-1] + self.dudlnp[-1] * (s - x[-1]), u)
        du = np.where(hi, self.dudlnp[-1], du)
        return u, du

    def area_fraction(self, p: FloatArray) -> FloatArray:
        """``A/A0`` [1] at nominal pressures ``p`` [Pa] (0 where ``p = 0``)."""
        x = self._x  # type: ignore[attr-defined]
        p = np.asarray(p, float)
        with np.errstate(divide="ignore"):
            s = np.log(p)
        inner = np.exp(self._ln_area(np.clip(s, x[0], x[-1])))  # type: ignore[attr-defined]
        below = self.area[0] * p / self.p[0]
        return np.minimum(np.where(s < x[0], below, inner), 1.0)


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
    """

    r: FloatArray
    edges: FloatArray
    cell: FloatArray
    p: FloatArray
    delta: float
    stiffness: float
    residual: float
    iterations: int


def force_radius(sol: BodySolution, fraction: float, symmetry: str) -> float:
    """Radius [m] inside which ``fraction`` of the load acts (linear in the cell's area)."""
    cum = np.concatenate([[0.0], np.cumsum(sol.p * sol.cell)])
    target = fraction * cum[-1]
    k = int(np.clip(np.searchsorted(cum, target) - 1, 0, sol.p.size - 1))
    t = (target - cum[k]) / max(cum[k + 1] - cum[k], 1e-300)
    e0, e1 = sol.edges[k], sol.edges[k + 1]
    if symmetry == "axisymmetric":
        return float(math.sqrt(e0 * e0 + t * (e1 * e1 - e0 * e0)))
    return float(e0 + t * (e1 - e0))


def solve_body(
    symmetry: str,
    profile: Callable[[FloatArray], FloatArray],
    load: float,
    E_star: float,
    sep: Separation,
    r_max: float,
    n: int,
    *,
    scale: float,
    guess: Callable[[FloatArray], FloatArray],
    datum: float = 1.0,
    tol: float = 1e-10,
    max_iter: int = 200,
) -> BodySolution:
    """Solve the gap equation and the load balance on ``n`` cells of ``[0, r_max]``.

    Parameters
    ----------
    symmetry : {"axisymmetric", "plane"}
    profile : callable
        ``h(r)`` [m].
    load : float
        Force [N] (axisymmetric) or force per length [N/m] (plane).
    E_star : float
        Contact modulus [Pa].
    sep : Separation
        The interface ``u(p)``.
    r_max : float
        Outer radius of the grid [m].
    n : int
        Cells.
    scale : float
        Length [m] the gap residual is measured in (the smooth approach).
    guess : callable
        Starting pressure [Pa] at radii [m] (positive).
    datum : float
        Plane contact: the distance ``R`` [m] of the displacement datum.
    tol : float
        Newton stops when the gap residual is below ``tol * scale`` and the load balance
        below ``tol``.

    Raises
    ------
    ArithmeticError
        No convergence within ``max_iter`` iterations.
    """
    h = r_max / n
    edges = np.arange(n + 1, dtype=float) * h
    r = edges[:-1] + 0.5 * h
    cell = cell_areas(symmetry, n, h)
    K = kernel(symmetry, n) * (h / E_star)
    if symmetry == "plane":
        K = K - (4.0 / math.pi) * math.log(h / datum) * (h / E_star)
    hr = np.asarray(profile(r), float)
    s = np.log(np.maximum(guess(r), 1e-300))
    delta = float(np.dot(hr + K @ np.exp(s) - sep(s)[0], cell * np.exp(s)) / load)
    weights = cell / load

    def resid(s: FloatArray, delta: float) -> tuple[FloatArray, FloatArray]:
        p = np.exp(s)
        u, du = sep(s)
        g = (u - K @ p + delta - hr) / scale
        return np.append(g, np.dot(weights, p) - 1.0), du

    s_max = math.log(load / float(cell.min()))  # the whole load on the smallest cell
    with np.errstate(over="ignore", invalid="ignore"):  # a rejected trial step may overflow
        s, delta, g, du, iterations = _newton(
            resid, K, weights, np.minimum(s, s_max), delta, scale, tol, max_iter, s_max
        )
    p = np.exp(s)
    Js = -K * p[None, :]
    Js[np.arange(n), np.arange(n)] += du
    dsdd = np.linalg.solve(Js, -np.ones(n))
    stiffness = float(np.dot(cell * p, dsdd))
    residual = float(np.max(np.abs(g[:n])))
    return BodySolution(r, edges, cell, p, delta, stiffness, residual, iterations)


def _newton(
    resid: Callable[[FloatArray, float], tuple[FloatArray, FloatArray]],
    K: FloatArray,
    weights: FloatArray,
    s: FloatArray,
    delta: float,
    scale: float,
    tol: float,
    max_iter: int,
    s_max: float,
) -> tuple[FloatArray, float, FloatArray, FloatArray, int]:
    """Newton's method on ``(ln p, delta)`` with a backtracking line search on ``|g|^2``."""
    n = s.size
    diag = np.arange(n)
    g, du = resid(s, delta)
    for it in range(1, max_iter + 1):
        p = np.exp(s)
        J = np.empty((n + 1, n + 1))
        J[:n, :n] = -K * p[None, :]
        J[diag, diag] += du
        J[:n, :n] /= scale
        J[:n, n] = 1.0 / scale
        J[n, :n] = weights * p
        J[n, n] = 0.0
        step = np.linalg.solve(J, -g)
        merit, lam = float(np.dot(g, g)), 1.0
        while True:
            s_new = np.minimum(s + lam * step[:n], s_max)
            g_new, du_new = resid(s_new, delta + lam * step[n])
            trial = float(np.dot(g_new, g_new))
            if (math.isfinite(trial) and trial <= (1 - 1e-4 * lam) * merit) or lam < 1e-6:
                break
            lam *= 0.5
        s, delta, g, du = s_new, delta + lam * step[n], g_new, du_new
        if np.max(np.abs(g[:n])) < tol and abs(g[n]) < tol:
            return s, delta, g, du, it
    raise ArithmeticError(
        f"the nominal pressure did not converge in {max_iter} Newton iterations "
        f"(gap residual {np.max(np.abs(g[:n])):.3g} of the approach scale)"
    )
