"""The nominal pressure on a finite body (sphere, cylinder): ``p(r)`` per force, with the Hertz
contact radius of the smooth body marked (:mod:`xpersson.pipeline.body` computes it)."""

from __future__ import annotations

from typing import Any

import numpy as np
import xarray as xr

from ._figure import new_axes
from ._units import human, text

__all__ = ["body"]


def body(ds: xr.Dataset, ax: Any = None, max_curves: int = 12) -> Any:
    """Nominal pressure ``nominal_pressure(force, r)`` against ``r``, one curve per force
    (evenly picked when there are more than ``max_curves``); the smooth body's Hertz radius of
    each drawn force as a dotted line of the same colour.

    Parameters
    ----------
    ds : xarray.Dataset
        A solved finite-body Dataset (``[geometry]`` sphere or cylinder).
    ax : matplotlib.axes.Axes, optional
        Where to draw (a new figure when not given).
    max_curves : int
        Most forces drawn.
    """
    if "nominal_pressure" not in ds:
        raise ValueError(
            "kind 'body' needs a finite-body archive (a scene with [geometry] sphere or "
            "cylinder and load.force); this one has no nominal_pressure"
        )
    p = ds["nominal_pressure"].transpose("force", "r")
    r = np.asarray(ds["r"].values, float)
    forces = np.asarray(ds["force"].values, float)
    pick = np.unique(np.linspace(0, forces.size - 1, min(max_curves, forces.size)).round())
    pf, pu = human("Pa", p.values)
    rf, ru = human("m", r)
    ax = new_axes(ax)
    for k, i in enumerate(pick.astype(int)):
        color = f"C{k % 10}"
        ax.plot(r / rf, p.values[i] / pf, color=color, label=text(forces[i], "N"))
        if "hertz_radius" in ds:
            ax.axvline(float(ds["hertz_radius"].values[i]) / rf, color=color, ls=":", lw=0.8)
    ax.set_xlabel(f"radial distance r ({ru})")
    ax.set_ylabel(f"nominal pressure ({pu})")
    drawn = f" ({pick.size} of {forces.size} drawn)" if pick.size < forces.size else ""
    ax.legend(title=f"force{drawn}; dotted: Hertz radius", fontsize="small")
    ax.set_title("nominal pressure on the body", fontsize="medium")
    return ax
