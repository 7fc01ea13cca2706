"""xpersson-example: a worked third-party plugin distribution for xpersson.

The package imports nothing at import time; xpersson finds the plugin through the entry point
``xpersson.boundaries: offset_wall`` declared in ``pyproject.toml`` and imports
:mod:`xpersson_example.offset_wall` only when a scene selects it.
"""

__version__ = "0.1.0"
