"""The one cache mechanism of xpersson: named, scoped, content-keyed, bounded, read-only.

Everything xpersson keeps in order to reuse it goes through a :class:`Cache` made here; no other
module keeps a dictionary of results, an ``lru_cache`` or an instance attribute filled by one
call and read by another. Each cache has

* a **name** (``"engine.level_rows"``), listed by :func:`caches` with its size and hit counts;
* a **scope**, which says how long a value lives:

  ``"solve"``
      one solve: the values live until the :func:`solve_scope` they were made in exits (the
      pipeline opens one per run); outside any solve scope nothing is kept;
  ``"spectrum"``
      values derived from one roughness spectrum (and a few numbers), reused by the later solves
      of scenes with that spectrum; the key holds the spectrum's content key;
  ``"process"``
      pure functions of their arguments (unit parsing, quadrature rules), kept for the process;

* a **content key**: :func:`content_key` turns numbers, strings, arrays (by dtype, shape and a
  128-bit digest of their bytes, or the bytes themselves up to 2 KiB) and objects that define
  ``cache_key()`` (spectra, plugin instances) into a hashable key; it refuses anything else,
  so nothing is ever keyed on ``id()`` or a partial fingerprint;
* a **bound** ``maxsize`` (least recently used dropped first);
* **read-only values**: the arrays of a value (also inside tuples, lists, dicts and
  dataclasses) are made read-only, whether or not the cache keeps them, so code that would
  write into a shared value fails the same way with the caches on and off;
* a lock: every cache is thread-safe.

One switch turns every cache off: ``xpersson.set_options(cache=False)`` or the environment
variable ``XPERSSON_CACHE=off`` (:mod:`xpersson.options`). Then every value is computed afresh,
and results are the same bit for bit (CI runs the whole test suite both ways).
"""

from __future__ import annotations

import contextlib
import contextvars
import dataclasses
import functools
import hashlib
import struct
import threading
from collections import OrderedDict
from collections.abc import Callable, Hashable, Iterator
from typing import Any, TypeVar

import numpy as np

from . import _scratch
from .options import cache_enabled

__all__ = [
    "SCOPES",
    "Cache",
    "CacheInfo",
    "cache",
    "caches",
    "clear_caches",
    "content_key",
    "dataclass_key",
    "made_key",
    "digest",
    "freeze",
    "memoize",
    "solve_scope",
]

T = TypeVar("T")

SCOPES: dict[str, str] = {
    "solve": "one solve (until the pipeline's solve_scope exits; nothing kept outside one)",
    "spectrum": "derived from one roughness spectrum, reused by later solves of that spectrum",
    "process": "a pure function of its arguments, kept for the process",
}
"""The scopes a cache may have, with what they mean."""

_REGISTRY: dict[str, Cache] = {}
_MISSING = object()
_REGISTRY_LOCK = threading.Lock()
#: the stores of the solve now running in this context (``None``: no solve scope open)
_SOLVE: contextvars.ContextVar[dict[str, OrderedDict[Hashable, Any]] | None] = (
    contextvars.ContextVar("xpersson_solve_caches", default=None)
)


@dataclasses.dataclass(frozen=True)
class CacheInfo:
    """What :func:`caches` reports of one cache."""

    name: str
    scope: str
    maxsize: int
    size: int
    hits: int
    misses: int
    doc: str


