"""The parts format of a sweep written to a folder: one netCDF file per block plus an index.

``part-NNNNN.nc`` holds the stacked Dataset of block ``NNNNN`` (see :mod:`.blocks`);
``xpersson_index.json`` (format ``xpersson-parts-2``) holds:

- ``state``: ``"running"`` from the moment a run starts (the index is invalidated first) until
  the run completes, then ``"complete"``;
- ``study`` (the scene's hash, see :mod:`.folder`), ``run`` (the id of the run that wrote the
  index) and ``layout`` (how the grid is cut into blocks: a resumed run cuts it the same way);
- ``dims``, ``shape``, ``coords`` (the values of every sweep coordinate);
- ``parts``: per block its number, grid index, index range, file name, the run that wrote it
  and the sha256 of the file;
- ``constant`` (the variables that do not depend on some sweep dimensions), ``scene_sha256``
  (of the scene stored in ``attrs``) and ``attrs`` (the sweep's global attributes);
- ``sha256``: of all the above (canonical JSON), verified on every read.

Every part carries the study hash, its run id and its block number in its ``xpersson_part``
attribute. :func:`open_parts` trusts nothing: the index's sizes and names are checked before
anything is allocated or opened (part names are confined to the folder), every part's bytes
against the index's sha256 and every part's identity and coordinates against the index; any
mismatch is an :class:`~xpersson.errors.ArchiveError` naming the part.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import re
import threading
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from ..archive import WriteError, decode, read, to_netcdf
from ..errors import ArchiveError
from ..pipeline import direct_dataset
from .blocks import PART_ATTR, POINT_STATUS
from .stacking import GAP, SHARED_GRIDS, document_regridded, variable, with_nan_meaning

__all__ = ["INDEX", "FORMAT", "part_name", "write_part", "read_part", "write_index", "finalize"]
__all__ += ["open_parts", "load_index", "read_index_file", "PART_NAME", "seal_index"]
__all__ += ["differing_grids"]

INDEX = "xpersson_index.json"
FORMAT = "xpersson-parts-2"
PART_NAME = re.compile(r"part-[0-9]{5,9}\.nc")
"""What a part may be called: a plain file name inside the folder."""
MAX_INDEX_BYTES = 256 * 2**20
"""Largest index read [bytes] (a crafted index cannot request more)."""


def part_name(number: int) -> str:
    """File name of the part of block ``number``."""
    return f"part-{number:05d}.nc"


def write_part(ds: xr.Dataset, path: str | os.PathLike[str]) -> None:
    """Write a block's Dataset as a part (replacing an older part of that name)."""
    to_netcdf(ds, path, overwrite=True)


def read_part(path: str | os.PathLike[str]) -> xr.Dataset:
    """One part, loaded into memory, verified (checksums) and decoded."""
    return read(path)


def write_index(folder: Path, index: dict[str, Any]) -> None:
    """Write the folder's index in one atomic step (temporary file, fsync, rename)."""
    index = {"format": FORMAT, **index}
    index.pop("sha256", None)
    if "attrs" in index:
        index["scene_sha256"] = _scene_sha(index["attrs"])
    index["sha256"] = _index_sha(index)
    tmp = folder / f".{INDEX}.{os.getpid()}.tmp"
    try:
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(json.dumps(index, indent=1))
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, folder / INDEX)
    except OSError as exc:  # disk full, quota, ...: named; no half-written index left behind
        tmp.unlink(missing_ok=True)
        raise WriteError(folder / INDEX, exc) from None
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def seal_index(index: dict[str, Any]) -> dict[str, Any]:
    """``index`` with its ``sha256`` recomputed (for tools and tests that edit an index)."""
    index = {k: v for k, v in index.items() if k != "sha256"}
    return {**index, "sha256": _index_sha(index)}


def _index_sha(index: dict[str, Any]) -> str:
    body = {k: v for k, v in index.items() if k != "sha256"}
    return hashlib.sha256(json.dumps(body, sort_keys=True).encode()).hexdigest()


def _scene_sha(attrs: dict[str, Any]) -> str:
    return hashlib.sha256(str(attrs.get("xpersson_scene", "")).encode()).hexdigest()


