"""netCDF archives, low level: safe writes, faithful re-opening, CF encoding.

A write goes to a hidden temporary file beside the target, is flushed to disk (``fsync``) and
then appears under the target name in one atomic step: ``os.replace`` when overwriting, a hard
link (which fails if the name exists) otherwise, so of several writers racing for one new path
exactly one succeeds and a reader never sees a partial archive. The temporary file is created
with mode ``0666`` minus the umask (as ``open`` would) and is named after its writer
(``.<name>.<host>.<pid>.<random>.part``). Temporaries left by killed writers -- their process
gone (same host) or older than an hour (other hosts), and not locked -- are removed by the next
write to the same target; on Linux the writer also holds an open-file-description lock on its
temporary, which dies with the process, so a reused pid never exposes a live writer's file.

CF encoding: what is written differs from the in-memory Dataset only where CF-1.11 requires
it, and :func:`decode` undoes it, so an archive re-opens identical.

- Coordinate variables carry no ``_FillValue`` (CF §2.5.1).
- String status variables (``solver_status``) are stored as ``int8`` flags with numeric
  ``flag_values`` and ``flag_meanings`` (CF §3.5); decoded back to strings on reading.
- ``flag_values`` are stored with the variable's own type.
- Integrity: every variable with a dimension is stored with HDF5's ``fletcher32`` checksum,
  and every variable carries ``xpersson_sha256`` (a digest of its stored values and attributes);
  the global ``xpersson_attrs_sha256`` covers the global attributes and the variable names.
  :func:`read` verifies them: a mismatch is an :class:`~xpersson.errors.ArchiveError` naming
  the file and the variable. Archives written before digests existed are read unchecked.
- The pressure PDF ``P`` is stored as ``pressure_pdf``: CF forbids variable names that differ
  only by case, and ``p`` is the pressure coordinate. The stored variable says so in its
  ``xpersson_name`` attribute; :func:`decode` restores ``P``.
"""

from __future__ import annotations

import contextlib
import errno
import hashlib
import json
import os
import secrets
import socket
import time
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from .errors import ArchiveError

__all__ = [
    "ENGINE",
    "to_netcdf",
    "read",
    "encode",
    "decode",
    "RENAMED",
    "stale_temporaries",
    "remove_stale_temporaries",
    "seal",
    "verify",
    "DIGEST",
    "file_digest",
]

ENGINE = "netcdf4"
_SUFFIX = ".part"
_STALE_AFTER_S = 3600.0
"""Age after which an unlocked temporary of another host counts as stale [s]."""

try:  # Linux open-file-description locks (independent of the flock HDF5 takes)
    import fcntl
    import struct

    _OFD = (fcntl.F_OFD_SETLK, struct.Struct("hhqqi4x"))
except (ImportError, AttributeError):  # pragma: no cover - other platforms: pid/age rules only
    _OFD = None


def to_netcdf(ds: xr.Dataset, path: str | os.PathLike[str], *, overwrite: bool = False) -> Path:
    """Write ``ds`` to ``path`` safely (temporary file, fsync, atomic rename or link).

    Parameters
    ----------
    ds : xarray.Dataset
        A Dataset returned by :func:`xpersson.solve`.
    path : path-like
        Target ``.nc`` file.
    overwrite : bool
        Replace an existing file; without it an existing file is an error, also when another
        writer creates it while this one is writing (exclusive creation).

    Returns
    -------
    pathlib.Path
        The written file.

    Raises
    ------
    FileExistsError
        ``path`` exists and ``overwrite`` is false. Nothing is written.
    FileNotFoundError
        The output folder does not exist.
    """
    target = Path(path)
    if target.exists() and not overwrite:
        raise FileExistsError(f"{target} exists; pass overwrite=True (CLI: --overwrite)")
    folder = target.parent if str(target.parent) else Path(".")
    if not folder.is_dir():
        raise FileNotFoundError(f"output folder {folder} does not exist")
    remove_stale_temporaries(target)
    tmp, fd = _create_temporary(target)
    try:
        stored, encoding = encode(ds)
        stored = seal(stored, encoding)
        try:
            stored.to_netcdf(tmp, engine=ENGINE, format="NETCDF4", encoding=encoding)
        except PermissionError:  # a file system emulating flock with our lock (NFS): unlock
            if not _lock(fd, unlock=True):
                raise
            stored.to_netcdf(tmp, engine=ENGINE, format="NETCDF4", encoding=encoding)
        os.fsync(fd)  # same inode: flushes what the netCDF library wrote
        if overwrite:
            os.replace(tmp, target)
        else:
            _link_exclusive(tmp, target)
            tmp.unlink()
        _fsync_folder(folder)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    finally:
        os.close(fd)  # releases the lock
    return target


