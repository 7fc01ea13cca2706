"""Checks of the ``viscoelastic`` coefficient's outputs (split from :mod:`.coefficient`)."""

from __future__ import annotations

from typing import Any

import numpy as np

from xpersson.plugins import VarSpec

__all__ = ["check_outputs"]


def check_outputs(
    values: dict[str, tuple[tuple[str, ...], Any]], specs: dict[str, VarSpec], who: str
) -> dict[str, tuple[tuple[str, ...], Any]]:
    """Check dims, finiteness and the declared valid range before values enter a Dataset."""
    for name, (dims, data) in values.items():
        spec = specs[name]
        arr = np.asarray(data, dtype=float)
        if tuple(dims) != spec.dims or arr.ndim != len(dims):
            raise RuntimeError(f"{who}: {name!r} has dims {dims}, declared {spec.dims}")
        if not np.all(np.isfinite(arr)):
            raise RuntimeError(f"{who}: {name!r} has non-finite values")
        lo, hi = spec.valid_min, spec.valid_max
        if (lo is not None and np.any(arr < lo)) or (hi is not None and np.any(arr > hi)):
            raise RuntimeError(
                f"{who}: {name!r} outside its declared range [{lo}, {hi}] "
                f"(min {arr.min():g}, max {arr.max():g})"
            )
    return values
