"""Memo of results derived from a frozen (immutable, shared) roughness spectrum.

Equal spectrum parameters give the same frozen :class:`~xpersson.physics.PowerSpectrum` object
(the spectrum plugin shares it), so what the physics and the plugins derive from it and from a
few numbers (quadrature rules and sub-problem nodes of the interface analyses, the adhesion
boundaries' detachment tables, ``gamma_eff``, the Tabor parameter) is computed once for the
repeated solves of one scene. The one home of such cross-solve caches.
"""

from __future__ import annotations

import collections
import dataclasses
import hashlib
import threading
import weakref
from collections.abc import Callable
from typing import Any

import numpy as np

__all__ = ["array_digest", "spectrum_memo"]

_MEMO: weakref.WeakKeyDictionary[Any, dict[tuple[Any, ...], Any]] = weakref.WeakKeyDictionary()
_ORDER: collections.deque[tuple[weakref.ref[Any], tuple[Any, ...]]] = collections.deque()
_LOCK = threading.Lock()
_MEMO_SIZE = 64
"""Results kept in all, over every spectrum (the oldest is dropped first)."""


def spectrum_memo(psd: object, key: tuple[Any, ...], compute: Callable[[], Any]) -> Any:
    """``compute()``, memoised per frozen spectrum ``psd`` and hashable ``key``.

    A frozen spectrum is immutable and shared by the scenes of equal spectrum parameters
    (:meth:`xpersson.physics.PowerSpectrum.freeze`), so what derives from it alone (and from
    the numbers in ``key``, whose first item names the quantity) is computed once for repeated
    solves of one scene. The value is shared: its arrays (also inside tuples and dataclasses)
    are made read-only. Computed afresh, not kept, for a spectrum that is not frozen or cannot
    be weakly referenced. The 64 newest results over all spectra are kept (and none of a
    spectrum no longer referenced elsewhere). Thread-safe.

    Parameters
    ----------
    psd : PowerSpectrum
        The spectrum the result derives from.
    key : tuple
        Hashable; the quantity's name first, then every number it depends on.
    compute : callable
        ``() -> value``, called on a miss.
    """
    if not getattr(psd, "frozen", False):
        return compute()
    try:
        with _LOCK:
            table = _MEMO.get(psd)
            if table is not None and key in table:
                return table[key]
    except TypeError:  # a spectrum that cannot be weakly referenced or hashed
        return compute()
    value = compute()
    _read_only(value)
    with _LOCK:
        table = _MEMO.setdefault(psd, {})
        if key not in table:
            _ORDER.append((weakref.ref(psd), key))
        table[key] = value
        while len(_ORDER) > _MEMO_SIZE:
            ref, old = _ORDER.popleft()
            owner = ref()
            if owner is not None:
                _MEMO.get(owner, {}).pop(old, None)
    return value


def _read_only(val: Any) -> None:
    """Make the arrays of ``val`` (an array, a tuple or a dataclass of them, nested) read-only."""
    if isinstance(val, np.ndarray):
        val.setflags(write=False)
    elif isinstance(val, tuple):
        for v in val:
            _read_only(v)
    elif dataclasses.is_dataclass(val) and not isinstance(val, type):
        for f in dataclasses.fields(val):
            _read_only(getattr(val, f.name))


def array_digest(*arrays: np.ndarray) -> bytes:
    """A 128-bit fingerprint of the arrays' bytes (a short memo key for long samples)."""
    h = hashlib.blake2b(digest_size=16)
    for a in arrays:
        h.update(np.ascontiguousarray(a).tobytes())
    return h.digest()
