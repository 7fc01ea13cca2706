"""The nearest admissible probabilities of a method's outputs (clipped areas and absorbed
fractions) and how far each moved: the ``cn`` and ``sine`` methods report the distance in
their error estimates. No imports beyond numpy (the closed-form and series paths use it)."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["project"]

Array = NDArray[np.float64]


def project(
    area: Array, abs_l: Array, abs_u: Array
) -> tuple[tuple[Array, Array, Array], dict[str, Array]]:
    """Nearest admissible probabilities and the distance each moved.

    ``area`` is clipped to [0, 1]; the absorbed fractions to >= 0 and, where their sum (the
    non-contact fraction) exceeds 1, scaled down to sum to 1.
    """
    a = np.asarray(area).clip(0.0, 1.0)  # (the method: np.clip's dispatch costs ~2 us)
    lo = np.maximum(abs_l, 0.0)
    up = np.maximum(abs_u, 0.0)
    total = lo + up
    if not total.max() <= 1.0:  # (some sum over 1, or a NaN: else lo and up stay as they are)
        over = total > 1.0
        scale = np.where(over, 1.0 / np.where(over, total, 1.0), 1.0)
        lo = np.minimum(lo * scale, 1.0)
        up = np.where(over, np.minimum(up * scale, 1.0 - lo), up)
        up = np.where(lo + up > 1.0, np.nextafter(up, 0.0), up)  # the sum's round-off
        total = lo + up
    dist = {
        "area": np.abs(a - area),
        "absorbed_lower": np.abs(lo - abs_l),
        "absorbed_upper": np.abs(up - abs_u),
        "non_contact_fraction": np.abs(total - (abs_l + abs_u)),
    }
    return (a, lo, up), dist
