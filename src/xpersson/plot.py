"""Figures of xpersson Datasets (matplotlib, imported only here; Agg when no display is set).

Each function draws one kind on a matplotlib ``Axes`` (a new constrained-layout figure when none
is given) and returns it. Axes and legends use human units (kPa, MPa, µm, mm³/s) chosen from the
values; curves of a sweep differ in colour (one swept dimension, a sequential colour map, a colour
bar when there are many values) *and* line style (the next dimension, or the quantity), so no
curve hides another; legends sit outside the axes.

Kinds (:data:`KINDS`): ``area`` (A/A0 versus zeta, or versus p0 at zeta_max for many loads and
sweeps; total, elastic and plastic area for plastic boundaries), ``pressure_pdf``, ``gap_pdf``,
``leakage`` (both theories, sealed loads shaded), ``energy`` and ``friction`` (mu(v) at each
temperature). The user guide's "Plots" page says what each needs in the scene.
"""

from __future__ import annotations

import json
import os
import textwrap
import warnings
from collections.abc import Callable
from typing import Any

import numpy as np
import xarray as xr

__all__ = [
    "KINDS",
    "MatplotlibMissingError",
    "human",
    "pyplot",
    "text",
    "plot",
    "area",
    "pressure_pdf",
    "gap_pdf",
    "leakage",
    "energy",
    "friction",
    "save",
]

STYLES = ["-", "--", ":", "-."]
MARKERS = ["o", "s", "^", "D", "v", "P"]
MAX_LEGEND = 7  # more colour values than this: a colour bar instead of legend entries
# human prefixes per CF unit: (factor in SI, text), largest first
_PREFIXES: dict[str, list[tuple[float, str]]] = {
    "Pa": [(1e9, "GPa"), (1e6, "MPa"), (1e3, "kPa"), (1.0, "Pa")],
    "m": [(1e-3, "mm"), (1e-6, "µm"), (1e-9, "nm")],
    "m s-1": [(1.0, "m/s"), (1e-2, "cm/s"), (1e-3, "mm/s"), (1e-6, "µm/s"), (1e-9, "nm/s")],
    "m3 s-1": [(1e-6, "cm³/s"), (1e-9, "mm³/s")],
    "J m-2": [(1.0, "J/m²"), (1e-3, "mJ/m²"), (1e-6, "µJ/m²")],
}
_SYMBOLS = {"p0": "$p_0$", "zeta": r"$\zeta$", "v": "$v$", "T": "$T$", "p": "$p$", "u": "$u$"}


class MatplotlibMissingError(ImportError):
    """matplotlib is not installed; ``str(error)`` is a one-line message saying how to get it."""


def pyplot() -> Any:
    """``matplotlib.pyplot`` (Agg backend without a display); :class:`MatplotlibMissingError`
    when matplotlib is not installed."""
    try:
        import matplotlib
    except ImportError:
        raise MatplotlibMissingError(
            "xpersson plot needs matplotlib, which is not installed: pip install 'xpersson[plot]'"
        ) from None
    if not os.environ.get("DISPLAY") and matplotlib.get_backend().lower() != "agg":
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _axes(ax: Any) -> Any:
    return ax if ax is not None else pyplot().subplots(figsize=(6.4, 4.2), layout="constrained")[1]


def human(units: str, values: Any) -> tuple[float, str]:
    """The SI factor and text of the human unit for ``values`` in CF ``units``.

    Parameters
    ----------
    units : str
        CF/UDUNITS unit string of the values (``"Pa"``, ``"m"``, ``"m3 s-1"``, ...).
    values : array_like
        Values in ``units``; the prefix is the largest one not above their largest magnitude.

    Returns
    -------
    factor, text : float, str
        Divide the values by ``factor`` to express them in ``text`` (``(1e6, "MPa")``).
    """
    table = _PREFIXES.get(units := units.replace("^", ""))  # "m s^-1" as "m s-1"
    if not table:
        return 1.0, {"1": "", "m-1": "1/m", "m2": "m²", "K": "K"}.get(units, units)
    v = np.abs(np.asarray(values, float))
    v = v[np.isfinite(v) & (v > 0)]
    top = float(v.max()) if v.size else table[-1][0]
    return next(((f, t) for f, t in table if top >= 0.999 * f), table[-1])


