"""The model-error band of an output (``X_exact_low``/``X_exact_high``, where the validation
campaign verified it): a shaded band versus load, or a bar at the largest magnification."""

from __future__ import annotations

from typing import Any

import numpy as np
import xarray as xr

__all__ = ["band"]


def band(ax: Any, ds: xr.Dataset, name: str, x: str = "p0", scale: float = 1.0) -> None:
    """Shade where exact contact's ``name`` lies (verified loads only; nothing without one).

    ``x``: ``"p0"`` (a band over the loads, divided by ``scale`` on the axis) or ``"zeta"``
    (a bar at ``zeta_max`` per load).
    """
    low, high = ds.get(name + "_exact_low"), ds.get(name + "_exact_high")
    status = ds.get(name + "_model_error_status")
    if low is None or high is None or status is None or low.ndim > 1:
        return  # a sweep's bands are not drawn (one curve per point)
    ok = np.asarray(status.values, bool).ravel()
    lo, hi = np.ravel(low.values), np.ravel(high.values)
    if not ok.any():
        return
    if x == "zeta":
        z = np.full(ok.sum(), float(ds["zeta"].values[-1]))
        mid = 0.5 * (lo[ok] + hi[ok])
        err = 0.5 * (hi[ok] - lo[ok])
        ax.errorbar(z, mid, yerr=err, fmt="none", color="0.5", capsize=3, label="exact (band)")
        return
    p = np.ravel(ds[x].values) / scale
    ax.fill_between(
        p,
        np.where(ok, lo, np.nan),
        np.where(ok, hi, np.nan),
        color="0.8",
        alpha=0.6,
        lw=0,
        zorder=0,
        label="exact contact (model-error band)",
    )