def _create_temporary(target: Path) -> tuple[Path, int]:
    """Create and lock ``.<name>.<host>.<pid>.<random>.part`` with mode 0666 & ~umask."""
    host = socket.gethostname().replace(".", "_") or "host"
    for _ in range(100):
        name = f".{target.name}.{host}.{os.getpid()}.{secrets.token_hex(4)}{_SUFFIX}"
        tmp = target.with_name(name)
        try:
            fd = os.open(tmp, os.O_RDWR | os.O_CREAT | os.O_EXCL, 0o666)
        except FileExistsError:  # pragma: no cover - 32 random bits collided
            continue
        with contextlib.suppress(BlockingIOError):  # a cleaner testing it this very moment
            _lock(fd)
        return tmp, fd
    raise FileExistsError(f"cannot create a temporary file beside {target}")  # pragma: no cover


def _lock(fd: int, *, unlock: bool = False, test: bool = False) -> bool:
    """Set (or release, or test-set) a write lock on the whole file; ``False`` if unsupported."""
    if _OFD is None:  # pragma: no cover
        return False
    cmd, layout = _OFD
    kind = fcntl.F_UNLCK if unlock else (fcntl.F_RDLCK if test else fcntl.F_WRLCK)
    try:
        fcntl.fcntl(fd, cmd, layout.pack(kind, os.SEEK_SET, 0, 0, 0))
    except OSError as exc:
        if exc.errno in (errno.EACCES, errno.EAGAIN):
            raise BlockingIOError(exc.errno, "locked") from None
        return False
    return True


def _link_exclusive(tmp: Path, target: Path) -> None:
    try:
        os.link(tmp, target)
    except FileExistsError:
        raise FileExistsError(
            f"{target} was created by another writer meanwhile; pass overwrite=True "
            "(CLI: --overwrite) to replace it"
        ) from None
    except OSError as exc:  # no hard links here (some network / FAT file systems)
        if exc.errno not in (errno.EPERM, errno.ENOTSUP, errno.EOPNOTSUPP, errno.EXDEV):
            raise
        fd = os.open(target, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)  # claims the name
        os.close(fd)
        os.replace(tmp, target)


def _fsync_folder(folder: Path) -> None:
    with contextlib.suppress(OSError):  # not every platform can open a directory
        fd = os.open(folder, os.O_RDONLY)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)


def stale_temporaries(target: str | os.PathLike[str]) -> list[Path]:
    """Temporary files of killed writers of ``target`` (safe to delete).

    A temporary is stale when no process holds its lock and either its writer (same host)
    no longer runs or it is older than an hour. Temporaries of live writers are never listed.
    """
    target = Path(target)
    folder = target.parent if str(target.parent) else Path(".")
    host = socket.gethostname().replace(".", "_") or "host"
    out = []
    for tmp in folder.glob(f".{_glob_escape(target.name)}.*{_SUFFIX}"):
        parts = tmp.name[len(target.name) + 2 : -len(_SUFFIX)].split(".")
        if len(parts) != 3:
            continue
        t_host, t_pid, _ = parts
        try:
            age = time.time() - tmp.stat().st_mtime
        except FileNotFoundError:
            continue
        if t_host == host and t_pid.isdigit():
            gone = not _alive(int(t_pid)) or age > _STALE_AFTER_S
        else:
            gone = age > _STALE_AFTER_S
        if gone and not _locked(tmp):
            out.append(tmp)
    return out


def remove_stale_temporaries(target: str | os.PathLike[str]) -> int:
    """Delete :func:`stale_temporaries` of ``target``; returns how many were removed."""
    n = 0
    for tmp in stale_temporaries(target):
        with contextlib.suppress(FileNotFoundError):
            tmp.unlink()
            n += 1
    return n


def _glob_escape(name: str) -> str:
    return "".join(f"[{c}]" if c in "*?[]" else c for c in name)


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # exists, owned by someone else
        return True
    return True


