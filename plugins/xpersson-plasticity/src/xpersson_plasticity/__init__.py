"""xpersson-plasticity: elastoplastic boundaries for xpersson (Persson contact theory).

Registered through the entry-point group ``xpersson.boundaries``:

* ``plastic`` -> :class:`PlasticBoundary` (constant penetration hardness sigma_Y);
* ``plastic_scale_dependent`` -> :class:`ScaleDependentPlasticBoundary` (Y(zeta), Lambert 2025).

The exact two-wall series (:func:`two_wall_areas`, :func:`two_wall_pdf`) are re-exported here.
"""

from ._series import three_gaussian_areas, two_wall_areas, two_wall_pdf
from .plastic import ApproximationValidityWarning, PlasticBoundary
from .scale_dependent import ScaleDependentPlasticBoundary

__version__ = "0.1.0"

__all__ = [
    "ApproximationValidityWarning",
    "PlasticBoundary",
    "ScaleDependentPlasticBoundary",
    "three_gaussian_areas",
    "two_wall_areas",
    "two_wall_pdf",
    "__version__",
]
