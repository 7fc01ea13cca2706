"""Archive integrity: digests of values and attributes, text that netCDF keeps (private)."""

from __future__ import annotations

import hashlib
import json
import os
import re
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import ArchiveError

if TYPE_CHECKING:
    import xarray as xr

# -- content integrity ---------------------------------------------------------------------------
DIGEST = "xpersson_sha256"
_ATTRS_DIGEST = "xpersson_attrs_sha256"
_NOT_HASHED = {DIGEST, "_FillValue", "coordinates", "dtype", "missing_value"}
FORMAT_ATTR = "xpersson_archive_format"
FORMAT_VERSION = 3
"""Archive format versions: 1 (no digests: read unverified), 2 (a digest on every variable and
on the global attributes, no version attribute), 3 (as 2, with ``xpersson_archive_format``).
From version 2 on every digest must exist: a missing one is an error, never a skip."""
UNVERIFIED = "unverified"
"""The ``status`` of an archive read without digests (format version 1)."""


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
    out.attrs[FORMAT_ATTR] = np.int32(FORMAT_VERSION)
    out.attrs[_ATTRS_DIGEST] = _global_digest(out)
    return out


def format_version(ds: xr.Dataset, path: str | os.PathLike[str]) -> int:
    """The archive format version an opened file declares (see :data:`FORMAT_VERSION`).

    Raises
    ------
    ArchiveError
        A version this xpersson does not know, or digests that say a version the file denies
        (some present, others removed).
    """
    declared = ds.attrs.get(FORMAT_ATTR)
    if declared is not None:
        ok = np.ndim(declared) == 0 and np.asarray(declared).dtype.kind in "iu"
        if not ok or not 2 <= int(declared) <= FORMAT_VERSION:
            raise ArchiveError(
                f"{path}: archive format version {str(declared)[:20]!r} is not one this xpersson "
                f"reads (2 to {FORMAT_VERSION}); upgrade xpersson"
            )
        return int(declared)
    if _ATTRS_DIGEST in ds.attrs:
        return 2
    marked = [str(n) for n, v in ds.variables.items() if DIGEST in v.attrs]
    if marked:
        raise ArchiveError(
            f"{path}: the global attributes lack their digest ({_ATTRS_DIGEST}) while variable "
            f"{marked[0]!r} has one: a digest was removed (the file is corrupt or forged)"
        )
    return 1


def verify(ds: xr.Dataset, path: str | os.PathLike[str]) -> int:
    """Check the digests :func:`seal` stored (loads every variable); returns the format version.

    From format version 2 on every variable and the global attributes must carry a digest; a
    version 1 archive (no digest at all) is read unverified (:func:`mark_unverified`).

    Raises
    ------
    ArchiveError
        Naming ``path`` and the first variable (or the global attributes) that changed or
        lacks its digest.
    """
    version = format_version(ds, path)
    if version == 1:
        return 1
    for name, var in ds.variables.items():
        stored = var.attrs.get(DIGEST)
        if stored is None:
            raise ArchiveError(
                f"{path}: variable {name!r} has no digest ({DIGEST}), which archive format "
                f"version {version} requires (the file is corrupt or forged)"
            )
        if stored != _variable_digest(var):
            raise ArchiveError(
                f"{path}: variable {name!r} fails its checksum: its stored values or "
                "attributes changed after writing (the file is corrupt)"
            )
    if ds.attrs.get(_ATTRS_DIGEST) != _global_digest(ds):
        raise ArchiveError(
            f"{path}: the global attributes fail their checksum (the file is corrupt)"
        )
    return version


def mark_unverified(ds: xr.Dataset, version: int) -> xr.Dataset:
    """An archive read without digests: ``status`` says so (never ``"success"``)."""
    note = (
        f"unverified: format version {version} (written without digests; its values "
        "cannot be checked against what was written)"
    )
    message = str(ds.attrs.get("status_message", "") or "")
    ds.attrs["status_message"] = f"{note}; {message}" if message else note
    ds.attrs["status"] = UNVERIFIED
    return ds


_BAD_TEXT = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\x7f\ud800-\udfff]")
"""Characters a netCDF text attribute does not store faithfully: NUL ends the text, other C0
controls and DEL are refused as unprintable, a lone surrogate has no UTF-8 form."""


def check_text(ds: xr.Dataset) -> None:
    """Refuse text a netCDF archive cannot store and give back (before anything is written).

    Every attribute name and text value (global and of every variable, whoever added it) and
    every variable name is checked.

    Raises
    ------
    ValueError
        Naming the attribute (and variable), the character and its position.
    """
    for where, attrs in [("global attribute", ds.attrs)] + [
        (f"attribute of variable {str(n)[:60]!r},", v.attrs) for n, v in ds.variables.items()
    ]:
        for key, value in attrs.items():
            _check_name(f"{where} {str(key)[:60]!r} (its name)", key)
            texts = [value] if isinstance(value, str) else []
            if isinstance(value, list | tuple | np.ndarray):
                texts = [x for x in np.asarray(value, dtype=object).ravel() if isinstance(x, str)]
            for text in texts:
                _check_one(f"{where} {str(key)[:60]!r}", text)
    for name in ds.variables:
        _check_name(f"variable name {str(name)[:60]!r}", name)


_NAME_START = re.compile(r"[A-Za-z0-9_]|[^\x00-\x7f]")


def _check_name(what: str, name: Any) -> None:
    """A netCDF name: starts with a letter, digit, ``_`` or a non-ASCII character; no ``/``, no
    trailing space, nothing :data:`_BAD_TEXT` refuses."""
    _check_one(what, name)
    text = str(name)
    if not text or not _NAME_START.match(text) or "/" in text or text != text.rstrip():
        raise ValueError(
            f"{what}: not a name netCDF accepts (it must start with a letter, digit, '_' or a "
            "non-ASCII character and contain no '/' and no trailing space)"
        )


def check_text_value(what: str, text: Any) -> None:
    """Refuse one text (see :func:`check_text`): a ``ValueError`` starting with ``what``."""
    _check_one(what, text)


def _check_one(what: str, text: Any) -> None:
    if not isinstance(text, str):
        return
    bad = _BAD_TEXT.search(text)
    if bad is not None:
        raise ValueError(
            f"{what}: character U+{ord(bad.group()):04X} at position {bad.start()} cannot be "
            "stored in a netCDF archive (control characters and lone surrogates are refused); "
            "remove it"
        )
