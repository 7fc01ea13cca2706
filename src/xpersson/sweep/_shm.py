"""A block's large arrays from a worker on this machine through shared memory, not the socket.

A batched sweep's result is large against its CPU time (a 1e5-point E x H study: 229 MiB of
float64 for about 0.5 s of CPU): sent through dask's comms (pickled, written to a socket, read
and unpickled by the client's event loop) it cost the client about three times the study's
serial time on a 2-core machine (``benchmarks/summary.py``, LocalCluster row). A worker on the
client's machine (:func:`same_machine`) instead copies each large variable of its block's
Dataset into a file of ``/dev/shm`` (:func:`pack`) and sends only its name; the client maps it,
removes the name at once (the memory lives as long as the mapped array) and fills the result
from it (:func:`unpack`). The values are copied, never recomputed: the result is bitwise the one the
socket would have carried.
"""

from __future__ import annotations

import contextlib
import mmap
import os
import socket
import uuid
from typing import Any

import numpy as np
import xarray as xr

from .stacking import BlockResult

__all__ = [
    "MIN_BYTES",
    "SHM",
    "discard",
    "discard_pending",
    "machine",
    "pack",
    "same_machine",
    "unpack",
]

#: Where the segments live: POSIX shared memory (a tmpfs on Linux).
SHM = "/dev/shm"  # noqa: S108
#: Variables smaller than this [bytes] travel with the block through dask's comms.
MIN_BYTES = 1 << 20


def machine() -> tuple[str, str]:
    """This process's machine: host name and boot id (equal for two processes sharing
    ``/dev/shm``)."""
    try:
        with open("/proc/sys/kernel/random/boot_id") as f:
            boot = f.read().strip()
    except OSError:
        boot = ""
    return socket.gethostname(), boot


def same_machine(client: Any) -> bool:
    """Whether every worker of ``client`` runs on this machine with shared memory to use."""
    if not os.path.isdir(SHM) or not os.access(SHM, os.W_OK):
        return False
    here = machine()
    try:
        there = client.run(machine)
    except Exception:  # noqa: BLE001 - any doubt: the ordinary comms
        return False
    return bool(there) and all(tuple(m) == here for m in there.values())


def pack(res: BlockResult) -> tuple[BlockResult, dict[str, Any]]:
    """On a worker: move the large data variables of ``res.dataset`` into shared memory.

    Returns the result without them and ``{name: (segment, shape, dtype, dims, attrs,
    encoding, order)}`` (``order``: the Dataset's data variables, to restore their order)."""
    ds = res.dataset
    if ds is None:
        return res, {}
    moved: dict[str, Any] = {}
    order = list(ds.data_vars)
    for name in order:
        var = ds.variables[name]
        a = var.values
        if a.nbytes < MIN_BYTES or a.dtype.hasobject:
            continue
        segment = os.path.join(SHM, f"xpersson-{uuid.uuid4().hex}")
        fd = os.open(segment, os.O_CREAT | os.O_EXCL | os.O_RDWR, 0o600)
        try:
            os.ftruncate(fd, a.nbytes)
            with mmap.mmap(fd, a.nbytes) as mm:
                np.frombuffer(mm, a.dtype).reshape(a.shape)[...] = a
        finally:
            os.close(fd)
        moved[name] = (segment, a.shape, a.dtype.str, var.dims, var.attrs, var.encoding, order)
    if moved:
        res.dataset = ds.drop_vars(list(moved))
    return res, moved


def _take(segment: str, shape: tuple[int, ...], dtype: str) -> np.ndarray:
    """The segment's values, mapped (not copied; the mapping lives as long as the array) and
    its name removed at once."""
    fd = os.open(segment, os.O_RDWR)
    try:
        size = os.fstat(fd).st_size
        mm = mmap.mmap(fd, size) if size else None
    finally:
        os.close(fd)
        os.unlink(segment)
    if mm is None:
        return np.empty(shape, np.dtype(dtype))
    return np.frombuffer(mm, np.dtype(dtype)).reshape(shape)


def unpack(res: BlockResult, moved: dict[str, Any]) -> BlockResult:
    """On the client: the values back from shared memory (mapped; the segments' names
    removed), the data variables in their worker's order."""
    if not moved:
        return res
    ds = res.dataset
    order = next(iter(moved.values()))[-1]
    back = {
        name: xr.Variable(dims, _take(seg, shape, dtype), attrs, encoding)
        for name, (seg, shape, dtype, dims, attrs, encoding, _) in moved.items()
    }
    data = {k: back[k] if k in back else ds.variables[k] for k in order}
    out = xr.Dataset(data, coords=ds.coords, attrs=ds.attrs)
    out.encoding = ds.encoding
    res.dataset = out
    return res


def discard_pending(futures: list[Any], local: bool) -> None:
    """After a failed run: cancel the block tasks not read and remove the segments of those
    that finished (``local``: they returned through shared memory)."""
    for fut in futures:
        if local and fut.status == "finished":
            with contextlib.suppress(Exception):
                discard(fut.result()[1])
        fut.cancel()


def discard(moved: dict[str, Any]) -> None:
    """Remove the segments of a result the client will not read."""
    for seg, *_ in moved.values():
        with contextlib.suppress(FileNotFoundError):
            os.unlink(seg)
