"""xpersson-interface: interfacial separation, elastic energy, gap distribution and leakage.

First-party analyses for :mod:`xpersson` (entry-point group ``xpersson.analyses``):
``elastic_energy``, ``mean_gap``, ``contact_stiffness``, ``gap_pdf``, ``leakage``. The numerical
functions live in small private modules (pure numpy/scipy, SI floats) and are re-exported here.
"""

from ._closures import CLOSURES, AreaLaw, area_law
from ._energy import elastic_energy, full_contact_energy
from ._gap import C3, contact_stiffness, dmean_gap_dp, gap_asymptote, mean_gap
from ._gap_diffusion import diffuse_with_injection
from ._gap_pdf import Detachment, detachment, gap_cdf, gap_mean, gap_pdf
from ._leakage import (
    bruggeman,
    bruggeman_gap,
    critical_junction,
    effective_pressure_drop,
    leak_rate,
)
from ._quad import QRule, q_rule

__version__ = "0.1.0"

__all__ = [
    "C3",
    "CLOSURES",
    "AreaLaw",
    "Detachment",
    "QRule",
    "area_law",
    "bruggeman",
    "bruggeman_gap",
    "contact_stiffness",
    "critical_junction",
    "detachment",
    "diffuse_with_injection",
    "dmean_gap_dp",
    "effective_pressure_drop",
    "elastic_energy",
    "full_contact_energy",
    "gap_asymptote",
    "gap_cdf",
    "gap_mean",
    "gap_pdf",
    "leak_rate",
    "mean_gap",
    "q_rule",
]
