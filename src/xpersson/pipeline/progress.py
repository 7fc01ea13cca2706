"""Progress bars on stderr: the points of a sweep, the engine's work of a single long solve."""

from __future__ import annotations

import sys
import warnings
from typing import Any

import xarray as xr

from ..scene import ResolvedScene
from .run import run

__all__ = ["progress_bar", "run_with_progress"]


def progress_bar(total: int | None, progress: bool | None, desc: str, unit: str = "point") -> Any:
    """A tqdm progress bar on stderr, or ``None`` when not shown (``progress`` False, or None
    and stderr not a terminal; tqdm missing: warned)."""
    show = sys.stderr.isatty() if progress is None else bool(progress)
    if not show:
        return None
    try:
        from tqdm.auto import tqdm
    except ImportError:  # pragma: no cover - optional extra
        warnings.warn("progress needs tqdm: pip install 'xpersson[progress]'", stacklevel=3)
        return None
    return tqdm(
        total=total,
        desc=desc,
        unit=unit,
        unit_scale=unit != "point",
        file=sys.stderr,
        dynamic_ncols=True,
    )


def run_with_progress(
    rs: ResolvedScene, progress: bool | None, *, model_errors: bool = False
) -> xr.Dataset:
    """:func:`run` with a counter of the engine's work on stderr (long moving-wall solves).

    The bar appears only once a solver reports work (closed-form solves print nothing).
    """
    from ..engine import progress_reporting

    bar: list[Any] = []

    def advance(node_steps: int) -> None:
        if not bar:  # first report: make the bar (None when tqdm is missing: warned once)
            bar.append(progress_bar(None, progress, "xpersson solve", unit="node-step"))
        if bar[0] is not None:
            bar[0].update(node_steps)

    try:
        with progress_reporting(advance):
            return run(rs, model_errors=model_errors)
    finally:
        if bar and bar[0] is not None:
            bar[0].close()