def _num(value: float) -> str:
    """``1e+05`` as mathtext ``10^5``; other values with three digits."""
    exp = np.log10(value) if value > 0 else 0.5
    return f"$10^{{{int(round(exp))}}}$" if abs(exp - round(exp)) < 1e-9 else f"{value:.3g}"


def text(value: float, units: str) -> str:
    """One value with its human unit: ``10 kPa``, ``0.6``, ``20 °C``."""
    if units == "K":
        return f"{value - 273.15:.3g} °C"
    factor, unit = human(units, [value])
    return f"{value / factor:.3g} {unit}".strip()


def _label(var: xr.DataArray, name: str, factor_unit: tuple[float, str]) -> str:
    words = f"{var.attrs.get('long_name', name)} {_SYMBOLS.get(name, '')}".strip()
    return words + (f" [{factor_unit[1]}]" if factor_unit[1] else "")


def _picks(n: int, most: int) -> np.ndarray:
    return np.unique(np.linspace(0, n - 1, min(n, max(most, 1))).round().astype(int))


def _norm(values: np.ndarray) -> Any:
    import matplotlib.colors as mcolors

    v = np.asarray(values, float)
    if v.size <= MAX_LEGEND:  # a legend: evenly spread colours, whatever the values
        ranks = {float(x): i / max(v.size - 1, 1) for i, x in enumerate(np.sort(v))}
        return lambda x: ranks[float(x)]
    lo, hi = float(np.min(v)), float(np.max(v))
    if lo > 0 and hi / lo > 20:
        return mcolors.LogNorm(lo, hi)
    return mcolors.Normalize(lo, hi if hi > lo else lo + 1.0)


def _cmap() -> Any:
    import matplotlib
    import matplotlib.colors as mcolors

    base = matplotlib.colormaps["viridis"]
    return mcolors.ListedColormap(base(np.linspace(0.0, 0.85, 256)), name="xpersson")


