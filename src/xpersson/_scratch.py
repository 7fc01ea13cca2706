"""Working memory kept between solves (private): a solve's large arrays on pages kept warm.

A solve's largest arrays (its splines' coefficients, ``Phi``'s look-up table and its values at
the mean gap's nodes) are 0.4-1.4 MB each at 100 loads. Between solves glibc gives the
heap's top back to the system and unmaps its largest blocks, so each such array of the next
solve lands on fresh pages, and each 4 kB page costs a page fault (~1-1.5 us) when first
written: ~10-15 % of a 100-load solve. :func:`empty` hands out arrays over buffers this module
keeps instead (written over, never read before written: the same operations give the same
bits).

The lease
---------
An array of :func:`empty` is a view of a kept buffer through an owner object of its own; every
view of the array, and every view of those, keeps that owner alive (numpy's base chain stops
at it). The buffer goes back to the pool when the owner dies, that is when the last array that
could read or write it is gone, and not before (``weakref.finalize``): a buffer is never handed
out twice at once, whatever the array flows into. An array kept beyond the solve (in a result,
a cache) simply keeps its buffer out of the pool. Callers use :func:`empty` only for arrays
whose lifetime they can see ends with the solve (objects of the solve's scope, a caller's
temporary), so the buffers come back for the next solve; and only for arrays that would land
on fresh pages: a temporary freed early in the solve is better left to malloc, which hands its
memory to the next array while it is still in the CPU's caches (measured: the spline systems'
right-hand sides and the blocks of ``1 - F`` kept here made 100-load solves interleaved with
1000-load ones ~3 % slower).

Bounds and switches
-------------------
Each thread returns its buffers to a pool of its own (dask threads run solves concurrently; a
buffer freed in another thread goes back to the pool it came from) and keeps at most
:data:`MAX_BYTES` (32 MiB) of free buffers in it, the oldest dropped first; arrays smaller than
:data:`MIN_BYTES` or larger than :data:`MAX_BUFFER` are plain ``np.empty`` (malloc's heap
reuses small blocks without faults anyway). With the caches off
(``xpersson.set_options(cache=False)`` / ``XPERSSON_CACHE=off``) every array is a plain
``np.empty`` and nothing is kept. :func:`xpersson.cache.clear_caches` empties every pool
(:func:`clear`); buffers out at that moment are dropped when they come back.
"""

from __future__ import annotations

import collections
import threading
import weakref
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .options import cache_enabled

__all__ = ["MAX_BUFFER", "MAX_BYTES", "MIN_BYTES", "clear", "empty", "kept_bytes"]

MAX_BYTES = 32 << 20
"""Bytes of free buffers one thread's pool keeps at most (32 MiB)."""
MAX_BUFFER = 8 << 20
"""The largest array on a kept buffer (8 MiB): a larger one is a plain ``np.empty``."""
MIN_BYTES = 128 << 10
"""Arrays smaller than this (128 kB) are plain ``np.empty``: malloc reuses such memory itself."""
_PAGE = 4096
"""Buffers are made of whole pages; an array takes the newest free buffer (warm in the CPU's
caches) of its size up to twice it."""


