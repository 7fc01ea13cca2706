"""The sweep's large output arrays in shared memory, written in place by workers on this machine.

A batched sweep's result is large against its CPU time (a 1e5-point E x H study: 229 MiB of
float64 for about 0.5 s of CPU). Sent through dask's comms (pickled, written to a socket, read
and unpickled, then copied into the sweep's arrays) it cost the client several times the study's
serial time. Instead, before any block runs, the client allocates each large output variable
of the whole sweep once, in one segment of ``/dev/shm`` (:func:`share`; the variables and their
shapes are known from the probe's block, :func:`~.probe.probe`), and every worker on this
machine (same host name and boot id, :func:`machine`) maps it in one round trip. The
segment's name is removed as soon as the workers have mapped it: from then on the memory has no
name, lives as long as a mapping of it (the client's arrays, the workers' until
:func:`release`), and nothing is left in ``/dev/shm`` whatever happens to the run (a failure, a
killed worker or client). A segment left by a client killed in the few milliseconds between
creating and sharing it carries that client's process id and is removed by the next
:func:`share` once that process is gone.

A worker writes its block's rows into the arrays (:class:`Sink`: a batched block's rows go
there directly, other blocks are copied there once, :func:`settle`) and sends back only the
rest of its block; a variable whose every probed point held one row is not shared, and a block
whose points all hold that row again sends nothing of it (the client writes the row). The client
wraps the arrays as the Dataset's variables: no copy, no pickling. The values are the ones the
block computed: the result is bitwise the serial one.

Measured (``benchmarks/sweep_scaling.py --crossover``): the 1e5-point E x H study still does not
pay on two local workers (1.18-1.92x serial wall, 1.35-1.45x the serial CPU on its critical
path): its tmpfs pages are 4 KiB, and populating them costs the workers more system time than
the serial run's 2 MiB anonymous pages (:data:`~.schedule.MEMORY_BOUND_RATE` keeps such a study
in the client's process, on threads there: :func:`~.schedule.run_here`). The path serves studies
above the threshold with large results.

Workers that are threads of this process (``LocalCluster(processes=False)``, :func:`in_process`)
get arrays of this process's own memory instead: no segment, the same sink and the same arrays
the client's Dataset wraps.
"""

from __future__ import annotations

import contextlib
import math
import mmap
import os
import socket
import uuid
from typing import Any

import numpy as np
import xarray as xr

from .filling import region_rows, same_memory, sweep_region
from .stacking import BlockResult

__all__ = [
    "MIN_BYTES",
    "SHM",
    "Sink",
    "attached",
    "in_process",
    "machine",
    "same_machine",
    "usable",
    "release",
    "settle",
    "share",
    "shared_specs",
]

#: Where the segments live: POSIX shared memory (a tmpfs on Linux).
SHM = "/dev/shm"  # noqa: S108
#: Output variables of the whole sweep smaller than this [bytes] travel with their blocks
#: through dask's comms (the default of ``solve_sweep(shm_bytes=...)``).
MIN_BYTES = 1 << 20
_PREFIX = "xpersson-sweep-"
_ALIGN = mmap.PAGESIZE
_POPULATE_WRITE = getattr(mmap, "MADV_POPULATE_WRITE", 23)  # Linux's value
#: Worker side: run token -> (mapping, {name: array}, the run's shared dict)
_ATTACHED: dict[str, tuple[Any, dict[str, np.ndarray], dict[str, Any]]] = {}


def machine() -> tuple[str, str]:
    """This process's machine: host name and boot id (equal for two processes sharing
    ``/dev/shm``)."""
    try:
        with open("/proc/sys/kernel/random/boot_id") as f:
            boot = f.read().strip()
    except OSError:
        boot = ""
    return socket.gethostname(), boot


def usable() -> bool:
    """Whether this process can create segments in :data:`SHM`."""
    return os.path.isdir(SHM) and os.access(SHM, os.W_OK)


def same_machine(machines: dict[str, Any]) -> bool:
    """Whether every worker (``{worker: (host name, boot id)}``) runs on this machine, with
    shared memory to use."""
    here = machine()
    return usable() and bool(machines) and all(tuple(m) == here for m in machines.values())


