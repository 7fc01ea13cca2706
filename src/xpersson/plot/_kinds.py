"""The kinds drawn straight from the Dataset: ``area``, ``pressure_pdf``, ``gap_pdf``, ``leakage``
and ``energy`` (``friction``, which may re-solve the scene, is in ``_friction``)."""

from __future__ import annotations

from typing import Any

import numpy as np
import xarray as xr

from ._band import band
from ._figure import log_limits, logx
from ._lines import lines
from ._units import human, number

__all__ = ["area", "pressure_pdf", "gap_pdf", "leakage", "energy"]


def need(ds: xr.Dataset, name: str, hint: str) -> xr.DataArray:
    """``ds[name]``; a ValueError with ``hint`` (what provides it) when ``ds`` has no ``name``."""
    if name not in ds:
        raise ValueError(f"this Dataset has no {name!r}; {hint}")
    return ds[name]


def _sweep_dims(da: xr.DataArray) -> list[str]:
    return [d for d in da.dims if d not in ("p0", "zeta")]


def _largest_zeta_title(ds: xr.Dataset) -> str:
    return rf"at the largest magnification $\zeta$ = {number(float(ds.zeta[-1]))}"


def area(ds: xr.Dataset, ax: Any = None, max_curves: int = 12) -> Any:
    """Contact area versus magnification (few loads) or versus load at the largest magnification
    (more than six loads, or a sweep); for a plastic boundary total, elastic and plastic area.

    Parameters
    ----------
    ds : xarray.Dataset
        A solved Dataset (``area_fraction``; ``total_contact_fraction`` and
        ``plastic_area_fraction`` of an elastoplastic boundary are drawn when present).
    ax : matplotlib.axes.Axes, optional
        Where to draw (a new figure when not given).
    max_curves : int
        Most curves drawn per quantity (evenly picked loads or swept values).
    """
    a = need(ds, "area_fraction", "solve a scene first")
    items = [("A/A0", a)]
    if "plastic_area_fraction" in ds and "total_contact_fraction" in ds:
        items = [
            ("total", ds["total_contact_fraction"]),
            ("elastic", ds["elastic_area_fraction"]),
            ("plastic", ds["plastic_area_fraction"]),
        ]
    many = "p0" in a.dims and (a.sizes["p0"] > 6 or bool(_sweep_dims(a)))
    if many:
        items = [(q, d.isel(zeta=-1)) for q, d in items]
        ax = lines(ax, items, "p0", max_curves=max_curves)
        band(ax, ds, "area_fraction", "p0", human("Pa", ds["p0"].values)[0])
        ax.set_title(_largest_zeta_title(ds))
        if float(ds["p0"].min()) > 0:
            logx(ax)
            log_limits(ax, 5)
        else:  # tensile (adhesive) to compressive loads
            ax.axvline(0.0, color="0.6", lw=0.8, zorder=0)
            at = {"transform": ax.get_xaxis_transform(), "ha": "center", "color": "0.4"}
            ax.text(0.0, 0.02, "tensile | compressive ", fontsize="small", **at)
    else:
        ax = lines(ax, items, "zeta", max_curves=max_curves)
        band(ax, ds, "area_fraction", "zeta")
        ax.set_xscale("log")
        log_limits(ax, 5)
    ax.set_ylabel("contact area fraction A/A0" if len(items) > 1 else "relative contact area A/A0")
    return ax


def pressure_pdf(ds: xr.Dataset, ax: Any = None, max_curves: int = 12) -> Any:
    """P(p) at the largest magnification, one curve per load (pressure axis cut where every
    curve has fallen below 1e-3 of its peak)."""
    P = need(ds, "P", "set output.pressure_pdf = true").isel(zeta=-1)
    ax = lines(ax, [("P", P)], "p", max_curves=max_curves)
    vals = np.asarray(P.transpose(..., "p").values, float).reshape(-1, P.sizes["p"])
    p = np.asarray(ds["p"].values, float)
    keep = (vals > 1e-3 * np.nanmax(vals, axis=1, keepdims=True)).any(axis=0)
    factor = human("Pa", p)[0]
    if keep.any():
        ax.set_xlim(min(0.0, p[keep].min() / factor), p[keep].max() / factor)
    ax.set_ylim(bottom=0)
    ax.set_ylabel(f"pressure distribution P(p) [1/{human('Pa', p)[1]}]")
    ax.set_title(_largest_zeta_title(ds))
    return ax


def gap_pdf(ds: xr.Dataset, ax: Any = None, max_curves: int = 12) -> Any:
    """Distribution of interfacial separations P(u) (log y, 6 decades), one curve per load."""
    g = need(ds, "gap_pdf", "request [analyses.gap_pdf]")
    x = next(d for d in g.dims if d not in ("p0", *_sweep_dims(g)) or d == "u")
    ax = lines(
        ax, [("P(u)", g.where(g > 0))], x, max_curves=max_curves, ylabel="gap distribution P(u)"
    )
    log_limits(ax, 6)
    ax.set_title("distribution of interfacial separations")
    return ax


def leakage(ds: xr.Dataset, ax: Any = None, max_curves: int = 12) -> Any:
    """Leak rate versus squeezing pressure (log-log): critical-junction theory and, when stored,
    the effective-medium (Bruggeman) one; sealed loads marked below the curves."""
    q = need(ds, "leak_rate", "request [analyses.leakage]")
    items = [("critical junction", q)]
    if "leak_rate_emt" in ds:
        items.append(("effective medium (Bruggeman)", ds["leak_rate_emt"]))
    items = [(n, d.where(d > 0)) for n, d in items]
    ax = lines(ax, items, "p0", max_curves=max_curves, ylabel="leak rate Q")
    logx(ax)
    log_limits(ax, 10)
    sealed = ds.get("leak_sealed")
    if sealed is not None and sealed.dims == ("p0",) and bool(sealed.any()):
        _shade_sealed(ax, ds, sealed)
    return ax


def _shade_sealed(ax: Any, ds: xr.Dataset, sealed: xr.DataArray) -> None:
    """Shade the sealed loads (from the lightest sealed p0 up) and say where sealing starts."""
    factor, unit = human("Pa", ds["p0"].values)
    p_seal = float(ds["p0"].where(sealed > 0).min()) / factor
    ax.axvspan(p_seal, float(ds["p0"].max()) / factor, color="0.9", zorder=0, lw=0)
    ax.text(
        p_seal,
        0.04,
        f" sealed (Q = 0)\n from {p_seal:.3g} {unit}",
        transform=ax.get_xaxis_transform(),
        fontsize="small",
        va="bottom",
    )


def energy(ds: xr.Dataset, ax: Any = None, max_curves: int = 12) -> Any:
    """Elastic energy per nominal area versus p0 (log-log)."""
    u = need(ds, "elastic_energy", "request [analyses.elastic_energy]")
    ax = lines(
        ax, [("U", u.where(u > 0))], "p0", max_curves=max_curves, ylabel="elastic energy U/A0"
    )
    logx(ax)
    log_limits(ax, 8)
    ax.set_title("elastic energy stored in the deformed solid")
    return ax
