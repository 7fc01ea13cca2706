"""The model-error band of an output (``X_exact_low``/``X_exact_high``, where the validation
campaign verified it): a shaded band versus load, or a bar at the largest magnification."""

from __future__ import annotations

from typing import Any

import numpy as np
import xarray as xr

__all__ = ["band"]


def band(ax: Any, ds: xr.Dataset, name: str, x: str = "p0", scale: float = 1.0) -> None:
    """Shade where exact contact's ``name`` lies: solid grey where the campaign verified the
    band (status 1), hatched where it is extrapolated in decades of roughness (status 2);
    nothing where it is not verified.

    ``x``: ``"p0"`` (a band over the loads, divided by ``scale`` on the axis) or ``"zeta"``
    (a bar at ``zeta_max`` per load).
    """
    low, high = ds.get(name + "_exact_low"), ds.get(name + "_exact_high")
    status = ds.get(name + "_model_error_status")
    if low is None or high is None or status is None or low.ndim > 1:
        return  # a sweep's bands are not drawn (one curve per point)
    flag = np.asarray(status.values).ravel()
    lo, hi = np.ravel(low.values), np.ravel(high.values)
    for value, style in ((1, _VERIFIED), (2, _EXTRAPOLATED)):
        ok = flag == value
        if ok.any():
            _draw(ax, ds, x, scale, ok, lo, hi, style)


_VERIFIED = {"label": "exact contact (model-error band)", "color": "0.8", "hatch": None}
_EXTRAPOLATED = {"label": "exact contact (band extrapolated)", "color": "0.6", "hatch": "///"}


def _draw(
    ax: Any,
    ds: xr.Dataset,
    x: str,
    scale: float,
    ok: np.ndarray,
    lo: np.ndarray,
    hi: np.ndarray,
    style: dict[str, Any],
) -> None:
    if x == "zeta":
        z = np.full(ok.sum(), float(ds["zeta"].values[-1]))
        mid = 0.5 * (lo[ok] + hi[ok])
        err = 0.5 * (hi[ok] - lo[ok])
        ax.errorbar(
            z, mid, yerr=err, fmt="none", color=style["color"], capsize=3,
            label=style["label"],
        )  # fmt: skip
        return
    p = np.ravel(ds[x].values) / scale
    ax.fill_between(
        p,
        np.where(ok, lo, np.nan),
        np.where(ok, hi, np.nan),
        facecolor=style["color"] if style["hatch"] is None else "none",
        edgecolor=style["color"],
        hatch=style["hatch"],
        alpha=0.6,
        lw=0,
        zorder=0,
        label=style["label"],
    )
