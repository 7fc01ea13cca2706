"""netCDF archives: safe writes and faithful re-opening (the public face).

A write goes to a hidden temporary file beside the target, is flushed to disk and then appears
under the target name in one atomic step (see :mod:`xpersson.archive` for the details: locks,
temporaries of killed writers, the CF encoding). :func:`open_dataset` opens a file written by
:func:`to_netcdf` or a folder of netCDF parts written by a sweep.
"""

from __future__ import annotations

import os
from pathlib import Path

import xarray as xr

from .archive import read, stale_temporaries, to_netcdf
from .sweep import open_parts

__all__ = ["to_netcdf", "open_dataset", "open_parts", "stale_temporaries"]


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
    """
    if Path(path).is_dir():
        return open_parts(path)
    return read(path, **kwargs)