def read_index_file(folder: Path) -> dict[str, Any]:
    """The folder's index as JSON (size-checked), or an :class:`ArchiveError` naming it."""
    path = folder / INDEX
    try:
        size = path.stat().st_size
    except FileNotFoundError:
        raise FileNotFoundError(f"{folder} is not a sweep folder (no {INDEX})") from None
    if size > MAX_INDEX_BYTES:
        raise ArchiveError(f"{path}: {size} bytes, more than an index may hold ({MAX_INDEX_BYTES})")
    try:
        index = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        raise ArchiveError(f"{path}: not a readable sweep index ({type(exc).__name__})") from None
    if not isinstance(index, dict):
        raise ArchiveError(f"{path}: not a sweep index (a JSON object expected)")
    if index.get("format") != FORMAT:
        raise ArchiveError(
            f"{path}: format {str(index.get('format'))[:40]!r} is not {FORMAT!r} (written by "
            "another program or an older xpersson; solve the study again into a new folder)"
        )
    if index.get("sha256") != _index_sha(index):
        raise ArchiveError(f"{path}: the index fails its checksum (changed after writing)")
    return index


def _ints(value: Any, n: int | None, what: str, path: Path) -> list[int]:
    ok = isinstance(value, list) and all(type(v) is int and v >= 0 for v in value)
    if not ok or (n is not None and len(value) != n):
        raise ArchiveError(f"{path}: {what} must be a list of {n or ''} non-negative integers")
    return value


def load_index(folder: Path) -> dict[str, Any]:
    """Read and check a complete index: types, sizes and names before any allocation."""
    index = read_index_file(folder)
    path = folder / INDEX
    if index.get("state") != "complete":
        raise ArchiveError(
            f"{folder}: the sweep in this folder is incomplete (interrupted or still running); "
            "solve the same study into it again to resume it"
        )
    dims = index.get("dims")
    if not (isinstance(dims, list) and dims and all(isinstance(d, str) for d in dims)):
        raise ArchiveError(f"{path}: dims must be a non-empty list of names")
    shape = _ints(index.get("shape"), len(dims), "shape", path)
    parts = index.get("parts")
    if not isinstance(parts, list) or not parts:
        raise ArchiveError(f"{path}: parts must be a non-empty list")
    if any(s < 1 for s in shape) or math.prod(shape) < len(parts):
        raise ArchiveError(f"{path}: shape {shape} cannot hold {len(parts)} parts")
    seen: set[tuple[int, ...]] = set()
    names: dict[str, int] = {}
    for k, entry in enumerate(parts):
        _check_entry(entry, dims, shape, path)
        seen.add(tuple(entry["grid_index"]))
        first = names.setdefault(entry["name"], k)
        if first != k:
            raise ArchiveError(
                f"{path}: parts[{first}] (grid_index {parts[first]['grid_index']}) and parts[{k}] "
                f"(grid_index {entry['grid_index']}) both name {entry['name']}"
            )
    counts = [max(g[d] for g in seen) + 1 for d in range(len(dims))]
    if len(seen) != len(parts) or math.prod(counts) != len(parts):
        raise ArchiveError(f"{path}: the parts do not tile the block grid {counts} exactly once")
    if not isinstance(index.get("constant"), dict) or not isinstance(index.get("attrs"), dict):
        raise ArchiveError(f"{path}: constant and attrs must be JSON objects")
    for name, along in index["constant"].items():
        if not (isinstance(along, list) and all(d in dims for d in along)):
            raise ArchiveError(f"{path}: constant[{str(name)[:40]!r}] must list sweep dims")
    if index.get("scene_sha256") != _scene_sha(index["attrs"]):
        raise ArchiveError(f"{path}: the stored scene does not match the index (scene_sha256)")
    _check_coords(index.get("coords"), dims, shape, path)
    return index


def _check_coords(coords: Any, dims: list[str], shape: list[int], path: Path) -> None:
    if not isinstance(coords, dict):
        raise ArchiveError(f"{path}: coords must be a JSON object")
    for name, value in coords.items():
        ok = isinstance(value, list) and len(value) == 2 and value[0] in dims
        if ok:
            values = value[1]
            ok = (
                isinstance(values, list)
                and len(values) == shape[dims.index(value[0])]
                and all(type(v) in (int, float) for v in values)
            )
        if not ok:
            raise ArchiveError(f"{path}: coordinate {str(name)[:40]!r} is malformed")