class Cache:
    """A named, scoped, bounded, thread-safe store of read-only values keyed on content.

    Parameters
    ----------
    name : str
        Unique dotted name (``"physics.phi_weights"``).
    scope : {"solve", "spectrum", "process"}
        How long values live (:data:`SCOPES`).
    maxsize : int
        Values kept at most (per solve for scope ``"solve"``); the least recently used goes.
    doc : str
        One line: what the values are.
    """

    def __init__(self, name: str, *, scope: str, maxsize: int, doc: str = "") -> None:
        if scope not in SCOPES:
            raise ValueError(
                f"cache {name!r}: scope must be one of {sorted(SCOPES)}, got {scope!r}"
            )
        if not isinstance(maxsize, int) or isinstance(maxsize, bool) or maxsize < 1:
            raise ValueError(f"cache {name!r}: maxsize must be a positive int, got {maxsize!r}")
        self.name, self.scope, self.maxsize, self.doc = name, scope, maxsize, doc
        self._store: OrderedDict[Hashable, Any] = OrderedDict()
        self._per_solve = scope == "solve"
        self._lock = threading.Lock()
        self.hits = 0
        self.misses = 0
        with _REGISTRY_LOCK:
            if name in _REGISTRY:
                raise ValueError(f"a cache named {name!r} exists already")
            _REGISTRY[name] = self

    def _table(self) -> OrderedDict[Hashable, Any] | None:
        """The store values go to now (``None``: keep nothing)."""
        if not cache_enabled():
            return None
        if not self._per_solve:
            return self._store
        stores = _SOLVE.get()
        if stores is None:
            return None
        table = stores.get(self.name)
        if table is None:
            table = stores[self.name] = OrderedDict()
        return table

    def get(self, key: Any, compute: Callable[[], T]) -> T:
        """The value for ``key`` (normalised by :func:`content_key`), computed on a miss.

        The value's arrays are made read-only (:func:`freeze`), also when nothing is kept.
        """
        # the process and spectrum scopes' store inline (a look-up is on every hot path)
        table = self._table() if self._per_solve or not cache_enabled() else self._store
        if table is None:
            return freeze(compute())
        k = content_key(key)
        with self._lock:
            found = table.get(k, _MISSING)
            if found is not _MISSING:
                table.move_to_end(k)
                self.hits += 1
                return found  # type: ignore[no-any-return]
            self.misses += 1
        value = freeze(compute())
        with self._lock:
            value = table.setdefault(k, value)  # another thread's equal value wins
            table.move_to_end(k)
            while len(table) > self.maxsize:
                table.popitem(last=False)
        return value

    def peek(self, key: Any) -> Any:
        """The value kept for ``key``, or ``None`` (nothing computed; nothing kept with the
        caches off or, for scope ``"solve"``, outside a solve). A value found counts as a hit
        of :meth:`get` (the most recently used)."""
        table = self._table()
        if table is None:
            return None
        k = content_key(key)
        with self._lock:
            found = table.get(k, _MISSING)
            if found is _MISSING:
                return None
            table.move_to_end(k)
            self.hits += 1
            return found

    def clear(self) -> None:
        """Drop every kept value (of the current solve too, for scope ``"solve"``)."""
        with self._lock:
            self._store.clear()
            stores = _SOLVE.get()
            if stores is not None:
                stores.pop(self.name, None)
            self.hits = self.misses = 0

    def __len__(self) -> int:
        if self.scope != "solve":
            return len(self._store)
        stores = _SOLVE.get() or {}
        return len(stores.get(self.name, ()))

    def info(self) -> CacheInfo:
        """Name, scope, bound, size now and the hit counts."""
        return CacheInfo(
            self.name, self.scope, self.maxsize, len(self), self.hits, self.misses, self.doc
        )

    def __repr__(self) -> str:
        return f"Cache({self.name!r}, scope={self.scope!r}, maxsize={self.maxsize})"

    def __reduce__(self) -> tuple[Any, ...]:  # a module-level cache pickles by name
        return (cache, (self.name,))


def cache(name: str) -> Cache:
    """The cache named ``name`` (``KeyError`` naming the known ones if there is none)."""
    try:
        return _REGISTRY[name]
    except KeyError:
        raise KeyError(f"no cache named {name!r}; known: {sorted(_REGISTRY)}") from None


def caches() -> list[CacheInfo]:
    """Every cache made so far (imported modules only), sorted by name."""
    with _REGISTRY_LOCK:
        found = list(_REGISTRY.values())
    return sorted((c.info() for c in found), key=lambda i: i.name)


def clear_caches() -> None:
    """Drop every kept value of every cache, and the working memory kept between solves
    (:mod:`xpersson._scratch`)."""
    with _REGISTRY_LOCK:
        found = list(_REGISTRY.values())
    for c in found:
        c.clear()
    _scratch.clear()


@contextlib.contextmanager
def solve_scope() -> Iterator[None]:
    """Open a solve: the ``"solve"``-scoped caches keep values until the block exits.

    A nested scope (an analysis re-solving through ``ctx.solve_at``) has stores of its own.
    Context-local, so threads and dask tasks each have theirs.
    """
    token = _SOLVE.set({})
    try:
        yield
    finally:
        _SOLVE.reset(token)


