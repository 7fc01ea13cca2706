"""xpersson-viscoelastic: viscoelastic coefficient and rubber friction for xpersson.

Registered through entry points (the core never imports this package by name):

* ``xpersson.coefficients``: ``viscoelastic`` -> :class:`ViscoelasticCoefficient`;
* ``xpersson.analyses``: ``friction`` -> :class:`Friction`.

The modulus models, shift laws, table readers and the vectorised kernels
(:mod:`xpersson_viscoelastic.kernel`) are public for studies outside a scene.
"""

from __future__ import annotations

import importlib
from typing import Any

_WHERE = {
    "MasterCurve": "._modulus",
    "ModulusModel": "._modulus",
    "Prony": "._modulus",
    "sls": "._modulus",
    "synthetic_tread": "._modulus",
    "u_of_b": "._modulus",
    "u_over_b": "._modulus",
    "GAS_CONSTANT": "._shift",
    "WLF": "._shift",
    "WLF_UNIVERSAL": "._shift",
    "Arrhenius": "._shift",
    "NoShift": "._shift",
    "TabulatedShift": "._shift",
    "TableError": "._tables",
    "load_master_curve": "._tables",
    "load_prony": "._tables",
    "load_shift_table": "._tables",
    "ViscoelasticCoefficient": ".coefficient",
    "Friction": ".friction",
    "friction_curve": "._curve",
}


def __getattr__(name: str) -> Any:
    """Import the public names lazily (listing plugins and importing one stay cheap)."""
    if name in _WHERE:
        return getattr(importlib.import_module(_WHERE[name], __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


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