def _check_entry(entry: Any, dims: list[str], shape: list[int], path: Path) -> None:
    if not isinstance(entry, dict):
        raise ArchiveError(f"{path}: each part must be a JSON object")
    name = entry.get("name")
    if not isinstance(name, str) or not PART_NAME.fullmatch(name):
        raise ArchiveError(
            f"{path}: part name {str(name)[:80]!r} is not allowed (part-NNNNN.nc inside the folder)"
        )
    n = len(dims)
    _ints(entry.get("grid_index"), n, f"{name}: grid_index", path)
    start = _ints(entry.get("start"), n, f"{name}: start", path)
    stop = _ints(entry.get("stop"), n, f"{name}: stop", path)
    if any(not (a < b <= s) for a, b, s in zip(start, stop, shape, strict=True)):
        raise ArchiveError(f"{path}: {name}: range {start}..{stop} outside the shape {shape}")
    for key in ("run", "sha256"):
        if not isinstance(entry.get(key), str):
            raise ArchiveError(f"{path}: {name}: {key} missing")


def _reduced(ds: xr.Dataset, name: str, dims: list[str]) -> xr.Variable:
    """Variable ``name`` with the sweep dimensions ``dims`` dropped (the value of any solved
    point: the largest, skipping NaN; integers of failed points skipped). For floating-point
    variables the smallest must equal it (:func:`_unchanged`): an index that calls a varying
    variable constant is refused."""
    var = ds.variables[name]
    dims = [d for d in dims if d in var.dims]
    kind = var.dtype.kind
    status = ds.variables.get("point_status")
    ints_ok = status is not None and set(status.dims) <= set(var.dims)
    if isinstance(var.data, np.ndarray) and (kind == "f" or (kind in "iub" and ints_ok)):
        axes = tuple(var.dims.index(d) for d in dims)
        keep = tuple(d for d in var.dims if d not in dims)
        if kind == "f" and all(var.data.strides[a] == 0 for a in axes):  # one row repeated
            first = tuple(0 if a in axes else slice(None) for a in range(var.ndim))
            data = low = np.array(var.data[first])  # (the reductions' values, fresh)
        elif kind == "f":  # nanmax without its all-NaN warning (no filter to change)
            data = np.fmax.reduce(var.data, axis=axes)
            low = np.fmin.reduce(var.data, axis=axes)
        else:  # the failed points' values replaced by the smallest of all (largest for low)
            ok = _broadcast_to_dims(status, var.dims) != POINT_STATUS["failed"]
            arr = np.asarray(var.data)
            data = np.where(ok, arr, arr.min()).max(axis=axes).astype(var.dtype)
            low = data  # a point lacking the variable holds a fill value: not checked
        _unchanged(data, low, name)
        return variable(keep, data, dict(var.attrs), dict(var.encoding))
    if isinstance(var.data, np.ndarray) and kind in "OUS":  # strings: the first point's
        first = tuple(0 if d in dims else slice(None) for d in var.dims)
        keep = tuple(d for d in var.dims if d not in dims)
        return variable(keep, np.asarray(var.data[first], dtype=var.dtype), dict(var.attrs))
    da = ds[name]
    if var.dtype.kind in "fc":  # NaN skipped; NaN where every point is NaN; no warning
        some = da.notnull().any(dims)
        reduced = da.fillna(-np.inf).max(dims, keep_attrs=True).where(some)
        low = da.fillna(np.inf).min(dims).where(some)
    elif var.dtype.kind in "iub":
        ok = ds["point_status"] != POINT_STATUS["failed"]
        reduced = low = da.where(ok, da.min()).max(dims, keep_attrs=True).astype(var.dtype)
    else:
        reduced = low = da.isel({d: 0 for d in dims}, drop=True)
    reduced = xr.apply_ufunc(
        _unchanged,
        reduced,
        low,
        kwargs={"name": name},
        dask="parallelized",
        output_dtypes=[reduced.dtype],
        keep_attrs=True,
    )
    out = reduced.variable.copy(deep=False)
    out.attrs = dict(var.attrs)
    return out


def _broadcast_to_dims(var: xr.Variable, dims: tuple[Any, ...]) -> np.ndarray:
    """The values of ``var`` (whose dims are among ``dims``) laid along ``dims``, length 1 on
    the others (numpy's broadcasting; no xarray arithmetic, whose Variables probe dask)."""
    order = [var.dims.index(d) for d in dims if d in var.dims]
    arr = np.transpose(np.asarray(var.values), order)
    return arr.reshape([var.sizes[d] if d in var.dims else 1 for d in dims])