def _lines(
    ax: Any,
    items: list[tuple[str, xr.DataArray]],
    x: str,
    *,
    max_curves: int = 12,
    ylabel: str | None = None,
) -> Any:
    """Draw every quantity of ``items`` along ``x``: colour = the largest other dimension, line
    style = the quantity (or the next dimension, with staggered markers so coinciding curves stay
    visible), markers = any further dimension; legends (or a colour bar) outside the axes."""
    ax = _axes(ax)
    da0 = items[0][1]
    others = sorted((d for d in da0.dims if d != x), key=lambda d: -da0.sizes[d])
    cdim, sdims = (others[0] if others else None), others[1:]
    xs = da0[x]
    xf = human(xs.attrs.get("units", "1"), xs.values)
    yf = human(da0.attrs.get("units", "1"), np.concatenate([d.values.ravel() for _, d in items]))
    if da0.attrs.get("units") == f"{xs.attrs.get('units')}-1":  # a density along x: 1/(x unit)
        yf = (1.0 / xf[0], f"1/{xf[1]}")
    n_style = max([len(items)] + [da0.sizes[d] for d in sdims[:1]])
    cvals = np.asarray(da0[cdim].values, float) if cdim else np.zeros(1)
    cidx = _picks(cvals.size, max_curves // max(n_style, 1)) if cdim else np.array([0])
    norm, cmap = _norm(cvals[cidx]), _cmap()
    style_items = [(q, {}) for q in items]
    if len(items) == 1 and sdims:
        style_items = [(items[0], {sdims[0]: i}) for i in range(da0.sizes[sdims[0]])]
    step = max(1, xs.size // 7)
    k = 0
    for si, ((_, da), sel) in enumerate(style_items):
        for ci in cidx:
            curve = (da.isel({cdim: ci}) if cdim else da).isel(sel)
            rest = [d for d in curve.dims if d != x]
            for mi, flat in enumerate(_flatten(curve, rest)):
                marked = bool(sel) or bool(rest)
                ax.plot(
                    np.asarray(xs.values, float) / xf[0],
                    np.asarray(flat, float) / yf[0],
                    color=cmap(norm(cvals[ci])) if cdim else "k",
                    ls=STYLES[si % len(STYLES)],
                    marker=MARKERS[(si + mi) % len(MARKERS)] if marked else None,
                    markevery=(k * step // 5 % step, step),
                    ms=4.5,
                    lw=1.6,
                )
                k += 1
    ax.set_xlabel(_label(xs, x, xf))
    words = ylabel or str(da0.attrs.get("long_name", da0.name))
    ax.set_ylabel(f"{words} [{yf[1]}]" if yf[1] else words)
    _legends(ax, items, cdim, cvals[cidx], norm, cmap, da0, sdims)
    return ax


def _flatten(curve: xr.DataArray, rest: list[str]) -> list[np.ndarray]:
    if not rest:
        return [curve.values]
    stacked = curve.stack(_r=rest).transpose("_r", ...)
    return [stacked.values[i] for i in range(stacked.sizes["_r"])]


def _handle(label: str, ls: str = "-", marker: str | None = None, color: Any = "0.3") -> Any:
    from matplotlib.lines import Line2D

    return Line2D([], [], color=color, ls=ls, marker=marker, ms=4.5, lw=1.6, label=label)


def _legends(ax, items, cdim, cvals, norm, cmap, da0, sdims) -> None:  # noqa: ANN001
    """Colour legend (or colour bar) and line-style legend, outside the axes of our figures."""
    from matplotlib.cm import ScalarMappable

    units = da0[cdim].attrs.get("units", "1") if cdim else "1"
    colour = [_handle(text(v, units), color=cmap(norm(v))) for v in cvals[::-1]]
    styles, stitle = [], None
    if len(items) > 1:
        styles = [_handle(q, STYLES[i % 4]) for i, (q, _) in enumerate(items)]
    elif sdims:
        su, stitle = da0[sdims[0]].attrs.get("units", "1"), _SYMBOLS.get(sdims[0], sdims[0])
        values = np.asarray(da0[sdims[0]].values, float)
        styles = [_handle(text(v, su), STYLES[i % 4], MARKERS[i % 6]) for i, v in enumerate(values)]
    kw: dict[str, Any] = {"fontsize": "small", "frameon": False}
    fig = ax.figure
    own = type(fig.get_layout_engine()).__name__ == "ConstrainedLayoutEngine" and (
        sum(not hasattr(a, "_colorbar") for a in fig.axes) == 1
    )
    if cdim and len(cvals) > MAX_LEGEND:
        factor, unit = human(units, cvals)
        bar = fig.colorbar(ScalarMappable(norm=norm, cmap=cmap), ax=ax, pad=0.02)
        bar.set_label(_label(da0[cdim], cdim, (factor, unit)))
        if factor != 1.0:
            bar.formatter = _scaled_formatter(factor)
            bar.update_ticks()
    elif cdim and len(cvals) > 1:
        if own:
            fig.legend(
                handles=colour, title=_SYMBOLS.get(cdim, cdim), loc="outside right upper", **kw
            )
        else:
            ax.add_artist(ax.legend(handles=colour, title=_SYMBOLS.get(cdim, cdim), **kw))
    if not styles:
        return
    if own and cdim and 1 < len(cvals) <= MAX_LEGEND:
        fig.legend(handles=styles, title=stitle, loc="outside right lower", **kw)
    else:
        ax.legend(handles=styles, title=stitle, loc="best", **kw)


def _scaled_formatter(factor: float) -> Any:
    from matplotlib.ticker import FuncFormatter

    return FuncFormatter(lambda v, _: f"{v / factor:g}")


def _need(ds: xr.Dataset, name: str, hint: str) -> xr.DataArray:
    if name not in ds:
        raise ValueError(f"this Dataset has no {name!r}; {hint}")
    return ds[name]


def _log_limits(ax: Any, decades: float) -> None:
    """Log y axis spanning at most ``decades`` below the largest plotted value (linear when the
    values span less than one decade)."""
    ys = np.concatenate([np.asarray(ln.get_ydata(), float) for ln in ax.lines] or [np.ones(1)])
    ys = ys[np.isfinite(ys) & (ys > 0)]
    if ys.size and ys.max() < 10 * ys.min():
        ax.set_ylim(0, 1.08 * float(ys.max()))
        return
    ax.set_yscale("log")
    if ys.size:
        top = float(ys.max())
        ax.set_ylim(max(float(ys.min()), top * 10.0**-decades) / 1.5, top * 1.6)


def _logx(ax: Any) -> None:
    """Log x axis; tick labels as plain numbers (0.1, 1, 10) when it spans under 4 decades."""
    from matplotlib.ticker import FuncFormatter

    ax.set_xscale("log")
    xs = np.concatenate([np.asarray(ln.get_xdata(), float) for ln in ax.lines] or [np.ones(1)])
    xs = xs[np.isfinite(xs) & (xs > 0)]
    if xs.size and xs.max() < 1e4 * xs.min():
        ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))


def _sweep_dims(da: xr.DataArray) -> list[str]:
    return [d for d in da.dims if d not in ("p0", "zeta")]


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
    a = _need(ds, "area_fraction", "solve a scene first")
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
        ax = _lines(ax, items, "p0", max_curves=max_curves)
        ax.set_title(rf"at the largest magnification $\zeta$ = {_num(float(ds.zeta[-1]))}")
        if float(ds["p0"].min()) > 0:
            _logx(ax)
            _log_limits(ax, 5)
        else:  # tensile (adhesive) to compressive loads
            ax.axvline(0.0, color="0.6", lw=0.8, zorder=0)
            at = {"transform": ax.get_xaxis_transform(), "ha": "center", "color": "0.4"}
            ax.text(0.0, 0.02, "tensile | compressive ", fontsize="small", **at)
    else:
        ax = _lines(ax, items, "zeta", max_curves=max_curves)
        ax.set_xscale("log")
        _log_limits(ax, 5)
    ax.set_ylabel("contact area fraction A/A0" if len(items) > 1 else "relative contact area A/A0")
    return ax


def pressure_pdf(ds: xr.Dataset, ax: Any = None, max_curves: int = 12) -> Any:
    """P(p) at the largest magnification, one curve per load (pressure axis cut where every
    curve has fallen below 1e-3 of its peak)."""
    P = _need(ds, "P", "set output.pressure_pdf = true").isel(zeta=-1)
    ax = _lines(ax, [("P", P)], "p", max_curves=max_curves)
    vals = np.asarray(P.transpose(..., "p").values, float).reshape(-1, P.sizes["p"])
    p = np.asarray(ds["p"].values, float)
    keep = (vals > 1e-3 * np.nanmax(vals, axis=1, keepdims=True)).any(axis=0)
    factor = human("Pa", p)[0]
    if keep.any():
        ax.set_xlim(min(0.0, p[keep].min() / factor), p[keep].max() / factor)
    ax.set_ylim(bottom=0)
    ax.set_ylabel(f"pressure distribution P(p) [1/{human('Pa', p)[1]}]")
    ax.set_title(rf"at the largest magnification $\zeta$ = {_num(float(ds.zeta[-1]))}")
    return ax


def gap_pdf(ds: xr.Dataset, ax: Any = None, max_curves: int = 12) -> Any:
    """Distribution of interfacial separations P(u) (log y, 6 decades), one curve per load."""
    g = _need(ds, "gap_pdf", "request [analyses.gap_pdf]")
    x = next(d for d in g.dims if d not in ("p0", *_sweep_dims(g)) or d == "u")
    ax = _lines(
        ax, [("P(u)", g.where(g > 0))], x, max_curves=max_curves, ylabel="gap distribution P(u)"
    )
    _log_limits(ax, 6)
    return ax


def leakage(ds: xr.Dataset, ax: Any = None, max_curves: int = 12) -> Any:
    """Leak rate versus squeezing pressure (log-log): critical-junction theory and, when stored,
    the effective-medium (Bruggeman) one; sealed loads marked below the curves."""
    q = _need(ds, "leak_rate", "request [analyses.leakage]")
    items = [("critical junction", q)]
    if "leak_rate_emt" in ds:
        items.append(("effective medium (Bruggeman)", ds["leak_rate_emt"]))
    items = [(n, d.where(d > 0)) for n, d in items]
    ax = _lines(ax, items, "p0", max_curves=max_curves, ylabel="leak rate Q")
    _logx(ax)
    _log_limits(ax, 10)
    sealed = ds.get("leak_sealed")
    if sealed is not None and sealed.dims == ("p0",) and bool(sealed.any()):
        factor = human("Pa", ds["p0"].values)[0]
        p_seal = float(ds["p0"].where(sealed > 0).min()) / factor
        ax.axvspan(p_seal, float(ds["p0"].max()) / factor, color="0.9", zorder=0, lw=0)
        ax.text(
            p_seal,
            0.04,
            f" sealed (Q = 0)\n from {p_seal:.3g} {human('Pa', ds['p0'].values)[1]}",
            transform=ax.get_xaxis_transform(),
            fontsize="small",
            va="bottom",
        )
    return ax


def energy(ds: xr.Dataset, ax: Any = None, max_curves: int = 12) -> Any:
    """Elastic energy per nominal area versus p0 (log-log)."""
    u = _need(ds, "elastic_energy", "request [analyses.elastic_energy]")
    ax = _lines(
        ax, [("U", u.where(u > 0))], "p0", max_curves=max_curves, ylabel="elastic energy U/A0"
    )
    _logx(ax)
    _log_limits(ax, 8)
    return ax


def _friction_sweep(ds: xr.Dataset, speeds: np.ndarray, temps: list[float]) -> xr.Dataset | None:
    """Re-solve the archive's scene over sliding speeds [m/s] and temperatures [K]."""
    if "xpersson_scene" not in ds.attrs:
        return None
    from .api import solve  # deferred: plotting an archive needs no solver otherwise
    from .scene import Scene, SceneError

    data = json.loads(ds.attrs["xpersson_scene"])
    data["coefficient"]["velocity"] = [f"{float(v)!r} m/s" for v in speeds]
    data["coefficient"]["temperature"] = [f"{float(t)!r} K" for t in temps]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            return solve(Scene(data, source=None))
        except SceneError:  # e.g. the archive's coefficient plugin is not installed here
            return None


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
    resolve : bool
        When ``ds`` holds one sliding speed, re-solve its stored scene over ``speeds`` at its
        temperature and 20 K below and above (about 10 s); the stored point is marked.
    speeds : array_like, optional
        Sliding speeds [m/s] of the re-solve (default 17 values from 1e-8 to 1e2 m/s).
    """
    mu = _need(ds, "mu", "request a friction analysis (e.g. [analyses.friction])")
    point = None
    if "v" not in mu.dims and resolve:
        t0 = float(ds["rubber_temperature"]) if "rubber_temperature" in ds else 293.15
        v = np.geomspace(1e-8, 1e2, 17) if speeds is None else np.asarray(speeds, float)
        swept = _friction_sweep(ds, v, [t0 - 20.0, t0, t0 + 20.0])
        if swept is not None:
            point = (float(ds["sliding_speed"]), ds["mu"])
            ds = swept
            mu = ds["mu"]
    if "v" not in mu.dims:
        return _lines(ax, [("mu", mu)], "p0", max_curves=max_curves)
    heavy = {"p0": -1} if "p0" in mu.dims else {}
    items = [("total", mu.isel(heavy))]
    if "mu_visc" in ds:
        items.append(("viscoelastic part", ds["mu_visc"].isel(heavy)))
    mu = items[0][1]
    ax = _lines(ax, items, "v", max_curves=max_curves)
    ax.set_xscale("log")
    ax.set_ylim(bottom=0)
    ax.set_ylabel(r"friction coefficient $\mu$")
    if point is not None:
        vf = human("m s-1", ds["v"].values)[0]
        ax.plot(point[0] / vf, float(np.ravel(point[1].values)[-1]), "k*", ms=11, label="_stored")
    if "p0" in mu.coords:
        ax.set_title(f"$p_0$ = {text(float(mu['p0']), 'Pa')}")
    return ax


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


def save(ds: xr.Dataset, kind: str, path: str | os.PathLike[str], dpi: int = 150) -> str:
    """Draw ``kind`` into a new figure and write it to ``path`` (PNG, PDF, SVG); returns it.

    The Dataset's title is the figure's suptitle (wrapped); the kind's own subtitle stays."""
    plt = pyplot()
    ax = plot(ds, kind)
    title = ds.attrs.get("title")
    if title:
        ax.figure.suptitle(textwrap.fill(str(title), 60), fontsize="large")
        ax.title.set_fontsize("medium")
    ax.figure.savefig(path, dpi=dpi)
    plt.close(ax.figure)
    return str(path)
