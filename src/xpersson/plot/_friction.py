"""The ``friction`` kind: mu(v) at each temperature, re-solving a one-speed Dataset's stored scene
over sliding speeds and temperatures when asked (the one kind that may solve)."""

from __future__ import annotations

import json
import warnings
from typing import Any

import numpy as np
import xarray as xr

from ._kinds import need
from ._lines import lines
from ._units import human, text

__all__ = ["friction"]

_NO_RESOLVE = "pass resolve=False to draw mu at the Dataset's one sliding speed"


def _friction_sweep(ds: xr.Dataset, speeds: np.ndarray, temps: list[float]) -> xr.Dataset:
    """Re-solve the archive's scene over sliding speeds [m/s] and temperatures [K].

    Raises
    ------
    ValueError
        When ``ds`` stores no scene, or its scene cannot be solved here (e.g. the archive's
        coefficient plugin is not installed); the message names ``resolve=False``.
    """
    if "xpersson_scene" not in ds.attrs:
        raise ValueError(f"friction: this Dataset stores no scene to re-solve; {_NO_RESOLVE}")
    from ..api import solve  # deferred: plotting an archive needs no solver otherwise
    from ..scene import Scene, SceneError

    data = json.loads(ds.attrs["xpersson_scene"])
    data["coefficient"]["velocity"] = [f"{float(v)!r} m/s" for v in speeds]
    data["coefficient"]["temperature"] = [f"{float(t)!r} K" for t in temps]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            return solve(Scene(data, source=None))
        except SceneError as exc:
            raise ValueError(
                f"friction: the stored scene cannot be re-solved here ({exc}); {_NO_RESOLVE}"
            ) from exc


def _star(speed: float, temperature: float) -> Any:
    """The legend entry of the archive's own point: a star at its speed [m/s] and temperature
    [K]."""
    from matplotlib.lines import Line2D

    where = f"{text(speed, 'm s-1')}, {text(temperature, 'K')}"
    return Line2D(
        [], [], color="k", ls="none", marker="*", ms=9, label=f"the archive's point ({where})"
    )


def friction(
    ds: xr.Dataset,
    ax: Any = None,
    max_curves: int = 12,
    resolve: bool = True,
    speeds: Any = None,
) -> Any:
    """Friction coefficient mu(v) at each temperature (log v), total (solid) and viscoelastic
    part (dashed), one colour per temperature, for the heaviest load.

    Parameters
    ----------
    ds : xarray.Dataset
        A Dataset with ``mu`` (friction analysis of the viscoelastic plugin).
    ax : matplotlib.axes.Axes, optional
        Where to draw (a new figure when not given).
    max_curves : int
        Most curves drawn per quantity.
    resolve : bool
        When ``ds`` holds one sliding speed, re-solve its stored scene over ``speeds`` at its
        temperature (``rubber_temperature`` [K]) and 20 K below and above (about 10 s); the
        stored point is marked by a star, explained in the legend. A Dataset that cannot be
        re-solved (no stored scene, no ``rubber_temperature``, a plugin missing here) is a
        ValueError; ``resolve=False`` draws mu versus p0 at the one speed instead.
    speeds : array_like, optional
        Sliding speeds [m/s] of the re-solve (default 17 values from 1e-8 to 1e2 m/s).
    """
    mu = need(ds, "mu", "request a friction analysis (e.g. [analyses.friction])")
    point = None
    if "v" not in mu.dims and resolve:
        speed = need(ds, "sliding_speed", _NO_RESOLVE)
        t0 = float(need(ds, "rubber_temperature", _NO_RESOLVE))
        v = np.geomspace(1e-8, 1e2, 17) if speeds is None else np.asarray(speeds, float)
        point = (float(speed), ds["mu"], t0)
        ds = _friction_sweep(ds, v, [t0 - 20.0, t0, t0 + 20.0])
        mu = ds["mu"]
    if "v" not in mu.dims:
        return lines(ax, [("mu", mu)], "p0", max_curves=max_curves)
    heavy = {"p0": -1} if "p0" in mu.dims else {}
    items = [("total", mu.isel(heavy))]
    if "mu_visc" in ds:
        items.append(("viscoelastic part", ds["mu_visc"].isel(heavy)))
    mu = items[0][1]
    extra = [] if point is None else [_star(point[0], point[2])]
    ax = lines(ax, items, "v", max_curves=max_curves, extra=extra)
    ax.set_xscale("log")
    ax.set_ylim(bottom=0)
    ax.set_ylabel(r"friction coefficient $\mu$")
    if point is not None:
        vf = human("m s-1", ds["v"].values)[0]
        ax.plot(point[0] / vf, float(np.ravel(point[1].values)[-1]), "k*", ms=11, label="_stored")
    if "p0" in mu.coords:
        ax.set_title(f"$p_0$ = {text(float(mu['p0']), 'Pa')}")
    return ax
