"""netCDF archives: atomic writes and faithful re-opening."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import xarray as xr

__all__ = ["to_netcdf", "open_dataset"]

ENGINE = "netcdf4"


def to_netcdf(ds: xr.Dataset, path: str | os.PathLike[str], *, overwrite: bool = False) -> Path:
    """Write ``ds`` to ``path`` atomically (temporary file in the same folder, then rename).

    Parameters
    ----------
    ds : xarray.Dataset
        A Dataset returned by :func:`xpersson.solve`.
    path : path-like
        Target ``.nc`` file.
    overwrite : bool
        Replace an existing file; without it an existing file is an error.

    Returns
    -------
    pathlib.Path
        The written file.

    Raises
    ------
    FileExistsError
        ``path`` exists and ``overwrite`` is false. Nothing is written.
    """
    target = Path(path)
    if target.exists() and not overwrite:
        raise FileExistsError(f"{target} exists; pass overwrite=True (CLI: --overwrite)")
    folder = target.parent if str(target.parent) else Path(".")
    if not folder.is_dir():
        raise FileNotFoundError(f"output folder {folder} does not exist")
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".part", dir=folder)
    os.close(fd)
    try:
        ds.to_netcdf(tmp, engine=ENGINE, format="NETCDF4")
        os.replace(tmp, target)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return target


def open_dataset(path: str | os.PathLike[str], **kwargs: object) -> xr.Dataset:
    """Open an xpersson archive (loaded into memory, file closed).

    Parameters
    ----------
    path : path-like
        A file written by :func:`to_netcdf` (or ``xpersson run``).
    **kwargs
        Passed to :func:`xarray.open_dataset`.
    """
    with xr.open_dataset(path, engine=ENGINE, **kwargs) as ds:  # type: ignore[arg-type]
        return ds.load()