def memoize(
    name: str, *, scope: str = "process", maxsize: int = 64
) -> Callable[[Callable[..., T]], Callable[..., T]]:
    """Decorator: a function memoised in a :class:`Cache` named ``name``.

    The key is the arguments' :func:`content_key` (positional and keyword), so arguments must
    be numbers, strings, arrays, tuples of them, or objects with ``cache_key()``. The wrapper's
    ``cache`` attribute is the :class:`Cache`.
    """

    def decorate(fn: Callable[..., T]) -> Callable[..., T]:
        doc = (fn.__doc__ or "").strip().splitlines()[0] if fn.__doc__ else fn.__qualname__
        store = Cache(name, scope=scope, maxsize=maxsize, doc=doc)

        @functools.wraps(fn)
        def wrapper(*args: Any, **kwargs: Any) -> T:
            key = (args, tuple(sorted(kwargs.items()))) if kwargs else args
            return store.get(key, lambda: fn(*args, **kwargs))

        wrapper.cache = store  # type: ignore[attr-defined]
        return wrapper

    return decorate


def digest(*arrays: Any) -> bytes:
    """A 128-bit digest (SHA-1, truncated; about twice BLAKE2b's speed where the CPU has SHA
    instructions) of arrays' dtypes, shapes and bytes (a content key part).

    A content key, not a signature: it lives in one process's caches (and keys equal content
    equally in every process of one version); nothing persisted depends on it.
    """
    h = hashlib.sha1(usedforsecurity=False)
    for a in arrays:
        arr = a if type(a) is np.ndarray else np.asarray(a)
        if arr.dtype.hasobject:
            raise TypeError("digest: an object array's bytes are pointers, not its content")
        h.update(f"{arr.dtype.str}{arr.shape}".encode())
        # a C-contiguous numeric array is read through its buffer (no copy of its bytes)
        plain = arr.flags.c_contiguous and arr.dtype.kind in "biufc"
        h.update(arr if plain else np.ascontiguousarray(arr).tobytes())
    return h.digest()[:16]


_PLAIN = (str, bytes, int, bool, type(None))


def content_key(item: Any) -> Hashable:
    """A hashable key made of ``item``'s content (recursively).

    Strings, bytes, ints, bools and ``None`` stand for themselves; floats by their exact bits
    (their 8 bytes: ``0.0`` and ``-0.0`` differ; a tuple or list of more than 8 floats by
    their bytes packed at once); numpy scalars as Python numbers; arrays as
    ``(dtype, shape, digest)`` (up to 2 KiB as ``(dtype, shape, bytes)``); tuples, lists,
    frozensets and dicts by their items; an object with a ``cache_key()`` method by its type
    and the content key of what that returns; a module-level class or function by its
    qualified name. An object array keys as its items do.

    Raises
    ------
    TypeError
        For anything else (naming its type): a cache never keys on object identity.
    """
    kind = type(item)  # the exact common types first (a look-up is on every hot path)
    if kind in _SELF:
        return item
    if kind is float:
        return ("f", _FLOAT_BITS(item))
    if kind is tuple or kind is list:
        if len(item) > 8 and set(map(type, item)) == _FLOATS:  # (a scene's zeta list)
            return ("F", struct.pack(f"<{len(item)}d", *item))  # every float's exact bits
        return tuple([v if type(v) in _SELF else _item_key(v) for v in item])
    if kind is dict:  # (a scene's tables)
        pairs = [
            (k if type(k) in _SELF else content_key(k), v if type(v) in _SELF else content_key(v))
            for k, v in item.items()
        ]
        pairs.sort()
        return ("d", tuple(pairs))
    if kind is np.ndarray:
        code = _DTYPES.get(item.dtype)
        if code is not None:  # a dtype without objects, seen before
            if item.nbytes <= _SMALL:  # its bytes themselves (a digest's set-up costs ~4 us)
                return ("b", code, item.shape, item.tobytes())
            return ("a", code, item.shape, digest(item))
    name = _KEYED.get(kind)
    if name is not None:  # a class seen before whose instances key by their cache_key()
        own = item.cache_key()  # (mostly a digest: bytes, which stand for themselves)
        return ("o", name, own if type(own) in _SELF else content_key(own))
    return _content_key(item)


def _item_key(item: Any) -> Hashable:
    """:func:`content_key` of a tuple's item that does not stand for itself (a float without a
    further call)."""
    kind = type(item)
    if kind is float:
        return ("f", _FLOAT_BITS(item))
    return content_key(item)


class MadeKey(tuple):
    """A tuple :func:`content_key` made (:func:`made_key`): it stands for itself in a later key
    (equal to and hashed as the plain tuple; read only)."""

    __slots__ = ()


