"""netCDF archives: safe writes and faithful re-opening (the public face).

A write goes to a hidden temporary file beside the target, is flushed to disk and then appears
under the target name in one atomic step (see :mod:`xpersson.archive` for the details: locks,
temporaries of killed writers, the CF encoding). :func:`open_dataset` opens a file written by
:func:`to_netcdf` or a folder of netCDF parts written by a sweep.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import xarray as xr

from .archive import read, stale_temporaries, to_netcdf
from .errors import ArchiveError

if TYPE_CHECKING:
    from .sweep import open_parts

__all__ = ["to_netcdf", "open_dataset", "open_parts", "stale_temporaries", "compare"]


def __getattr__(name: str) -> Any:
    if name == "open_parts":  # re-exported, imported on first access
        from .sweep import open_parts

        return open_parts
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def open_dataset(path: str | os.PathLike[str], **kwargs: object) -> xr.Dataset:
    """Open an xpersson archive (loaded into memory, file closed), or a sweep folder (lazily).

    Parameters
    ----------
    path : path-like
        A file written by :func:`to_netcdf` (or ``xpersson run``), or a folder of netCDF parts
        written by a sweep (``xpersson run -o DIR/``, ``xpersson.solve(..., output=DIR)``):
        opened lazily (dask) as one Dataset by :func:`open_parts`.
    **kwargs
        Passed to :func:`xarray.open_dataset` (files only).

    Raises
    ------
    FileNotFoundError
        No such file or folder.
    ArchiveError
        The file is corrupt, truncated, not an xpersson archive, fails a checksum or carries
        malformed attributes; a sweep folder is incomplete or a part does not belong to it.
        The message names the file (and the variable or part).
    """
    p = Path(path)
    if p.is_dir():
        from .sweep import open_parts  # lazily: a file needs no sweep code

        ds = open_parts(p)
    elif not p.exists():
        raise FileNotFoundError(f"{p}: no such file")
    else:
        ds = read(p, **kwargs)
    check_attributes(ds, p)
    return ds


_JSON_ATTRS = {
    "xpersson_scene": dict,
    "xpersson_plugins": list,
    "xpersson_solver": dict,
    "xpersson_point_messages": list,
    "xpersson_sweep": dict,
}


def check_attributes(
    ds: xr.Dataset, path: str | os.PathLike[str], *, require: bool = False
) -> None:
    """Refuse a Dataset whose xpersson attributes are malformed, or (``require``) that is not an
    xpersson result at all (:class:`ArchiveError` naming ``path`` and the attribute)."""
    if require and "xpersson_scene" not in ds.attrs:
        raise ArchiveError(f"{path}: not an xpersson archive (no xpersson_scene attribute)")
    for name, kind in _JSON_ATTRS.items():
        if name not in ds.attrs:
            continue
        try:
            value = json.loads(str(ds.attrs[name]))
        except ValueError:
            value = None
        if not isinstance(value, kind):
            raise ArchiveError(f"{path}: attribute {name} is malformed (JSON {kind.__name__})")
        if name == "xpersson_plugins" and not all(
            isinstance(x, dict) and {"group", "name"} <= set(x) for x in value
        ):
            raise ArchiveError(f"{path}: attribute {name} is malformed (plugin records)")
    for name in ("status", "status_message"):
        if not isinstance(ds.attrs.get(name, ""), str):
            raise ArchiveError(f"{path}: attribute {name} is malformed (text expected)")


def compare(
    old: xr.Dataset, new: xr.Dataset, *, rtol: float = 1e-9, atol: float = 0.0
) -> tuple[int, list[str]]:
    """Compare two results: coordinates exactly, then every variable within a tolerance.

    Coordinates are compared first, exactly (names, dimensions, values; NaN equals NaN); if
    any differs, the variables are not compared (nothing is aligned or reindexed). Then every
    variable: the same names, dimensions and shape, numbers within
    ``|new - old| <= atol + rtol |old|`` (NaN only where the other is NaN), anything else equal.

    Returns
    -------
    (int, list of str)
        The number of variables compared (coordinates included) and one line per difference;
        an empty comparison is itself reported as a difference.
    """
    diffs: list[str] = []
    for name in sorted(set(old.coords) ^ set(new.coords), key=str):
        diffs.append(f"coordinate {name}: only in the {'old' if name in old.coords else 'new'}")
    n = 0
    for name in sorted(set(old.coords) & set(new.coords), key=str):
        n += 1
        a, b = old[name], new[name]
        if a.dims != b.dims or a.shape != b.shape or not _equal(a.values, b.values):
            diffs.append(f"coordinate {name}: differs (compared exactly)")
    if diffs:
        return n, diffs
    for name in sorted(set(old.data_vars) ^ set(new.data_vars), key=str):
        diffs.append(f"variable {name}: only in the {'old' if name in old.data_vars else 'new'}")
    for name in sorted(set(old.data_vars) & set(new.data_vars), key=str):
        n += 1
        line = _differs(str(name), old[name], new[name], rtol, atol)
        if line:
            diffs.append(line)
    if n == 0:
        diffs.append("nothing to compare: no coordinate or variable in common")
    return n, diffs


def _equal(a: np.ndarray, b: np.ndarray) -> bool:
    a, b = np.asarray(a), np.asarray(b)
    nan = a.dtype.kind in "fc" and b.dtype.kind in "fc"
    return a.shape == b.shape and bool(np.array_equal(a, b, equal_nan=nan))


def _differs(name: str, a: xr.DataArray, b: xr.DataArray, rtol: float, atol: float) -> str:
    if a.dims != b.dims or a.shape != b.shape:
        return f"variable {name}: dimensions {dict(a.sizes)} vs {dict(b.sizes)}"
    x, y = np.asarray(a.values), np.asarray(b.values)
    if x.dtype.kind not in "fc" or y.dtype.kind not in "fc":
        return "" if _equal(x, y) else f"variable {name}: values differ"
    with np.errstate(invalid="ignore"):
        bad = ~(np.abs(y - x) <= atol + rtol * np.abs(x))
    bad &= ~(np.isnan(x) & np.isnan(y))
    if not bad.any():
        return ""
    k = np.unravel_index(int(np.argmax(bad)), bad.shape)
    where = ", ".join(f"{d}={i}" for d, i in zip(a.dims, k, strict=True))
    return (
        f"variable {name}: {int(bad.sum())} of {bad.size} values beyond rtol={rtol:g} "
        f"atol={atol:g}; first at {where or 'the scalar'}: {x[k]!r} -> {y[k]!r}"
    )
