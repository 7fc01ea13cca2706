"""Figures of xpersson Datasets (matplotlib, imported only when drawing; the backend is
matplotlib's choice, Agg on a machine without a display).

Each function draws one kind on a matplotlib ``Axes`` (a new constrained-layout figure when none
is given) and returns it. Axes and legends use human units (kPa, MPa, µm, mm³/s) chosen from the
values; curves of a sweep differ in colour (one swept dimension, a sequential colour map, a colour
bar when there are many values) *and* line style (the next dimension, or the quantity), so no
curve hides another; legends sit outside the axes.

Kinds (:data:`KINDS`): ``area`` (A/A0 versus zeta, or versus p0 at zeta_max for many loads and
sweeps; total, elastic and plastic area for plastic boundaries), ``pressure_pdf``, ``gap_pdf``,
``leakage`` (both theories, sealed loads shaded), ``energy`` and ``friction`` (mu(v) at each
temperature). The user guide's "Plots" page says what each needs in the scene.

The package, one job per module: ``_units`` (human units and labels), ``_figure`` (matplotlib
access, new axes, log axes), ``_lines`` (curves, legends, colour bar), ``_kinds`` (the kinds drawn
straight from the Dataset), ``_friction`` (mu(v), re-solving a one-speed scene), ``_titles`` (the
suptitle from the archive's metadata); this face holds the kind table, :func:`plot` and
:func:`save`.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from typing import Any

import xarray as xr

from ._body import body
from ._figure import MatplotlibMissingError, pyplot
from ._friction import friction
from ._kinds import area, energy, gap_pdf, leakage, pressure_pdf
from ._psd import draw_psd, psd
from ._titles import suptitle
from ._units import human, text

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
    "psd",
    "draw_psd",
    "body",
    "save",
    "suptitle",
]

KINDS: dict[str, Callable[..., Any]] = {
    "area": area,
    "pressure_pdf": pressure_pdf,
    "gap_pdf": gap_pdf,
    "leakage": leakage,
    "energy": energy,
    "friction": friction,
    "psd": psd,
    "body": body,
}


def plot(ds: xr.Dataset, kind: str = "area", ax: Any = None, **kwargs: Any) -> Any:
    """Draw ``kind`` (one of :data:`KINDS`) and return the matplotlib Axes."""
    if kind not in KINDS:
        raise ValueError(f"kind: {kind!r} is not allowed; one of {', '.join(KINDS)}")
    return KINDS[kind](ds, ax=ax, **kwargs)


def save(ds: xr.Dataset, kind: str, path: str | os.PathLike[str], dpi: int = 150) -> str:
    """Draw ``kind`` into a new figure and write it to ``path`` (PNG, PDF, SVG); returns it.

    The figure's suptitle comes from the archive's own metadata (:func:`suptitle`: its title,
    the swept values it holds, the ``--set`` overrides in its history); the kind's own axes
    title says what is drawn."""
    plt = pyplot()
    ax = plot(ds, kind)
    title = suptitle(ds)
    if title:
        ax.figure.suptitle(title, fontsize="large")
        ax.title.set_fontsize("medium")
    ax.figure.savefig(path, dpi=dpi)
    plt.close(ax.figure)
    return str(path)
