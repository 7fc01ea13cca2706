"""Curves of one or more quantities along one dimension, and their legends or colour bar.

Colour = the largest other dimension (a sequential colour map), line style = the quantity (or the
next dimension, with staggered markers so coinciding curves stay visible), markers = any further
dimension; legends sit outside the axes, a colour bar replaces the colour legend for many values.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import xarray as xr

from ._figure import new_axes, scaled_formatter
from ._units import SYMBOLS, compact, human, label, text

__all__ = ["lines"]

STYLES = ["-", "--", ":", "-."]
MARKERS = ["o", "s", "^", "D", "v", "P"]
MAX_LEGEND = 7  # more colour values than this: a colour bar instead of legend entries


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


def lines(
    ax: Any,
    items: list[tuple[str, xr.DataArray]],
    x: str,
    *,
    max_curves: int = 12,
    ylabel: str | None = None,
    extra: list[Any] | None = None,
) -> Any:
    """Draw every quantity of ``items`` (name, DataArray) along dimension ``x`` on ``ax`` (a new
    figure when None) and return the Axes; at most ``max_curves`` curves per quantity.

    When fewer than all values of the colour dimension are drawn, its legend title (or colour
    bar label) says how many of how many; ``extra`` legend handles (a marked point) join the
    line-style legend."""
    ax = new_axes(ax)
    da0 = items[0][1]
    others = sorted((d for d in da0.dims if d != x), key=lambda d: -da0.sizes[d])
    cdim, sdims = (others[0] if others else None), others[1:]
    xs = da0[x]
    xf = human(xs.attrs.get("units", "1"), xs.values)
    yf = human(da0.attrs.get("units", "1"), np.concatenate([d.values.ravel() for _, d in items]))
    # a density along x (P [Pa^-1] along p [Pa]): 1/(x unit), whatever the caret form
    if compact(da0.attrs.get("units", "1")) == compact(f"{xs.attrs.get('units')}-1"):
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
    ax.set_xlabel(label(xs, x, xf))
    words = ylabel or str(da0.attrs.get("long_name", da0.name))
    ax.set_ylabel(f"{words} [{yf[1]}]" if yf[1] else words)
    note = f" ({cidx.size} of {cvals.size} drawn)" if cidx.size < cvals.size else ""
    _legends(ax, items, (cdim, note), cvals[cidx], norm, cmap, da0, sdims, extra or [])
    return ax


def _flatten(curve: xr.DataArray, rest: list[str]) -> list[np.ndarray]:
    if not rest:
        return [curve.values]
    stacked = curve.stack(_r=rest).transpose("_r", ...)
    return [stacked.values[i] for i in range(stacked.sizes["_r"])]


def _handle(entry: str, ls: str = "-", marker: str | None = None, color: Any = "0.3") -> Any:
    """A legend entry ``entry`` drawn as a short line of style ``ls`` with ``marker``."""
    from matplotlib.lines import Line2D

    return Line2D([], [], color=color, ls=ls, marker=marker, ms=4.5, lw=1.6, label=entry)


def _legends(ax, items, cdim_note, cvals, norm, cmap, da0, sdims, extra) -> None:  # noqa: ANN001
    """Colour legend (or colour bar) and line-style legend, outside the axes of our figures;
    ``cdim_note`` is the colour dimension and the note on how many of its values are drawn."""
    from matplotlib.cm import ScalarMappable

    cdim, note = cdim_note
    units = da0[cdim].attrs.get("units", "1") if cdim else "1"
    colour = [_handle(text(v, units), color=cmap(norm(v))) for v in cvals[::-1]]
    styles, stitle = [], None
    if len(items) > 1:
        styles = [_handle(q, STYLES[i % 4]) for i, (q, _) in enumerate(items)]
    elif sdims:
        su, stitle = da0[sdims[0]].attrs.get("units", "1"), SYMBOLS.get(sdims[0], sdims[0])
        values = np.asarray(da0[sdims[0]].values, float)
        styles = [_handle(text(v, su), STYLES[i % 4], MARKERS[i % 6]) for i, v in enumerate(values)]
    styles = styles + list(extra)
    kw: dict[str, Any] = {"fontsize": "small", "frameon": False}
    fig = ax.figure
    own = type(fig.get_layout_engine()).__name__ == "ConstrainedLayoutEngine" and (
        sum(not hasattr(a, "_colorbar") for a in fig.axes) == 1
    )
    if cdim and len(cvals) > MAX_LEGEND:
        factor, unit = human(units, cvals)
        bar = fig.colorbar(ScalarMappable(norm=norm, cmap=cmap), ax=ax, pad=0.02)
        bar.set_label(label(da0[cdim], cdim, (factor, unit)) + note)
        if factor != 1.0:
            bar.formatter = scaled_formatter(factor)
            bar.update_ticks()
    elif cdim and len(cvals) > 1:
        title = SYMBOLS.get(cdim, cdim) + note
        if own:
            fig.legend(handles=colour, title=title, loc="outside right upper", **kw)
        else:
            ax.add_artist(ax.legend(handles=colour, title=title, **kw))
    if not styles:
        return
    if own and cdim and 1 < len(cvals) <= MAX_LEGEND:
        fig.legend(handles=styles, title=stitle, loc="outside right lower", **kw)
    else:
        ax.legend(handles=styles, title=stitle, loc="best", **kw)
