"""matplotlib access and the axes helpers every kind shares (new axes, log axes and their limits).

matplotlib is imported here, inside the functions, and nowhere else in xpersson but the other
modules of this package (inside their functions too), so ``import xpersson.plot`` stays light.
The backend is matplotlib's choice (Agg on a machine without a display); xpersson never sets it.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["MatplotlibMissingError", "pyplot"]


class MatplotlibMissingError(ImportError):
    """matplotlib is not installed; ``str(error)`` is a one-line message saying how to get it."""


def pyplot() -> Any:
    """``matplotlib.pyplot`` (the backend that matplotlib picks: Agg without a display);
    :class:`MatplotlibMissingError` when matplotlib is not installed."""
    try:
        import matplotlib.pyplot as plt
    except ImportError:
        raise MatplotlibMissingError(
            "xpersson plot needs matplotlib, which is not installed: pip install 'xpersson[plot]'"
        ) from None
    return plt


def new_axes(ax: Any) -> Any:
    """``ax``, or the Axes of a new constrained-layout figure when ``ax`` is None."""
    if ax is not None:
        return ax
    return pyplot().subplots(figsize=(6.4, 4.2), layout="constrained")[1]


def log_limits(ax: Any, decades: float) -> None:
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


def logx(ax: Any) -> None:
    """Log x axis; tick labels as plain numbers (0.1, 1, 10) when it spans under 4 decades."""
    from matplotlib.ticker import FuncFormatter

    ax.set_xscale("log")
    xs = np.concatenate([np.asarray(ln.get_xdata(), float) for ln in ax.lines] or [np.ones(1)])
    xs = xs[np.isfinite(xs) & (xs > 0)]
    if xs.size and xs.max() < 1e4 * xs.min():
        ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))


def scaled_formatter(factor: float) -> Any:
    """A tick formatter showing the values divided by ``factor`` (a colour bar's human unit)."""
    from matplotlib.ticker import FuncFormatter

    return FuncFormatter(lambda v, _: f"{v / factor:g}")