def _unchanged(high: Any, low: Any, name: str) -> Any:
    """``high`` when it equals ``low`` wherever it is a number, else an :class:`ArchiveError`."""
    high_a, low_a = np.asarray(high), np.asarray(low)
    same = high_a == low_a
    if high_a.dtype.kind in "fc":
        same |= np.isnan(high_a)
    if not np.all(same):
        raise ArchiveError(
            f"variable {name!r} varies along a sweep dimension its index lists under "
            "'constant' (the index was altered; the parts disagree with it)"
        )
    return high


def finalize(ds: xr.Dataset, constant: dict[str, list[str]], attrs: dict[str, Any]) -> xr.Dataset:
    """Drop the sweep dimensions along which a variable never changes; set the sweep's attrs.

    The kept value is the one of any solved point (failed points hold NaN and are skipped).
    The Dataset is built once from its variables (in their order), not merged per variable.
    """
    reduced = {n: _reduced(ds, n, dims) for n, dims in constant.items() if n in ds.variables}
    coords = set(ds.coords)
    variables = {n: reduced.get(n, v) for n, v in ds.variables.items()}
    data = {n: v for n, v in variables.items() if n not in coords}
    out = direct_dataset(data, {n: v for n, v in variables.items() if n in coords}, attrs)
    if out is None:  # pragma: no cover - other xarray versions
        out = xr.Dataset(data, coords={n: v for n, v in variables.items() if n in coords})
        out.attrs = dict(attrs)
        if list(out.variables) != list(variables):  # keep the order of the combined Dataset
            out = out[list(data)]
    out.encoding = dict(ds.encoding)
    _document_failed(out)
    return out


def _document_failed(ds: xr.Dataset) -> None:
    """Where a point failed, the NaN it holds documented on every float variable that keeps a
    sweep dimension (in place; once)."""
    status = ds.variables.get("point_status")
    if status is None or not np.any(np.asarray(status.values) == POINT_STATUS["failed"]):
        return
    sweep = set(status.dims)
    for var in ds.data_vars.values():
        if var.dtype.kind in "fc" and sweep & set(var.dims):
            var.attrs["comment"] = with_nan_meaning(var.attrs.get("comment", ""), GAP)


def open_parts(folder: str | os.PathLike[str]) -> xr.Dataset:
    """Open the netCDF parts of a sweep folder lazily as one Dataset (needs dask).

    The folder's index (``xpersson_index.json``) names the parts, their place on the sweep
    grid, the variables that do not depend on some sweep dimensions and the global attributes.
    Every part is verified first (see the module's docstring). The folder opened is the folder
    read: each part's bytes are read once, checked against the index's sha256 and parsed from
    memory; up to :data:`SNAPSHOT_BYTES` of parts are kept in memory, the others are read again
    when their values are loaded and checked against the same sha256, so a folder changed
    after opening is an :class:`~xpersson.errors.ArchiveError` naming the part, never another
    study's values.

    Raises
    ------
    ArchiveError
        The index is malformed or incomplete, or a part is missing, damaged or does not belong
        to the index; the message names the part.
    """
    folder = Path(folder)
    index = load_index(folder)
    entries = {e["name"]: e for e in index["parts"]}
    dims = index["dims"]
    counts = [max(e["grid_index"][d] for e in entries.values()) + 1 for d in range(len(dims))]
    nested = np.empty(counts, dtype=object)
    kept = 0
    for name, entry in entries.items():
        path = folder / name
        ds = _check_part(_open_verified(path, entry["sha256"]), path, entry, index)
        size = sum(v.nbytes for v in ds.variables.values())
        kept += size
        nested[tuple(entry["grid_index"])] = _snapshot(ds, path, entry["sha256"], kept)
    regridded = differing_grids([d for d in nested.ravel() if d is not None], dims)
    try:
        ds = xr.combine_nested(
            nested.tolist(),
            concat_dim=dims,
            data_vars="minimal",
            coords="minimal",
            join="outer",
            compat="override",
            combine_attrs="override",
        )
    except Exception as exc:  # noqa: BLE001 - verified bytes that still do not combine
        raise ArchiveError(f"{folder}: the parts do not combine ({type(exc).__name__})") from None
    out = finalize(decode(ds), index["constant"], index["attrs"])
    document_regridded(out, regridded)  # (xarray's outer join put them on the union)
    return out