def shared_specs(
    ds: xr.Dataset, dims: tuple[str, ...], shape: tuple[int, ...], min_bytes: float
) -> dict[str, Any]:
    """``{name: (dims, full shape, dtype)}`` of the variables of a block's Dataset ``ds`` that
    go through shared memory: numeric, led by every sweep dimension in the sweep's order, and
    at least ``min_bytes`` over the whole sweep."""
    out = {}
    for name, var in ds.data_vars.items():
        if var.dims[: len(dims)] != tuple(dims) or var.dtype.hasobject:
            continue
        full = tuple(shape) + var.shape[len(dims) :]
        if math.prod(full) * var.dtype.itemsize >= min_bytes:
            out[name] = (var.dims, full, var.dtype.str)
    return out


def _offsets(specs: dict[str, Any]) -> tuple[dict[str, int], int]:
    """Page-aligned offset of each variable in the segment, and the segment's size [bytes]."""
    at, out = 0, {}
    for name, (_, shape, dtype) in specs.items():
        out[name] = at
        nbytes = math.prod(shape) * np.dtype(dtype).itemsize
        at += -(-nbytes // _ALIGN) * _ALIGN
    return out, max(at, _ALIGN)


def _arrays(mm: Any, specs: dict[str, Any], offsets: dict[str, int]) -> dict[str, np.ndarray]:
    return {
        name: np.frombuffer(mm, np.dtype(dtype), math.prod(shape), offsets[name]).reshape(shape)
        for name, (_, shape, dtype) in specs.items()
    }


def _remove_orphans() -> None:
    """Remove segments whose creating process is gone (a client killed before sharing)."""
    with contextlib.suppress(OSError):
        for entry in os.scandir(SHM):
            pid = entry.name.removeprefix(_PREFIX).partition("-")[0]
            if entry.name.startswith(_PREFIX) and pid.isdigit() and not _alive(int(pid)):
                with contextlib.suppress(OSError):
                    os.unlink(entry.path)


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _create(size: int) -> tuple[str, Any] | None:
    """A named segment of ``size`` bytes mapped here, or ``None`` (no room in ``/dev/shm``)."""
    try:
        st = os.statvfs(SHM)
    except OSError:
        return None
    if st.f_bavail * st.f_frsize < 2 * size:  # leave room: a worker writing past it dies
        return None
    path = os.path.join(SHM, f"{_PREFIX}{os.getpid()}-{uuid.uuid4().hex}")
    fd = os.open(path, os.O_CREAT | os.O_EXCL | os.O_RDWR, 0o600)
    try:
        os.ftruncate(fd, size)
        return path, mmap.mmap(fd, size)
    except OSError:
        os.unlink(path)
        return None
    finally:
        os.close(fd)


def share(
    client: Any, specs: dict[str, Any], token: str, same: dict[str, np.ndarray] | None = None
) -> dict[str, np.ndarray] | None:
    """The client's arrays of ``specs`` (:func:`shared_specs`) in a segment every worker of
    ``client`` has mapped under ``token``, its name already removed; ``None`` where a worker
    is on another machine or ``/dev/shm`` lacks the room (then nothing is shared).

    ``same``: variables (not in ``specs``) every point of the probe held the same row of, as
    that row's fingerprint (:func:`~.stacking._digests`): a block whose every point holds it
    sends neither the variable nor its rows (:func:`settle`)."""
    if not specs:
        return None
    if in_process(client):  # threads of this process: the arrays are its own memory
        arrays = {n: np.empty(shape, np.dtype(dt)) for n, (_, shape, dt) in specs.items()}
        _ATTACHED[token] = (None, arrays, _state(None, arrays, same, os.getpid()))
        return arrays
    if not usable():
        return None
    _remove_orphans()
    offsets, size = _offsets(specs)
    made = _create(size)
    if made is None:
        return None
    path, mm = made
    try:
        answers = client.run(_attach, token, path, specs, offsets, machine(), same or {})
    except Exception:  # noqa: BLE001 - any doubt: the ordinary comms
        answers = {}
    finally:
        os.unlink(path)
    if not answers or not all(answers.values()):
        release(client, token)
        return None
    return _arrays(mm, specs, offsets)


def _attach(
    token: str,
    path: str,
    specs: dict[str, Any],
    offsets: dict[str, int],
    host: Any,
    same: dict[str, np.ndarray],
) -> bool:
    """On a worker: map the run's segment (``False``: another machine, nothing mapped)."""
    if machine() != tuple(host):
        return False
    fd = os.open(path, os.O_RDWR)
    try:
        mm = mmap.mmap(fd, os.fstat(fd).st_size)
    finally:
        os.close(fd)
    arrays = _arrays(mm, specs, offsets)
    for old, (_, _, state) in list(_ATTACHED.items()):  # runs of clients killed since
        if not _alive(state["client"]):
            _ATTACHED.pop(old, None)
    _ATTACHED[token] = (mm, arrays, _state(mm, arrays, same, _owner(path)))
    return True


def _state(mm: Any, arrays: dict[str, np.ndarray], same: Any, client: int) -> dict[str, Any]:
    """A run's shared dict on a worker: its sink and the client's process id."""
    return {"sink": Sink(mm, arrays, same), "client": client}


def in_process(client: Any) -> bool:
    """Whether every worker of ``client`` is a thread of this process (a
    ``LocalCluster(processes=False)``: its workers' addresses are ``inproc://``, which only
    this process reaches)."""
    if not hasattr(client, "scheduler_info"):  # a scheduler's name or address
        return False
    try:
        workers = client.scheduler_info().get("workers", {})
    except Exception:  # noqa: BLE001 - no answer: not in this process
        return False
    return bool(workers) and all(str(w).startswith("inproc://") for w in workers)


def _owner(path: str) -> int:
    """The process id of the client that created a segment (its name carries it)."""
    return int(os.path.basename(path).removeprefix(_PREFIX).partition("-")[0])


async def _detach(token: str) -> None:
    """On a worker: drop the run's mapping (the memory goes with the last mapping); a
    coroutine, so that the client need not wait for it (``client.run(..., wait=False)``)."""
    _ATTACHED.pop(token, None)


def release(client: Any, token: str) -> None:
    """After the run, whatever its end: the workers drop their mappings (not waited for)."""
    with contextlib.suppress(Exception):
        client.run(_detach, token, wait=False)


class Sink:
    """On a worker: a block's rows written into the run's shared arrays (the interface of
    :meth:`~.filling.Filling.rows` that :func:`~.batched.batched_block` writes through).

    A region is populated before it is written (``madvise(MADV_POPULATE_WRITE)``, Linux 5.14):
    the pages of a tmpfs mapping are 4 KiB, and faulting them in one by one as the rows are
    written cost about twice as much (1-1.5 ms per MiB on the benchmark's machine)."""

    def __init__(self, mm: Any, arrays: dict[str, np.ndarray], same: Any = None) -> None:
        self.mm, self.arrays, self.same = mm, arrays, dict(same or {})
        self._base = None if mm is None else np.frombuffer(mm, np.uint8).ctypes.data

    def rows(self, name: str, block: Any, point_shape: tuple[int, ...], dtype: Any) -> Any:
        full = self.arrays.get(name)
        rows = None if full is None else region_rows(full, block, point_shape, dtype)
        if rows is not None:
            self.populate(rows)
        return rows

    def populate(self, region: np.ndarray) -> None:
        """Map the pages of a contiguous region for writing, in one call (nothing to do in
        this process's own memory: its pages are faulted in as written, 2 MiB at a time where
        transparent huge pages are on)."""
        if self.mm is None:
            return
        start = region.ctypes.data - self._base
        lo = start - start % _ALIGN
        with contextlib.suppress(OSError, ValueError):  # an older kernel: faulted as written
            self.mm.madvise(_POPULATE_WRITE, lo, start + region.nbytes - lo)


def attached(token: str | None) -> tuple[Sink, dict[str, Any]] | None:
    """On a worker: the run's sink and its shared dict (``"sink"``, and the first template,
    reused across the worker's blocks), or ``None`` (nothing shared with this worker)."""
    got = None if token is None else _ATTACHED.get(token)
    return None if got is None else (got[2]["sink"], got[2])


def settle(res: BlockResult, sink: Sink) -> tuple[BlockResult, dict[str, str]]:
    """On a worker: the block's shared variables in the run's arrays (copied where the block
    did not write them in place) and dropped from its Dataset, and so are the variables whose
    every point holds the row the probe's did (``sink.same``); returns the result and
    ``{name: "shm" or "same"}``."""
    ds = res.dataset
    if ds is None:
        return res, {}
    moved = {}
    for name, full in sink.arrays.items():
        var = ds.variables.get(name)
        if var is None or var.dtype != full.dtype:
            continue
        dst = full[sweep_region(res.block)]
        if var.shape != dst.shape:
            continue
        src = var.values
        if not same_memory(src, dst):
            if dst.flags.c_contiguous:
                sink.populate(dst)
            dst[...] = src
        moved[name] = "shm"
    for name, ref in sink.same.items():
        held = res.digests.get(name)
        if name in ds.variables and isinstance(held, np.ndarray) and np.all(held == ref):
            moved[name] = "same"
    if moved:
        res.dataset = ds.drop_vars(list(moved))
    return res, moved
