"""xpersson-viscoelastic: viscoelastic coefficient and rubber friction for xpersson.

Registered through entry points (the core never imports this package by name):

* ``xpersson.coefficients``: ``viscoelastic`` -> :class:`ViscoelasticCoefficient`;
* ``xpersson.analyses``: ``friction`` -> :class:`Friction`.

The modulus models, shift laws, table readers and the vectorised kernels
(:mod:`xpersson_viscoelastic.kernel`) are public for studies outside a scene.
"""

from ._modulus import MasterCurve, ModulusModel, Prony, sls, synthetic_tread, u_of_b, u_over_b
from ._shift import GAS_CONSTANT, WLF, WLF_UNIVERSAL, Arrhenius, NoShift, TabulatedShift
from ._tables import TableError, load_master_curve, load_prony, load_shift_table
from .coefficient import ViscoelasticCoefficient
from .friction import Friction
from .kernel import friction_curve

__version__ = "0.1.0"

__all__ = [
    "GAS_CONSTANT",
    "WLF_UNIVERSAL",
    "Arrhenius",
    "Friction",
    "MasterCurve",
    "ModulusModel",
    "NoShift",
    "Prony",
    "TableError",
    "TabulatedShift",
    "ViscoelasticCoefficient",
    "WLF",
    "friction_curve",
    "load_master_curve",
    "load_prony",
    "load_shift_table",
    "sls",
    "synthetic_tread",
    "u_of_b",
    "u_over_b",
    "__version__",
]