def differing_grids(parts: list[xr.Dataset], sweep: list[str]) -> set[str]:
    """The index dimensions (not the sweep's, nor the shared grids) on which parts differ."""
    out = set()
    for dim in {d for ds in parts for d in ds.indexes} - set(sweep) - set(SHARED_GRIDS):
        grids = [ds.indexes[dim].values for ds in parts if dim in ds.indexes]
        if any(len(g) != len(grids[0]) or not np.array_equal(g, grids[0]) for g in grids):
            out.add(dim)
    return out


SNAPSHOT_BYTES = 64 * 2**20
"""Bytes of parts an opened sweep folder keeps in memory [bytes]; the others are re-read (and
re-verified) when loaded."""


def _open_verified(path: Path, sha256: str) -> xr.Dataset:
    """Part ``path`` read once, checked against ``sha256`` and parsed from those bytes."""
    if not path.is_file():
        raise ArchiveError(f"{path}: part missing (the index lists it)")
    try:
        return _parse_verified(str(path), sha256)
    except _Changed:
        read(path)  # names the damaged variable when it can
        raise ArchiveError(
            f"{path}: part differs from the checksum its index holds (damaged)"
        ) from None


_PARSE_LOCK = threading.Lock()


class _Changed(ArchiveError):
    """A part's bytes are not those its index names."""


def _parse_verified(path: str, sha256: str) -> xr.Dataset:
    import netCDF4

    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as exc:
        raise ArchiveError(f"{path}: part cannot be read ({exc.strerror or exc})") from None
    if hashlib.sha256(data).hexdigest() != sha256:
        raise _Changed(f"{path}: bytes differ from the index's sha256")
    from xarray.backends.locks import HDF5_LOCK, NETCDFC_LOCK, combine_locks

    lock = combine_locks([HDF5_LOCK, NETCDFC_LOCK])  # the libraries are not thread-safe
    try:
        with _PARSE_LOCK:  # xarray reads attributes unlocked: one part parsed at a time
            with lock:
                nc = netCDF4.Dataset(Path(path).name, mode="r", memory=data)
            with xr.open_dataset(xr.backends.NetCDF4DataStore(nc, lock=lock)) as ds:
                out = ds.load()
    except Exception as exc:  # noqa: BLE001 - netCDF/HDF5 errors come as many classes
        raise ArchiveError(f"{path}: not a readable netCDF part ({type(exc).__name__})") from None
    out.encoding["source"] = path
    return out


def _part_arrays(path: str, sha256: str) -> dict[str, np.ndarray]:
    """The values of every variable of a part whose values were not kept at opening."""
    try:
        ds = _parse_verified(path, sha256)
    except _Changed:
        raise ArchiveError(
            f"{path}: part changed after the sweep folder was opened (its bytes differ from "
            "the checksum the index held then); open the folder again"
        ) from None
    return {str(n): np.asarray(v.values) for n, v in ds.variables.items()}


def _snapshot(ds: xr.Dataset, path: Path, sha256: str, kept: int) -> xr.Dataset:
    """``ds`` with dask-backed variables: its own values (up to :data:`SNAPSHOT_BYTES` kept in
    all) or values read again, verified, when loaded."""
    import dask
    import dask.array as da

    lazy = kept > SNAPSHOT_BYTES
    loader = dask.delayed(_part_arrays, pure=True)(str(path), sha256) if lazy else None
    out = ds.copy(deep=False)
    for name, var in ds.variables.items():
        if name in ds.dims:  # an index: its values are the snapshot's
            continue
        key = f"xpersson-part-{sha256[:24]}-{name}"
        if loader is None:
            data = da.from_array(var.values, chunks=var.shape or (), name=key)
        else:
            data = da.from_delayed(loader[str(name)], var.shape, dtype=var.dtype, name=key)
        out.variables[name].data = data
    return out


def _check_part(ds: xr.Dataset, path: Path, entry: dict[str, Any], index: dict[str, Any]) -> Any:
    try:
        info = json.loads(ds.attrs.get(PART_ATTR, "{}"))
    except ValueError:
        info = {}
    for key, want in (
        ("study", index.get("study")),
        ("run", entry["run"]),
        ("grid_index", entry["grid_index"]),
    ):
        if info.get(key) != want:
            raise ArchiveError(f"{path}: part does not belong to this index ({key} differs)")
    coords = index.get("coords") or {}
    for name, (dim, values) in coords.items():
        d = index["dims"].index(dim)
        want = np.asarray(values)[entry["start"][d] : entry["stop"][d]]
        if name not in ds.variables or not np.array_equal(ds[name].values, want):
            raise ArchiveError(f"{path}: coordinate {name!r} differs from the index")
    return ds
