"""The statistics of BEM values across realisations (one helper for every cross-check)."""

from __future__ import annotations

import numpy as np

__all__ = ["mean_se"]


def mean_se(values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Mean and standard error of the mean over the first axis (realisations), NaN values
    (solves that did not converge) left out; the standard error needs two values, else NaN."""
    ok = np.isfinite(values)
    n = ok.sum(axis=0)
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = np.where(n > 0, np.nansum(values, axis=0) / np.maximum(n, 1), np.nan)
        var = np.nansum((values - mean) ** 2, axis=0) / np.maximum(n - 1, 1)
        se = np.where(n >= 2, np.sqrt(var / np.maximum(n, 1)), np.nan)
    return mean, se
