"""Boundary-element reference solutions (tamaas) for the theory's outputs.

Low level (stable API, SI floats and numpy arrays):

* :func:`synthesise` -- periodic Gaussian height maps with Persson's spectrum ``C(q)``
  (seeded, ``N`` realisations, ``n x n`` grid); :func:`map_moments`,
  :func:`discrete_moments`, :func:`spectrum_moments` check them.
* :func:`solve` -- frictionless elastic (or constant-hardness plastic) contact of a height map
  at mean pressures; :func:`solve_gaps` -- at mean gaps, optionally adhesive. Both return
  :class:`BemState` objects with the solver's convergence; a non-converged solve raises
  :class:`BemConvergenceError` (or is flagged, its values NaN).

A sphere or any macroscopic shape: add it to the height map before :func:`solve`.

tamaas is an optional dependency (``pip install "xpersson[bem]"``); importing this package
does not import it.
"""

from __future__ import annotations

from ._plan import CrosscheckError
from .crosscheck import crosscheck, estimate_line
from .derived import (
    adhesive_path,
    conductance_direct,
    electrical_factor,
    gap_pdf,
    retraction_branch,
    stiffness,
    thermal_factor,
)
from .solve import (
    BemConvergenceError,
    BemState,
    GapSolver,
    MissingTamaasError,
    require_tamaas,
    solve,
    solve_gaps,
    tamaas_version,
)
from .synthesis import (
    discrete_moments,
    map_moments,
    spectrum_moments,
    synthesise,
    wavenumbers,
)

__all__ = [
    "CrosscheckError",
    "crosscheck",
    "estimate_line",
    "BemConvergenceError",
    "BemState",
    "GapSolver",
    "MissingTamaasError",
    "adhesive_path",
    "conductance_direct",
    "discrete_moments",
    "electrical_factor",
    "gap_pdf",
    "retraction_branch",
    "stiffness",
    "thermal_factor",
    "map_moments",
    "require_tamaas",
    "solve",
    "solve_gaps",
    "spectrum_moments",
    "synthesise",
    "tamaas_version",
    "wavenumbers",
]
