"""The parts format of a sweep written to a folder: one netCDF file per block plus an index.

``part-NNNNN.nc`` holds the stacked Dataset of block ``NNNNN`` (see :mod:`.blocks`);
``xpersson_index.json`` names the parts, their place on the block grid, the variables that do
not depend on some sweep dimensions and the global attributes of the sweep. :func:`open_parts`
opens the folder lazily as the Dataset an in-memory sweep returns (:func:`finalize` is the
last step of both).
"""

from __future__ import annotations

import json
import os
import warnings
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from ..archive import ENGINE, decode, read, to_netcdf
from .blocks import POINT_STATUS

__all__ = ["INDEX", "FORMAT", "part_name", "write_part", "read_part", "write_index", "finalize"]
__all__ += ["open_parts"]

INDEX = "xpersson_index.json"
FORMAT = "xpersson-parts-1"


def part_name(number: int) -> str:
    """File name of the part of block ``number``."""
    return f"part-{number:05d}.nc"


def write_part(ds: xr.Dataset, path: str | os.PathLike[str]) -> None:
    """Write a block's Dataset as a part (replacing an older part of that name)."""
    to_netcdf(ds, path, overwrite=True)


def read_part(path: str | os.PathLike[str]) -> xr.Dataset:
    """One part, loaded into memory and decoded."""
    return read(path)


def write_index(
    folder: Path,
    dims: tuple[str, ...],
    shape: tuple[int, ...],
    parts: list[tuple[tuple[int, ...], str]],
    constant: dict[str, list[str]],
    attrs: dict[str, Any],
) -> None:
    """Write the folder's index in one atomic step.

    ``parts`` lists (block grid index, part path) pairs; ``constant`` maps a variable to the
    sweep dimensions along which it never changes; ``attrs`` are the sweep's global attributes.
    """
    index = {
        "format": FORMAT,
        "dims": list(dims),
        "shape": list(shape),
        "parts": [[list(grid_index), Path(part).name] for grid_index, part in parts],
        "constant": constant,
        "attrs": attrs,
    }
    tmp = folder / f".{INDEX}.tmp"
    tmp.write_text(json.dumps(index, indent=1), encoding="utf-8")
    os.replace(tmp, folder / INDEX)


def finalize(ds: xr.Dataset, constant: dict[str, list[str]], attrs: dict[str, Any]) -> xr.Dataset:
    """Drop the sweep dimensions along which a variable never changes; set the sweep's attrs.

    The kept value is the one of any solved point (failed points hold NaN and are skipped).
    """
    for name, dims in constant.items():
        if name not in ds.variables:
            continue
        var = ds[name]
        dims = [d for d in dims if d in var.dims]
        if var.dtype.kind in "fc":
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)
                reduced = var.max(dims, skipna=True, keep_attrs=True)
        elif var.dtype.kind in "iub":
            ok = ds["point_status"] != POINT_STATUS["failed"]
            reduced = var.where(ok, var.min()).max(dims, keep_attrs=True).astype(var.dtype)
        else:
            reduced = var.isel({d: 0 for d in dims}, drop=True)
        reduced.attrs = dict(var.attrs)
        if name in ds.coords:
            ds = ds.assign_coords({name: reduced})
        else:
            ds[name] = reduced
    ds.attrs = dict(attrs)
    return ds


def open_parts(folder: str | os.PathLike[str]) -> xr.Dataset:
    """Open the netCDF parts of a sweep folder lazily as one Dataset (needs dask).

    The folder's index (``xpersson_index.json``) names the parts, their place on the sweep
    grid, the variables that do not depend on some sweep dimensions and the global attributes.
    """
    folder = Path(folder)
    index_file = folder / INDEX
    if not index_file.is_file():
        raise FileNotFoundError(f"{folder} is not a sweep folder (no {INDEX})")
    index = json.loads(index_file.read_text(encoding="utf-8"))
    dims = index["dims"]
    counts = [max(g[d] for g, _ in index["parts"]) + 1 for d in range(len(dims))]
    nested = np.empty(counts, dtype=object)
    for grid_index, name in index["parts"]:
        nested[tuple(grid_index)] = str(folder / name)
    ds = xr.open_mfdataset(
        nested.tolist(),
        combine="nested",
        concat_dim=dims,
        engine=ENGINE,
        chunks={},
        data_vars="minimal",
        coords="minimal",
        join="outer",
        compat="override",
        combine_attrs="override",
    )
    return finalize(decode(ds), index["constant"], index["attrs"])