def made_key(item: Any) -> Hashable:
    """``content_key(item)``, marked as made: a key that holds it, or a :meth:`Cache.get` of it,
    takes it as it is instead of walking it again (a key kept on an object and used in several
    look-ups, e.g. a diffusion clock's: its walk costs more than the item's)."""
    made = content_key(item)
    return MadeKey(made) if type(made) is tuple else made


_SELF = frozenset({str, bytes, int, bool, type(None), MadeKey})
_FLOATS = {float}
_SMALL = 2048
"""Arrays of at most this many bytes key by their bytes (exact, and cheaper than a digest)."""
_FLOAT_BITS = struct.Struct("<d").pack
"""A float's exact bits (8 bytes; ~7x cheaper than ``float.hex``)."""
_DTYPES: dict[np.dtype[Any], str] = {}
"""``dtype.str`` of the dtypes without objects seen so far (a read of it costs ~1 us)."""
_MAX_DTYPES = 64
"""At most this many dtypes are kept in :data:`_DTYPES` (others read ``dtype.str`` each time)."""
_KEYED: dict[type, str] = {}
"""Classes whose instances key by their ``cache_key()`` (a method of the class, and none of
the types keyed before it), with their qualified names: found once per class."""


def _content_key(item: Any) -> Hashable:
    """:func:`content_key` of the other types, and of subclasses of the common ones."""
    if isinstance(item, _PLAIN):
        return item
    if isinstance(item, float):
        return ("f", _FLOAT_BITS(item))
    if isinstance(item, tuple | list):
        return tuple(content_key(v) for v in item)
    if isinstance(item, np.ndarray):
        if item.dtype.hasobject:  # its bytes are pointers: identity, not content
            return ("A", item.shape, tuple(content_key(v) for v in item.ravel().tolist()))
        if type(item) is np.ndarray:  # a dtype not seen before
            code = item.dtype.str
            if len(_DTYPES) < _MAX_DTYPES:
                _DTYPES[item.dtype] = code
            if item.nbytes <= _SMALL:
                return ("b", code, item.shape, item.tobytes())
            return ("a", code, item.shape, digest(item))
        return content_key(np.asarray(item))  # a subclass: as its plain array
    if isinstance(item, np.generic):
        return content_key(item.item())
    if isinstance(item, frozenset | set):
        return ("s", frozenset(content_key(v) for v in item))
    if isinstance(item, dict):
        return ("d", tuple(sorted((content_key(k), content_key(v)) for k, v in item.items())))
    method = getattr(item, "cache_key", None)
    if callable(method) and not isinstance(item, type):
        kind = type(item)
        name = f"{kind.__module__}.{kind.__qualname__}"
        if callable(getattr(kind, "cache_key", None)) and "cache_key" not in getattr(
            item, "__dict__", ()
        ):  # the class's method: every instance keys this way
            _KEYED[kind] = name
        return ("o", name, content_key(method()))
    name = getattr(item, "__qualname__", "<")
    if (isinstance(item, type) or callable(item)) and "<" not in name:  # not a lambda or local
        return ("c", f"{item.__module__}.{name}")
    raise TypeError(
        f"cannot key a cache on the content of a {type(item).__module__}."
        f"{type(item).__qualname__} (give it a cache_key() method, or key on its numbers)"
    )


def dataclass_key(obj: Any) -> bytes:
    """The content key of a frozen dataclass: a 128-bit digest of its init fields'
    :func:`content_key`, computed on the first call and kept on the (immutable) object.

    For a ``cache_key()`` method of frozen dataclasses whose fields define them (modulus models,
    shift laws): the fields' arrays are digested once per object instead of at every look-up.
    """
    key = obj.__dict__.get("_content_key")
    if key is None:
        fields = tuple(getattr(obj, f.name) for f in dataclasses.fields(obj) if f.init)
        key = hashlib.blake2b(repr(content_key(fields)).encode(), digest_size=16).digest()
        object.__setattr__(obj, "_content_key", key)
    return key  # type: ignore[no-any-return]


def freeze(value: T) -> T:
    """``value`` with its arrays made read-only (also inside tuples, lists, dicts, dataclasses)."""
    if isinstance(value, np.ndarray):
        value.setflags(write=False)
    elif isinstance(value, tuple | list):
        for v in value:
            freeze(v)
    elif isinstance(value, dict):
        for v in value.values():
            freeze(v)
    elif dataclasses.is_dataclass(value) and not isinstance(value, type):
        for f in dataclasses.fields(value):
            freeze(getattr(value, f.name))
    return value