def _locked(tmp: Path) -> bool:
    """Whether a live writer holds the temporary's lock (``True`` when unsure)."""
    try:
        fd = os.open(tmp, os.O_RDONLY)
    except OSError:
        return True
    try:
        _lock(fd, test=True)
    except BlockingIOError:
        return True
    finally:
        os.close(fd)
    return False


def read(path: str | os.PathLike[str], **kwargs: object) -> xr.Dataset:
    """Open one archive file, load it into memory (the file is closed), verify and decode it.

    ``kwargs`` are passed to :func:`xarray.open_dataset`.

    Raises
    ------
    ArchiveError
        The file is not a readable netCDF file, a variable fails its checksum, or its
        attributes are malformed; the message names the file (and the variable).
    """
    try:
        handle = xr.open_dataset(path, engine=ENGINE, **kwargs)  # type: ignore[arg-type]
    except Exception as exc:  # noqa: BLE001 - netCDF/HDF5 errors come as many classes
        raise ArchiveError(f"{path}: not a readable netCDF archive ({_short(exc)})") from None
    with handle as ds:
        for name in list(ds.variables):
            try:
                ds[name].load()
            except Exception as exc:  # noqa: BLE001 - HDF errors come as several classes
                raise ArchiveError(
                    f"{path}: variable {name!r} cannot be read, the file is corrupt ({_short(exc)})"
                ) from None
        verify(ds, path)
        try:
            return decode(ds.load())
        except Exception as exc:  # noqa: BLE001 - any malformed attribute
            raise ArchiveError(f"{path}: malformed encoding attributes ({_short(exc)})") from None


def _short(exc: BaseException) -> str:
    text = f"{type(exc).__name__}: {exc}".splitlines()[0] if str(exc) else type(exc).__name__
    return text if len(text) <= 160 else text[:157] + "..."


# -- content integrity ----------------------------------------------------------------------------
DIGEST = "xpersson_sha256"
_ATTRS_DIGEST = "xpersson_attrs_sha256"
_NOT_HASHED = {DIGEST, "_FillValue", "coordinates", "dtype", "missing_value"}


def _canonical(value: Any) -> Any:
    if isinstance(value, str | bytes):
        return str(value)
    return [repr(x) for x in np.atleast_1d(np.asarray(value)).ravel().tolist()]


def _attrs_bytes(attrs: Any) -> bytes:
    items = {str(k): _canonical(v) for k, v in attrs.items() if k not in _NOT_HASHED}
    return json.dumps(items, sort_keys=True).encode()


def _variable_digest(var: xr.Variable) -> str:
    arr = np.asarray(var.values)
    h = hashlib.sha256(repr((var.dims, arr.shape)).encode())
    if arr.dtype.kind in "OUS":
        h.update(json.dumps([str(x) for x in arr.ravel().tolist()]).encode())
    elif arr.dtype.kind == "b":
        h.update(arr.astype(np.uint8).tobytes())
    else:
        h.update(np.ascontiguousarray(arr).tobytes())
    h.update(_attrs_bytes(var.attrs))
    return h.hexdigest()


def _global_digest(ds: xr.Dataset) -> str:
    h = hashlib.sha256(json.dumps(sorted(map(str, ds.variables))).encode())
    h.update(_attrs_bytes({k: v for k, v in ds.attrs.items() if k != _ATTRS_DIGEST}))
    return h.hexdigest()