class _Pool:
    """One thread's free buffers (1-D ``uint8``, oldest first), the bytes they hold, the
    number of buffers out, and the generation (bumped by :meth:`empty`: a buffer of an older
    one is dropped when returned).

    A buffer comes back through :meth:`give`, called when its array dies: in any thread, and
    possibly by the garbage collector while this thread holds the lock (a collection can run at
    any allocation). So ``give`` only appends to a deque (atomic) and files what came back
    where the lock is free; :meth:`take` files it first.
    """

    __slots__ = ("__weakref__", "back", "free", "generation", "lock", "nbytes", "out")

    def __init__(self) -> None:
        self.free: list[NDArray[np.uint8]] = []
        self.back: collections.deque[tuple[NDArray[np.uint8], int]] = collections.deque()
        self.nbytes = 0
        self.out = 0
        self.generation = 0
        self.lock = threading.Lock()

    def _file(self) -> None:
        """Move what came back to the free buffers (the lock held): those of the current
        generation, the oldest dropped beyond :data:`MAX_BYTES`."""
        while self.back:
            buf, generation = self.back.popleft()
            if generation == self.generation:
                self.out -= 1
                self.free.append(buf)
                self.nbytes += buf.nbytes
        while self.nbytes > MAX_BYTES:
            self.nbytes -= self.free.pop(0).nbytes

    def take(self, nbytes: int) -> NDArray[np.uint8]:
        """The newest free buffer of ``nbytes`` to ``2 nbytes`` bytes (no longer free), else
        a new one of whole pages."""
        with self.lock:
            self._file()
            self.out += 1
            for k in range(len(self.free) - 1, -1, -1):  # the newest first: warm in cache
                if nbytes <= self.free[k].nbytes <= 2 * nbytes:
                    buf = self.free.pop(k)
                    self.nbytes -= buf.nbytes
                    return buf
        return np.empty(-(-nbytes // _PAGE) * _PAGE, dtype=np.uint8)

    def give(self, buf: NDArray[np.uint8], generation: int) -> None:
        """A buffer whose array died comes back (filed now unless the lock is held)."""
        self.back.append((buf, generation))
        if self.lock.acquire(blocking=False):
            try:
                self._file()
            finally:
                self.lock.release()

    def empty(self) -> None:
        """Drop the free buffers; those out now are dropped when they come back."""
        with self.lock:
            self._file()
            self.free.clear()
            self.nbytes = 0
            self.generation += 1
            self.out = 0  # (those out now are not counted when they come back)

    def kept(self) -> int:
        """Bytes of the free buffers (what came back filed first)."""
        with self.lock:
            self._file()
            return self.nbytes


class _Owner:
    """The base of one array over a kept buffer: alive while any view of the array is."""

    __slots__ = ("__array_interface__", "__weakref__", "buf")

    def __init__(self, buf: NDArray[np.uint8], shape: tuple[int, ...], dtype: np.dtype) -> None:
        self.buf = buf
        self.__array_interface__ = {
            "shape": shape,
            "typestr": dtype.str,
            "data": (buf.ctypes.data, False),
            "version": 3,
        }


_LOCAL = threading.local()
_POOLS: weakref.WeakSet[_Pool] = weakref.WeakSet()  # every thread's (for clear())
_POOLS_LOCK = threading.Lock()


def _pool() -> _Pool:
    """This thread's pool (made on first use)."""
    pool: _Pool | None = getattr(_LOCAL, "pool", None)
    if pool is None:
        pool = _LOCAL.pool = _Pool()
        with _POOLS_LOCK:
            _POOLS.add(pool)
    return pool


def empty(shape: int | tuple[int, ...], dtype: Any = np.float64) -> NDArray[Any]:
    """``np.empty(shape, dtype)`` (C order, contents unspecified) over a kept buffer.

    Parameters
    ----------
    shape : int or tuple of int
        The array's shape.
    dtype : numpy dtype, optional
        Its dtype (float64).

    Returns
    -------
    ndarray
        A writeable C-contiguous array; its buffer goes back to this thread's pool when the
        array and every view of it are gone. A plain ``np.empty`` with the caches off, or
        below :data:`MIN_BYTES` or above :data:`MAX_BUFFER`.
    """
    dt = np.dtype(dtype)
    shape = (int(shape),) if isinstance(shape, int | np.integer) else tuple(map(int, shape))
    nbytes = dt.itemsize
    for n in shape:
        nbytes *= n
    if not MIN_BYTES <= nbytes <= MAX_BUFFER or dt.hasobject or not cache_enabled():
        return np.empty(shape, dtype=dt)
    pool = _pool()
    buf = pool.take(nbytes)
    owner = _Owner(buf, shape, dt)
    weakref.finalize(owner, pool.give, buf, pool.generation).atexit = False
    return np.asarray(owner)


def clear() -> None:
    """Empty every thread's pool (buffers out now are dropped when they come back)."""
    with _POOLS_LOCK:
        pools = list(_POOLS)
    for pool in pools:
        pool.empty()


def kept_bytes() -> int:
    """Bytes of free buffers this thread's pool keeps now."""
    pool: _Pool | None = getattr(_LOCAL, "pool", None)
    return 0 if pool is None else pool.kept()
