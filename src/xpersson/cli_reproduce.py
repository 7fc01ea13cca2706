"""What the CLI checks before any work: the texts of a scene, the files ``reproduce`` reads."""

from __future__ import annotations

import json
from typing import Any

__all__ = ["archived_scene", "check_texts", "MAX_READ_BYTES"]


def check_texts(node: Any, where: str) -> None:
    """Refuse text a netCDF archive could not store (a NUL, control characters, lone
    surrogates) before any work, naming the key."""
    from .archive import check_text_value
    from .scene import SceneError

    items = node.items() if isinstance(node, dict) else enumerate(node)
    for key, value in items:
        name = f"{where}{key}" if isinstance(node, dict) else f"{where}[{key}]"
        try:
            check_text_value(name, key)
            check_text_value(name, value)
        except ValueError as exc:
            raise SceneError(str(exc)) from None
        if isinstance(value, dict | list | tuple):
            check_texts(value, f"{name}." if isinstance(value, dict) else name)


def archived_scene(ds: Any, archive: str, read_files: bool) -> dict[str, Any]:
    """The archive's scene; files it names are refused unless ``read_files`` (a tabulated
    spectrum's stored ``q``/``C`` table replaces its file), and then read only from regular
    files of at most :data:`MAX_READ_BYTES`."""
    from .errors import ArchiveError

    data = json.loads(ds.attrs["xpersson_scene"])
    names = _path_parameters()
    if read_files:
        for where, value in _file_values(data, names, ""):
            _check_readable(archive, where, value)
        return data
    refs = _file_references(data, names, "")
    if refs:
        raise ArchiveError(
            f"{archive}: its scene names files ({', '.join(refs)}); reproduce reads no file an "
            "archive names unless --read-files is given"
        )
    return data


MAX_READ_BYTES = 256 * 2**20
"""Largest file ``reproduce --read-files`` reads [bytes]."""


def _path_parameters() -> set[str]:
    from .plugins import get_registry

    names = set()
    registry = get_registry()
    for info in registry.infos():
        try:
            cls = registry.load(info.group, info.name)
        except Exception:  # noqa: BLE001, S112 - a broken plugin names no path parameter
            continue
        params = getattr(cls, "parameters", {}) or {}
        names |= {k for k, spec in params.items() if getattr(spec, "kind", None) == "path"}
    return names


def _file_values(node: Any, names: set[str], where: str) -> list[tuple[str, Any]]:
    if not isinstance(node, dict):
        return []
    out: list[tuple[str, Any]] = []
    for key, value in node.items():
        if key in names and value is not None:
            out.append((f"{where}{key}", value))
        else:
            out += _file_values(value, names, f"{where}{key}.")
    return out


def _check_readable(archive: str, where: str, value: Any) -> None:
    """A file an archive's scene names: a regular file of at most :data:`MAX_READ_BYTES`
    (never a device, a FIFO or a folder, which could block or never end)."""
    import os
    import stat

    from .errors import ArchiveError

    try:
        info = os.stat(str(value))
    except (OSError, ValueError) as exc:
        raise ArchiveError(
            f"{archive}: {where} names a file that cannot be read ({type(exc).__name__})"
        ) from None
    if not stat.S_ISREG(info.st_mode):
        raise ArchiveError(
            f"{archive}: {where} names something that is not a regular file (a device, FIFO, "
            "socket or folder); reproduce reads regular files only"
        )
    if info.st_size > MAX_READ_BYTES:
        raise ArchiveError(
            f"{archive}: {where} names a file of {info.st_size} bytes, more than reproduce reads "
            f"({MAX_READ_BYTES})"
        )


def _file_references(node: Any, names: set[str], where: str) -> list[str]:
    out: list[str] = []
    if not isinstance(node, dict):
        return out
    inline = node.get("q") is not None and node.get("C") is not None
    for key in list(node):
        path = f"{where}{key}"
        if key in names and node[key] is not None:
            if inline:  # the stored table is used; the file stays out of reach
                del node[key]
            else:
                out.append(path)
        else:
            out += _file_references(node[key], names, path + ".")
    return out
