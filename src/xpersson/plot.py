"""Plots of xpersson Datasets (matplotlib, imported only here; Agg when no display is set).

Each function draws one kind on a matplotlib ``Axes`` (created when not given) and returns it:
units from the variables' CF attributes on the axes, log axes where the physics is
logarithmic, one curve per load or per swept value (at most ``max_curves``, evenly picked).

==============  =====================================================  ======================
kind            what                                                   needs
==============  =====================================================  ======================
area            A/A0 versus zeta (one scene) or versus p0 at zeta_max  core
pressure_pdf    P(p) at the largest magnification                      output.pressure_pdf
gap_pdf         gap distribution P(u)                                  analyses.gap_pdf
leakage         leak rate versus p0                                    analyses.leakage
energy          elastic energy versus p0                               analyses.elastic_energy
friction        friction coefficient versus sliding speed or p0        a friction analysis
==============  =====================================================  ======================
"""

from __future__ import annotations

import os
from collections.abc import Callable
from typing import Any

import numpy as np
import xarray as xr

__all__ = [
    "KINDS",
    "plot",
    "area",
    "pressure_pdf",
    "gap_pdf",
    "leakage",
    "energy",
    "friction",
    "save",
]


def _plt() -> Any:
    import matplotlib

    if not os.environ.get("DISPLAY") and matplotlib.get_backend().lower() != "agg":
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _axes(ax: Any) -> Any:
    if ax is not None:
        return ax
    _, ax = _plt().subplots(figsize=(5.5, 4.0), layout="constrained")
    return ax


def _label(var: xr.DataArray, name: str | None = None) -> str:
    text = var.attrs.get("long_name", name or var.name or "")
    units = var.attrs.get("units")
    return f"{text} [{units}]" if units not in (None, "", "1") else str(text)


def _value(v: Any, units: str) -> str:
    u = "" if units in ("", "1") else f" {units}"
    return f"{float(v):.3g}{u}"


def _curves(da: xr.DataArray, x: str, max_curves: int) -> list[tuple[str, xr.DataArray]]:
    """Split ``da`` into 1-D curves along ``x``: one per combination of its other dims."""
    others = [d for d in da.dims if d != x]
    if not others:
        return [("", da)]
    stacked = da.stack(_curve=others)
    n = stacked.sizes["_curve"]
    picks = np.unique(np.linspace(0, n - 1, min(n, max_curves)).round().astype(int))
    out = []
    for i in picks:
        curve = stacked.isel(_curve=int(i))
        label = ", ".join(
            f"{d} = {_value(curve[d].values, da[d].attrs.get('units', ''))}"
            for d in others
            if d in da.coords
        )
        out.append((label, curve.drop_vars(["_curve", *others], errors="ignore")))
    return out


def _draw(
    da: xr.DataArray,
    x: str,
    ax: Any,
    *,
    logx: bool,
    logy: bool,
    max_curves: int,
    xcoord: xr.DataArray | None = None,
) -> Any:
    ax = _axes(ax)
    xs = da[x] if xcoord is None else xcoord
    for label, curve in _curves(da, x, max_curves):
        y = np.asarray(curve.values, float)
        ax.plot(np.asarray(xs.values, float), y, label=label or None)
    ax.set_xlabel(_label(xs, x))
    ax.set_ylabel(_label(da))
    if logx:
        ax.set_xscale("log")
    if logy:
        ax.set_yscale("log")
    if any(line.get_label() and not line.get_label().startswith("_") for line in ax.lines):
        ax.legend(fontsize="small", frameon=False)
    return ax


def _need(ds: xr.Dataset, name: str, hint: str) -> xr.DataArray:
    if name not in ds:
        raise ValueError(f"this Dataset has no {name!r}; {hint}")
    return ds[name]


