"""xpersson-adhesion: adhesive boundaries for xpersson (Persson contact theory).

Registered through the entry-point group ``xpersson.boundaries``:

* ``jkr`` -> :class:`JKRBoundary`: absorbing detachment wall at ``p = -sigma_a(zeta)``
  (Persson 2002), ``sigma_a = [c_a gamma_eff E* q]^(1/2)`` or a user table;
* ``dmt`` -> :class:`DMTBoundary`: repulsive contact plus an attractive traction-gap law
  integrated over the gap distribution of the solved contact.
* ``adhesive`` -> :class:`AdhesiveBoundary`: the same mean field on a tabulated ``p_att(p_rep)``
  (fast), with pull-off, stickiness and a per-load regime; verified against a BEM referee.

Physics helpers (pure numpy, SI units) are re-exported: :func:`true_area_ratio`,
:func:`gamma_effective`, :func:`detachment_stress`, :func:`tabor_parameter`, :func:`stickiness`.
"""

from ._detachment import detachment_stress, gamma_effective, true_area_ratio
from ._dmt_reference import solve_dmt
from ._tabor import AdhesionLimitWarning, tabor_parameter
from ._traction import LAWS, traction
from .adhesive import AdhesiveBoundary
from .dmt import DMTAccuracyWarning, DMTBoundary, DMTState
from .jkr import JKRBoundary, stickiness

__version__ = "0.1.0"

__all__ = [
    "AdhesionLimitWarning",
    "AdhesiveBoundary",
    "DMTAccuracyWarning",
    "DMTBoundary",
    "DMTState",
    "JKRBoundary",
    "LAWS",
    "detachment_stress",
    "gamma_effective",
    "solve_dmt",
    "stickiness",
    "tabor_parameter",
    "traction",
    "true_area_ratio",
    "__version__",
]
