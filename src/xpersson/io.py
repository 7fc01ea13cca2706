"""netCDF archives: safe writes and faithful re-opening.

A write goes to a hidden temporary file beside the target, is flushed to disk (``fsync``) and
then appears under the target name in one atomic step: ``os.replace`` when overwriting, a hard
link (which fails if the name exists) otherwise, so of several writers racing for one new path
exactly one succeeds and a reader never sees a partial archive. The temporary file is created
with mode ``0666`` minus the umask (as ``open`` would) and is named after its writer
(``.<name>.<host>.<pid>.<random>.part``). Temporaries left by killed writers -- their process
gone (same host) or older than an hour (other hosts), and not locked -- are removed by the next
write to the same target; on Linux the writer also holds an open-file-description lock on its
temporary, which dies with the process, so a reused pid never exposes a live writer's file.
"""

from __future__ import annotations

import contextlib
import errno
import os
import secrets
import socket
import time
from pathlib import Path

import xarray as xr

__all__ = ["to_netcdf", "open_dataset", "open_parts", "stale_temporaries"]

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
        from ._cf import encode

        stored, encoding = encode(ds)
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
    from ._cf import decode

    return finalize(decode(ds), index["constant"], index["attrs"])
