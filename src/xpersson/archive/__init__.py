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
  the file and the variable. The global attribute ``xpersson_archive_format`` (3) says which
  digests must exist: from version 2 on (digests without the attribute) a missing digest is an
  error; an archive without any digest (version 1) is read with ``status = "unverified"``.
- The pressure PDF ``P`` is stored as ``pressure_pdf``: CF forbids variable names that differ
  only by case, and ``p`` is the pressure coordinate. The stored variable says so in its
  ``xpersson_name`` attribute; :func:`decode` restores ``P``.
"""

from __future__ import annotations

import contextlib
import errno
import os
import secrets
import signal
import socket
import threading
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..errors import ArchiveError
from ._cf import RENAMED, decode, encode
from ._integrity import (
    DIGEST,
    FORMAT_VERSION,
    check_text,
    check_text_value,
    file_digest,
    mark_unverified,
    seal,
    verify,
)

if TYPE_CHECKING:
    import xarray as xr

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
    "WriteError",
    "FORMAT_VERSION",
    "check_text",
    "check_text_value",
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
    ValueError
        A text attribute netCDF cannot store faithfully (naming it); nothing is written.
    WriteError
        The operating system refused the write (disk full, quota, file-size limit, permission,
        read-only file system): one line naming the file and the cause; nothing is written.
    """
    target = Path(path)
    if target.exists() and not overwrite:
        raise FileExistsError(f"{target} exists; pass overwrite=True (CLI: --overwrite)")
    folder = target.parent if str(target.parent) else Path(".")
    if not folder.is_dir():
        raise FileNotFoundError(f"output folder {folder} does not exist")
    check_text(ds)
    stored, encoding = encode(ds)
    stored = seal(stored, encoding)
    try:
        _write_file(target, stored, encoding, folder, overwrite)
    except (FileExistsError, FileNotFoundError):
        raise
    except OSError as exc:  # disk full, quota, file-size limit, permission, read-only, ...
        raise WriteError(target, exc) from None
    return target


class WriteError(OSError):
    """An archive could not be written (the operating system's cause named; nothing written).

    The message is one line: ``cannot write PATH: CAUSE (nothing was written)``.
    """

    def __init__(self, target: Path, exc: OSError) -> None:
        cause = exc.strerror or os.strerror(exc.errno or 0) or type(exc).__name__
        super().__init__(exc.errno, cause, str(target))

    def __str__(self) -> str:
        return f"cannot write {self.filename}: {self.strerror} (nothing was written)"


def _write_file(
    target: Path, stored: xr.Dataset, encoding: dict[str, Any], folder: Path, overwrite: bool
) -> None:
    """``stored`` to a locked temporary beside ``target``, fsync, then the atomic rename/link."""
    _ignore_file_size_signal()
    remove_stale_temporaries(target)
    tmp, fd = _create_temporary(target)
    try:
        try:
            stored.to_netcdf(tmp, engine=ENGINE, format="NETCDF4", encoding=encoding)
        except PermissionError:  # a file system emulating flock with our lock (NFS): unlock
            if not _lock(fd, unlock=True):
                raise
            stored.to_netcdf(tmp, engine=ENGINE, format="NETCDF4", encoding=encoding)
        except Exception:
            _probe(fd)  # the operating system's cause, when the netCDF library hid it
            raise
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


_PROBE_BYTES = 1 << 20


def _probe(fd: int) -> None:
    """Append :data:`_PROBE_BYTES` to the failed temporary: raises the ``OSError`` (``ENOSPC``,
    ``EDQUOT``, ``EFBIG``, ...) the netCDF library reports only as "HDF error"."""
    os.lseek(fd, 0, os.SEEK_END)
    view = memoryview(bytes(_PROBE_BYTES))
    while view:
        view = view[os.write(fd, view) :]


def _ignore_file_size_signal() -> None:
    """A file-size limit (``RLIMIT_FSIZE``) kills a process whose ``SIGXFSZ`` keeps its default
    action; ignored (main thread, default action only), the write fails with ``EFBIG``."""
    sig = getattr(signal, "SIGXFSZ", None)
    if sig is None or threading.current_thread() is not threading.main_thread():
        return
    with contextlib.suppress(ValueError, OSError):
        if signal.getsignal(sig) == signal.SIG_DFL:
            signal.signal(sig, signal.SIG_IGN)


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
        import xarray as xr

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
        version = verify(ds, path)
        try:
            out = decode(ds.load())
        except Exception as exc:  # noqa: BLE001 - any malformed attribute
            raise ArchiveError(f"{path}: malformed encoding attributes ({_short(exc)})") from None
    return mark_unverified(out, version) if version == 1 else out


def _short(exc: BaseException) -> str:
    text = f"{type(exc).__name__}: {exc}".splitlines()[0] if str(exc) else type(exc).__name__
    return text if len(text) <= 160 else text[:157] + "..."
