"""xpersson-transport: electrical and thermal contact conductance from the solved contact.

First-party analyses for :mod:`xpersson` (entry-point group ``xpersson.analyses``):
``electrical_contact`` and ``thermal_contact``. They turn the incremental contact stiffness and
the gap distribution that ``xpersson-interface`` computes into conductances by Barber's
stiffness-conductance analogy, Holm's spot picture beside it, gas conduction with the
temperature-jump length, far-field radiation and a film in series (:mod:`._physics`).
"""

from ._physics import (
    SIGMA_SB,
    closest_to_one,
    electrical_factor,
    film_conductance,
    gas_gap_conductance,
    holm_stiffness,
    in_series,
    jump_length,
    radiation_conductance,
    series_conductivity,
    thermal_factor,
)

__version__ = "0.1.0"

__all__ = [
    "SIGMA_SB",
    "closest_to_one",
    "electrical_factor",
    "film_conductance",
    "gas_gap_conductance",
    "holm_stiffness",
    "in_series",
    "jump_length",
    "radiation_conductance",
    "series_conductivity",
    "thermal_factor",
]
