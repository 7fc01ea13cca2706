"""xpersson-interface: interfacial separation, elastic energy, gap distribution and leakage.

First-party analyses for :mod:`xpersson` (entry-point group ``xpersson.analyses``):
``elastic_energy``, ``mean_gap``, ``contact_stiffness``, ``gap_pdf``, ``leakage``. They compute
from the solved contact through the public core physics :mod:`xpersson.physics.interface`
(energy, mean gap, stiffness, gap distribution) on the solved curve that
:mod:`xpersson.plugins.solved` reads; this package adds the seal-leakage models, the
gap-distribution diffusion adapter and the plugin classes.
"""

# The solved curve lives in the core (xpersson-transport reads it too); re-exported here so
# that ``from xpersson_interface import solved_curve`` keeps working.
from xpersson.plugins.solved import FORMS, Solved, dense_zeta, solved_curve

from ._gap_diffusion import DiffusionResult, diffuse_with_injection
from ._leakage import bruggeman, bruggeman_gap, effective_pressure_drop, leak_rate

__version__ = "0.2.0"

__all__ = [
    "FORMS",
    "DiffusionResult",
    "Solved",
    "bruggeman",
    "bruggeman_gap",
    "dense_zeta",
    "diffuse_with_injection",
    "effective_pressure_drop",
    "leak_rate",
    "solved_curve",
]