def file_digest(path: str | os.PathLike[str]) -> str:
    """sha256 of a file's bytes (hex)."""
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for chunk in iter(lambda: f.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def seal(stored: xr.Dataset, encoding: dict[str, dict[str, Any]]) -> xr.Dataset:
    """Add the digests and the ``fletcher32`` checksums to an encoded Dataset (in place for
    ``encoding``; returns a shallow copy of ``stored``)."""
    out = stored.copy(deep=False)
    for name in list(out.variables):
        var = out.variables[name]
        var.attrs.pop(DIGEST, None)
        var.attrs[DIGEST] = _variable_digest(var)
        if var.ndim:
            encoding.setdefault(str(name), {})["fletcher32"] = True
    out.attrs.pop(_ATTRS_DIGEST, None)
    out.attrs[_ATTRS_DIGEST] = _global_digest(out)
    return out


def verify(ds: xr.Dataset, path: str | os.PathLike[str]) -> None:
    """Check the digests :func:`seal` stored (loads every variable).

    Raises
    ------
    ArchiveError
        Naming ``path`` and the first variable (or the global attributes) that changed.
    """
    for name, var in ds.variables.items():
        stored = var.attrs.get(DIGEST)
        if stored is not None and stored != _variable_digest(var):
            raise ArchiveError(
                f"{path}: variable {name!r} fails its checksum: its stored values or "
                "attributes changed after writing (the file is corrupt)"
            )
    stored = ds.attrs.get(_ATTRS_DIGEST)
    if stored is not None and stored != _global_digest(ds):
        raise ArchiveError(
            f"{path}: the global attributes fail their checksum (the file is corrupt)"
        )


# -- CF encoding ----------------------------------------------------------------------------------
RENAMED = {"P": "pressure_pdf"}
_ENCODED = "xpersson_encoding"


def _flag_codes(var: xr.DataArray) -> tuple[list[str], np.ndarray]:
    meanings = str(var.attrs.get("flag_meanings", "")).split()
    values = np.asarray(var.values, dtype=object)
    extra = sorted({str(v) for v in values.ravel()} - set(meanings) - {""})
    meanings = meanings + extra + ["not_solved"]
    index = {m: i for i, m in enumerate(meanings)}
    index[""] = len(meanings) - 1
    codes = (
        np.vectorize(lambda v: index[str(v)], otypes=[np.int8])(values)
        if values.size
        else (np.zeros(values.shape, np.int8))
    )
    return meanings, codes


def encode(ds: xr.Dataset) -> tuple[xr.Dataset, dict[str, dict[str, Any]]]:
    """The Dataset as written (a shallow copy) and its netCDF ``encoding``."""
    out = ds.copy(deep=False)
    encoding: dict[str, dict[str, Any]] = {}
    for name in list(out.data_vars):
        var = out[name]
        if var.dtype.kind in "OUS" and "flag_meanings" in var.attrs:
            n_declared = len(str(var.attrs["flag_meanings"]).split())
            meanings, codes = _flag_codes(var)
            attrs = dict(var.attrs)
            attrs.update(
                {
                    "flag_values": np.arange(len(meanings), dtype=np.int8),
                    "flag_meanings": " ".join(meanings),
                    _ENCODED: f"flags_from_strings:{n_declared}",
                }
            )
            out[name] = xr.DataArray(codes, dims=var.dims, attrs=attrs)
        elif "flag_values" in var.attrs:
            kind = np.int8 if var.dtype.kind == "b" else var.dtype
            vals = var.attrs["flag_values"]
            if isinstance(vals, str):
                vals = vals.split()
            out[name].attrs["flag_values"] = np.asarray(vals, dtype=float).astype(kind)
    for old, new in RENAMED.items():
        if old in out.variables and new not in out.variables:
            out = out.rename({old: new})
            out[new].attrs[_ENCODED] = f"renamed_from:{old}"
    for name in out.coords:
        encoding[name] = {"_FillValue": None}
    for name in out.data_vars:
        if out[name].dtype.kind in "iub":
            encoding[name] = {"_FillValue": None}
    return out, encoding


def decode(ds: xr.Dataset) -> xr.Dataset:
    """Undo :func:`encode` and :func:`seal` (works on lazily opened Datasets too)."""
    ds.attrs.pop(_ATTRS_DIGEST, None)
    for name in list(ds.variables):
        ds.variables[name].attrs.pop(DIGEST, None)
    for name in list(ds.variables):
        how = ds[name].attrs.get(_ENCODED)
        if how is None:
            continue
        if how.startswith("flags_from_strings:"):
            var = ds[name]
            n_declared = int(how.split(":", 1)[1])
            meanings = np.array(str(var.attrs["flag_meanings"]).split(), dtype=object)
            codes = np.asarray(var.values)
            strings = meanings[codes.ravel()].reshape(codes.shape)
            strings[codes == len(meanings) - 1] = ""
            attrs = {k: v for k, v in var.attrs.items() if k not in ("flag_values", _ENCODED)}
            attrs["flag_meanings"] = " ".join(meanings[:n_declared])
            # fastpath: a plain object ndarray; the duck-array checks would import dask.array
            ds[name] = xr.Variable(var.dims, strings, attrs, fastpath=True)
        elif how.startswith("renamed_from:"):
            old = how.split(":", 1)[1]
            ds = ds.rename({name: old})
            del ds[old].attrs[_ENCODED]
    return ds
