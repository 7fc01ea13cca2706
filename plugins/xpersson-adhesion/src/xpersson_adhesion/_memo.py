"""Memo of results derived from a frozen (shared, immutable) roughness spectrum.

Equal spectrum parameters give the same frozen :class:`~xpersson.physics.PowerSpectrum` object
(the spectrum plugin shares it), so what the adhesion boundaries derive from it and from a few
numbers (the detachment-stress table, sigma_a(1), gamma_eff and the Tabor parameter at the
output magnifications) is computed once for the repeated solves of one scene.
"""

from __future__ import annotations

import collections
import hashlib
import threading
import weakref
from collections.abc import Callable
from typing import Any

import numpy as np

__all__ = ["memo", "digest"]

_MEMO: weakref.WeakKeyDictionary[Any, dict[tuple[Any, ...], Any]] = weakref.WeakKeyDictionary()
_ORDER: collections.deque[tuple[weakref.ref[Any], tuple[Any, ...]]] = collections.deque()
_MEMO_LOCK = threading.Lock()
_MEMO_SIZE = 64
"""Results kept in all (the oldest is dropped first; ~0.1 MB each at most)."""


def memo(psd: object, key: tuple[Any, ...], compute: Callable[[], Any]) -> Any:
    """``compute()``, memoised per frozen spectrum ``psd`` and hashable ``key``.

    A frozen spectrum is immutable and shared by the scenes of equal spectrum parameters
    (:meth:`xpersson.physics.PowerSpectrum.freeze`), so what derives from it alone (and from
    the numbers in ``key``) is computed once for repeated solves of one scene. The value is
    shared: callers must not modify it (arrays are returned read-only). Computed afresh, not
    kept, for a spectrum that is not frozen. The :data:`_MEMO_SIZE` newest results are kept
    (and none of a spectrum no longer referenced elsewhere).
    """
    if not getattr(psd, "frozen", False):
        return compute()
    try:
        with _MEMO_LOCK:
            table = _MEMO.get(psd)
            if table is not None and key in table:
                return table[key]
    except TypeError:  # an unhashable spectrum
        return compute()
    value = compute()
    for item in value if isinstance(value, tuple) else (value,):
        if isinstance(item, np.ndarray):
            item.setflags(write=False)
    with _MEMO_LOCK:
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


def digest(*arrays: np.ndarray) -> bytes:
    """A 128-bit fingerprint of the arrays' bytes (a short memo key for long samples)."""
    h = hashlib.blake2b(digest_size=16)
    for a in arrays:
        h.update(np.ascontiguousarray(a).tobytes())
    return h.digest()