def area(ds: xr.Dataset, ax: Any = None, max_curves: int = 8) -> Any:
    """A/A0 versus magnification (log x), one curve per load; for a sweep, A/A0 at the largest
    magnification versus p0 (log-log), one curve per swept value."""
    a = _need(ds, "area_fraction", "solve a scene first")
    sweep = [d for d in a.dims if d not in ("p0", "zeta")]
    if sweep and "p0" in a.dims and a.sizes["p0"] > 1:
        last = a.isel(zeta=-1)
        ax = _draw(last, "p0", ax, logx=True, logy=True, max_curves=max_curves)
        ax.set_title(f"A/A0 at zeta = {float(ds.zeta[-1]):.3g}")
        return ax
    return _draw(a, "zeta", ax, logx=True, logy=False, max_curves=max_curves)


def pressure_pdf(ds: xr.Dataset, ax: Any = None, max_curves: int = 8) -> Any:
    """P(p) at the largest magnification, one curve per load."""
    P = _need(ds, "P", "set output.pressure_pdf = true").isel(zeta=-1)
    ax = _draw(P, "p", ax, logx=False, logy=False, max_curves=max_curves)
    ax.set_title(f"zeta = {float(ds.zeta[-1]):.3g}")
    return ax


def gap_pdf(ds: xr.Dataset, ax: Any = None, max_curves: int = 8) -> Any:
    """Distribution of interfacial separations P(u) (log y), one curve per load."""
    g = _need(ds, "gap_pdf", "request [analyses.gap_pdf]")
    g = g.where(g > 0)
    return _draw(g, "u", ax, logx=False, logy=True, max_curves=max_curves)


def leakage(ds: xr.Dataset, ax: Any = None, max_curves: int = 8) -> Any:
    """Leak rate versus squeezing pressure (log-log)."""
    q = _need(ds, "leak_rate", "request [analyses.leakage]")
    q = q.where(q > 0)
    return _draw(q, "p0", ax, logx=True, logy=True, max_curves=max_curves)


def energy(ds: xr.Dataset, ax: Any = None, max_curves: int = 8) -> Any:
    """Elastic energy per nominal area versus p0 (log-log)."""
    u = _need(ds, "elastic_energy", "request [analyses.elastic_energy]")
    return _draw(u.where(u > 0), "p0", ax, logx=True, logy=True, max_curves=max_curves)


def friction(ds: xr.Dataset, ax: Any = None, max_curves: int = 8) -> Any:
    """Friction coefficient versus sliding speed (log x) when swept, else versus p0."""
    names = [n for n in ("mu", "friction_coefficient") if n in ds.data_vars]
    names += [
        n
        for n in ds.data_vars
        if n not in names
        and str(ds[n].attrs.get("long_name", "")).startswith("friction coefficient")
    ]
    if not names:
        raise ValueError(
            "this Dataset has no friction coefficient; request a friction analysis "
            "(e.g. [analyses.friction] of the viscoelastic plugin)"
        )
    mu = ds[names[0]]
    x = next((d for d in ("v", "velocity") if d in mu.dims), "p0")
    if "zeta" in mu.dims:
        mu = mu.isel(zeta=-1)
    return _draw(mu, x, ax, logx=True, logy=False, max_curves=max_curves)


KINDS: dict[str, Callable[..., Any]] = {
    "area": area,
    "pressure_pdf": pressure_pdf,
    "gap_pdf": gap_pdf,
    "leakage": leakage,
    "energy": energy,
    "friction": friction,
}


def plot(ds: xr.Dataset, kind: str = "area", ax: Any = None, **kwargs: Any) -> Any:
    """Draw ``kind`` (one of :data:`KINDS`) and return the matplotlib Axes."""
    if kind not in KINDS:
        raise ValueError(f"kind: {kind!r} is not allowed; one of {', '.join(KINDS)}")
    return KINDS[kind](ds, ax=ax, **kwargs)


def save(ds: xr.Dataset, kind: str, path: str | os.PathLike[str], dpi: int = 110) -> str:
    """Draw ``kind`` into a new figure and write it to ``path`` (PNG, PDF, SVG)."""
    plt = _plt()
    ax = plot(ds, kind)
    title = ds.attrs.get("title")
    if title and not ax.get_title():
        ax.set_title(str(title)[:70], fontsize="medium")
    ax.figure.savefig(path, dpi=dpi)
    plt.close(ax.figure)
    return str(path)
