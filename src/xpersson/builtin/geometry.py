"""Built-in geometries: a sphere and a cylinder (line contact) pressed on the rough flat.

The body is smooth and the flat carries the roughness (the scene's spectrum); ``[material]``
gives the contact modulus of the pair (``E* = E/(1 - nu^2)`` of the scene is the combined
modulus ``1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2``). The profiles are the small-slope parabolas
of Hertz theory, so the nominal contact must stay well inside the body: its smooth (Hertz)
radius is at most :data:`SLOPE_LIMIT` times the body's radius (and, for a cylinder, a tenth
of its length, so that plane strain holds).
"""

from __future__ import annotations

import numpy as np

from ..physics.body import hertz_cylinder, hertz_sphere
from ..plugins import Geometry, ParamSpec

__all__ = ["Cylinder", "SLOPE_LIMIT", "Sphere"]

SLOPE_LIMIT = 0.2
"""Largest Hertz contact radius per body radius [1]: the parabolic, small-slope profile holds."""

_REFS = (
    "10.1115/1.3607616",  # Greenwood & Tripp 1967, the elastic contact of rough spheres
    "10.1103/PhysRevLett.99.125502",  # Persson 2007, interfacial separation and load
    "10.1017/CBO9781139171731",  # Johnson 1985, Contact Mechanics
)
_RADIUS = ParamSpec(
    "m",
    bounds=(0, None),
    inclusive=(False, True),
    example=0.005,
    description="radius of curvature of the body",
)


class Sphere(Geometry):
    """A smooth sphere of radius ``R`` on the rough flat under a total force [N].

    Profile ``h(r) = r^2/(2R)``; smooth reference: Hertz, ``a = (3 F R / (4 E*))^(1/3)``.
    Johnson's roughness parameter is ``alpha = sigma R / a^2`` with ``sigma`` the rms height of
    the spectrum and ``a`` the Hertz radius at the same force (Johnson 1985, §13.4).
    """

    summary = "smooth sphere (radius R) on the rough flat, Hertz profile r^2/(2R)"
    references = _REFS
    parameters = {"radius": _RADIUS}
    symmetry = "axisymmetric"

    def profile(self, r: np.ndarray) -> np.ndarray:
        """``h(r) = r^2 / (2 R)`` [m]."""
        return np.asarray(r, float) ** 2 / (2.0 * self.params["radius"])

    def extent(self) -> float:
        """:data:`SLOPE_LIMIT` times the radius [m]."""
        return SLOPE_LIMIT * float(self.params["radius"])

    def reference(self, load: float, E_star: float) -> tuple[float, float, float]:
        """Hertz: radius [m], approach [m], peak pressure [Pa]."""
        return hertz_sphere(load, float(self.params["radius"]), E_star)

    def roughness_parameter(self, h_rms: float, load: float, E_star: float) -> float:
        """``sigma R / a^2`` [1] with the Hertz radius ``a`` at ``load``."""
        a = self.reference(load, E_star)[0]
        return h_rms * float(self.params["radius"]) / (a * a)


class Cylinder(Geometry):
    """A smooth cylinder of radius ``R`` and length ``L`` on the rough flat (a line contact).

    The scene gives the total force [N]; plane strain carries the force per length ``F/L``.
    Profile ``h(x) = x^2/(2R)``; smooth reference: Hertz, ``b = (4 F R / (pi L E*))^(1/2)``.
    The approach of a line contact needs a datum: the displacement is referred to the distance
    ``R`` from the line (Hertz: ``delta = (F/(pi L E*)) (2 ln(2R/b) + 1)``). Johnson's parameter
    is ``sigma R / b^2``.
    """

    summary = "smooth cylinder (radius R, length L) on the rough flat: plane-strain line contact"
    references = _REFS
    parameters = {
        "radius": _RADIUS,
        "length": ParamSpec(
            "m",
            bounds=(0, None),
            inclusive=(False, True),
            example=0.01,
            description="length of the cylinder (the line load is force/length)",
        ),
    }
    symmetry = "plane"

    def profile(self, r: np.ndarray) -> np.ndarray:
        """``h(x) = x^2 / (2 R)`` [m]."""
        return np.asarray(r, float) ** 2 / (2.0 * self.params["radius"])

    def extent(self) -> float:
        """The smaller of :data:`SLOPE_LIMIT` times the radius and a tenth of the length [m]."""
        return min(SLOPE_LIMIT * float(self.params["radius"]), 0.1 * float(self.params["length"]))

    def solver_load(self, force: float) -> float:
        """Force per length [N/m]."""
        return float(force) / float(self.params["length"])

    def reference(self, load: float, E_star: float) -> tuple[float, float, float]:
        """Hertz line contact: half-width [m], approach [m], peak pressure [Pa]."""
        return hertz_cylinder(load, float(self.params["radius"]), E_star)

    def roughness_parameter(self, h_rms: float, load: float, E_star: float) -> float:
        """``sigma R / b^2`` [1] with the Hertz half-width ``b`` at ``load`` [N/m]."""
        b = self.reference(load, E_star)[0]
        return h_rms * float(self.params["radius"]) / (b * b)
