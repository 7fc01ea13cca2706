"""netCDF archives: atomic writes and faithful re-opening."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import xarray as xr

__all__ = ["to_netcdf", "open_dataset", "open_parts"]

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
        from ._cf import encode

        stored, encoding = encode(ds)
        stored.to_netcdf(tmp, engine=ENGINE, format="NETCDF4", encoding=encoding)
        os.replace(tmp, target)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return target


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
    from ._cf import decode

    with xr.open_dataset(path, engine=ENGINE, **kwargs) as ds:  # type: ignore[arg-type]
        return decode(ds.load())


def open_parts(folder: str | os.PathLike[str]) -> xr.Dataset:
    """Open the netCDF parts of a sweep folder lazily as one Dataset (needs dask).

    The folder's index (``xpersson_index.json``) names the parts, their place on the sweep
    grid, the variables that do not depend on some sweep dimensions and the global attributes.
    """
    import json

    from ._sweeprun import INDEX, finalize

    folder = Path(folder)
    index_file = folder / INDEX
    if not index_file.is_file():
        raise FileNotFoundError(f"{folder} is not a sweep folder (no {INDEX})")
    index = json.loads(index_file.read_text(encoding="utf-8"))
    dims = index["dims"]
    counts = [max(g[d] for g, _ in index["parts"]) + 1 for d in range(len(dims))]
    import numpy as np

    nested = np.empty(counts, dtype=object)
    for grid_index, name in index["parts"]:
        nested[tuple(grid_index)] = str(folder / name)
    ds = xr.open_mfdataset(
        nested.tolist(), combine="nested", concat_dim=dims, engine=ENGINE, chunks={},
        data_vars="minimal", coords="minimal", join="outer", compat="override",
        combine_attrs="override",
    )
    from ._cf import decode

    return finalize(decode(ds), index["constant"], index["attrs"])
