"""The public facade: :func:`solve` builds the scene and dispatches to one run or to a sweep."""

from __future__ import annotations

import sys
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import xarray as xr

from .pipeline import as_scene, run, run_with_progress
from .pipeline.frontend import resolve, reused
from .plugins import Registry, get_registry
from .scene import Scene
from .sweep import expand

__all__ = ["solve"]


def solve(
    scene: str | Path | Mapping[str, Any] | Scene,
    *,
    registry: Registry | None = None,
    scheduler: Any = None,
    progress: bool | None = False,
    output: str | Path | None = None,
    chunk: int | None = None,
    workers: int | None = None,
    resume: bool | None = None,
    overwrite: bool = False,
    **overrides: Any,
) -> xr.Dataset:
    """Solve a scene and return the Dataset over (sweep dims..., p0, zeta[, p]).

    Parameters
    ----------
    scene : path, dict or Scene
        A TOML scene file, the same structure as a dict, or a :class:`~xpersson.Scene`.
        Sweepable parameters may be lists or ranges (see :mod:`xpersson.sweep`).
    registry : Registry, optional
        Plugin registry (default: the entry-point registry).
    scheduler : None, str or distributed.Client
        Where the points of a sweep run: ``None``/``"serial"`` (default), ``"threads"``,
        ``"processes"`` (a dask ``LocalCluster``), a scheduler address or a ``Client``.
    progress : bool or None
        Show a progress bar on stderr (``None``: when stderr is a terminal).
    output : path, optional
        Folder for a sweep written as one netCDF part per block plus an index; the returned
        Dataset is then opened lazily from it (see :func:`xpersson.open_dataset`).
    chunk : int, optional
        Points per block (task); default about a quarter of the points per worker.
    workers : int, optional
        Worker count for ``"threads"``/``"processes"`` (default: the number of cores).
    resume : bool or None
        With ``output``: ``None`` (default) resumes when the folder holds the same study
        (only missing or damaged parts are solved), ``True`` requires that, ``False`` never
        reuses parts. A folder holding another study is refused unless ``overwrite``.
    overwrite : bool
        With ``output``: start over whatever the folder holds.
    **overrides
        ``section__key=value`` replacements, e.g. ``load__p0="1 MPa"``.

    Returns
    -------
    xarray.Dataset
        CF-annotated results; ``ds.attrs["status"]`` is ``"success"`` when every load met the
        requested tolerance (otherwise an :class:`XperssonWarning` is issued too).

    Raises
    ------
    SceneError
        Malformed scene (raised before any work, naming the parameter).
    FolderBusyError
        Another run is writing into ``output``.
    ArchiveError
        ``output`` holds another study (and ``overwrite`` is false).
    """
    sc = as_scene(scene)
    if overrides:
        sc = sc.with_values(**{k.replace("__", "."): v for k, v in overrides.items()})
    reg = registry or get_registry()
    rs = reused(sc, reg)  # a scene solved before (and found to sweep nothing)
    plan = expand(sc, reg) if rs is None else None
    if plan is not None:
        from .sweep import solve_sweep  # lazily: a solve without a sweep never needs it

        return solve_sweep(
            plan,
            reg,
            scheduler=scheduler,
            progress=progress,
            output=output,
            chunk=chunk,
            workers=workers,
            resume=resume,
            overwrite=overwrite,
        )
    rs = resolve(sc, reg) if rs is None else rs
    if progress is False or (progress is None and not sys.stderr.isatty()):
        return run(rs, model_errors=True)
    return run_with_progress(rs, progress, model_errors=True)
