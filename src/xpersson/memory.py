"""Memory estimate of a request, checked before any work against a configurable budget.

The budget is, in this order: the value given to :func:`set_budget`, the environment variable
``XPERSSON_MEMORY_BUDGET`` (bytes, or a number with a unit: ``"2 GB"``, ``"500 MiB"``), or
:data:`DEFAULT_FRACTION` of the memory the operating system reports as available. Where the
operating system does not report it, :data:`UNKNOWN_AVAILABLE` is assumed and a
:class:`~xpersson.XperssonWarning` says so once per process, naming the two ways to state
the budget.
"""

from __future__ import annotations

import math
import os
import re
import time
import warnings

from .errors import MemoryBudgetError, XperssonWarning

__all__ = [
    "MemoryBudgetError",
    "budget",
    "set_budget",
    "estimate",
    "check_request",
    "estimate_study",
    "check_study",
    "DEFAULT_FRACTION",
    "UNKNOWN_AVAILABLE",
]

#: Fraction of the available memory one request may use by default.
DEFAULT_FRACTION = 0.5

#: Available memory [bytes] assumed where the operating system does not report it (with a
#: warning): 4 GiB.
UNKNOWN_AVAILABLE = 4 * 2**30

_UNITS = {
    "": 1,
    "b": 1,
    "kb": 1e3,
    "mb": 1e6,
    "gb": 1e9,
    "tb": 1e12,
    "kib": 2**10,
    "mib": 2**20,
    "gib": 2**30,
    "tib": 2**40,
}
_override: int | None = None

# bytes per stored (p0, zeta) value: ~15 core variables plus the engine's temporaries
_PER_POINT = 8 * 40
# the P field: engine result, closed-form temporaries, one copy for the Dataset
_PER_P_VALUE = 8 * 6
# a sweep point resolved before any work and held until its block runs (measured: ~9 kB)
_PER_RESOLVED = 12 * 2**10
# stored per point of a sweep: ~16 doubles per (p0, zeta) and P with its flags
_PER_STORED = 8 * 16
_PER_STORED_P = 8 * 2


def _parse(text: str) -> int:
    m = re.fullmatch(r"\s*([0-9.eE+]+)\s*([A-Za-z]*)\s*", str(text))
    if not m or m.group(2).lower() not in _UNITS:
        raise ValueError(
            f"XPERSSON_MEMORY_BUDGET [bytes] must be a positive number of bytes or a size like "
            f"'2 GB' / '500 MiB'; got {text!r}"
        )
    try:
        value = float(m.group(1)) * _UNITS[m.group(2).lower()]
    except ValueError:
        value = math.nan
    if not 0 < value <= MAX_BUDGET:
        raise ValueError(
            f"XPERSSON_MEMORY_BUDGET [bytes] must be a number of bytes > 0 and at most "
            f"{MAX_BUDGET:.3g} (16 EiB); got {str(text)[:40]!r}"
        )
    return int(value)


MAX_BUDGET = float(2**64)
"""Largest memory budget accepted [bytes]."""


def available() -> int:
    """Memory the operating system reports as available [bytes] (:data:`UNKNOWN_AVAILABLE`,
    with a warning once per process, when it reports none).

    Read at most once a second (a solve costs well under a millisecond otherwise).
    """
    now = time.monotonic()
    if _AVAILABLE and now - _AVAILABLE[0] < 1.0:
        return _AVAILABLE[1]
    value = _read_available()
    _AVAILABLE[:] = [now, value]
    return value


_AVAILABLE: list = []
_WARNED: list[bool] = []  # the unknown-memory warning was given (once per process)


def _read_available() -> int:
    """Available memory [bytes]: ``/proc/meminfo``, else ``sysconf``, else
    :data:`UNKNOWN_AVAILABLE` with a warning (once per process)."""
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass  # not Linux: ask sysconf
    try:
        return int(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):
        pass
    if not _WARNED:
        _WARNED.append(True)
        warnings.warn(
            f"xpersson: the operating system does not report the available memory; the "
            f"memory budget assumes {UNKNOWN_AVAILABLE / 2**30:g} GiB available "
            f"({DEFAULT_FRACTION:g} of it per request). State the budget with the environment "
            "variable XPERSSON_MEMORY_BUDGET (e.g. '2 GB') or xpersson.memory.set_budget().",
            XperssonWarning,
            stacklevel=4,
        )
    return UNKNOWN_AVAILABLE


def set_budget(nbytes: int | str | None) -> None:
    """Set the budget [bytes] (an int, a size like ``"2 GB"``, or None for the default)."""
    global _override
    if nbytes is None:
        _override = None
    elif isinstance(nbytes, str):
        _override = _parse(nbytes)
    else:
        if not 0 < nbytes <= MAX_BUDGET:
            raise ValueError(
                f"memory budget [bytes] must be > 0 and at most {MAX_BUDGET:.3g}; got {nbytes!r}"
            )
        _override = int(nbytes)


def budget() -> int:
    """The memory budget of one request [bytes]."""
    if _override is not None:
        return _override
    env = os.environ.get("XPERSSON_MEMORY_BUDGET")
    if env:
        return _parse(env)
    return int(DEFAULT_FRACTION * available())


def estimate(n_load: int, n_zeta: int, n_p: int | None = None) -> int:
    """Peak memory [bytes] of a solve over ``n_load`` loads, ``n_zeta`` magnifications and,
    when the pressure field is stored, ``n_p`` pressures."""
    size = _PER_POINT * n_load * n_zeta
    if n_p:
        size += _PER_P_VALUE * n_load * n_zeta * n_p
    return int(size)


def _human(n: float) -> str:
    for unit in ("B", "kB", "MB", "GB", "TB"):
        if n < 1000 or unit == "TB":
            return f"{n:.3g} {unit}"
        n /= 1000
    return f"{n:.3g} TB"  # pragma: no cover


def check_request(n_load: int, n_zeta: int, n_p: int | None = None) -> int:
    """Raise :class:`MemoryBudgetError` (before any work) when the estimate exceeds the budget.

    Returns the estimate [bytes].
    """
    need, have = estimate(n_load, n_zeta, n_p), budget()
    if need > have:
        field = f" x {n_p} pressures (output.p_points)" if n_p else ""
        raise MemoryBudgetError(
            f"the request needs about {_human(need)} ({n_load} loads x {n_zeta} magnifications"
            f"{field}), above the memory budget of {_human(have)}: use fewer p points "
            "(output.p_points) or drop output.pressure_pdf, fewer loads or output.zeta_per_decade, "
            "or a sweep written in parts; the budget is set by XPERSSON_MEMORY_BUDGET "
            "(e.g. '8 GB') or xpersson.memory.set_budget()"
        )
    return need


def estimate_study(
    n_points: int,
    n_load: int,
    n_zeta: int,
    n_p: int | None = None,
    *,
    block_points: int = 1,
    workers: int = 1,
    in_memory: bool = True,
) -> int:
    """Peak memory [bytes] of a sweep of ``n_points`` points: the resolved points, the stored
    results (all of them in memory, or a block per worker when written to a folder) and one
    solve per worker."""
    point = _PER_STORED * n_load * n_zeta + (_PER_STORED_P * n_load * n_zeta * n_p if n_p else 0)
    held = n_points * point if in_memory else 2 * block_points * max(1, workers) * point
    resolved = n_points * (_PER_RESOLVED + 16 * n_zeta)
    return int(resolved + held + max(1, workers) * estimate(n_load, n_zeta, n_p))


def check_study(
    n_points: int,
    n_load: int,
    n_zeta: int,
    n_p: int | None = None,
    *,
    block_points: int = 1,
    workers: int = 1,
    in_memory: bool = True,
) -> int:
    """Raise :class:`MemoryBudgetError` before any work when a whole sweep exceeds the budget
    (:func:`estimate_study`); returns the estimate [bytes]."""
    need = estimate_study(
        n_points,
        n_load,
        n_zeta,
        n_p,
        block_points=block_points,
        workers=workers,
        in_memory=in_memory,
    )
    have = budget()
    if need > have:
        field = f" x {n_p} pressures" if n_p else ""
        advice = (
            "write it to a folder in parts (output=DIR, CLI: -o DIR/) with smaller chunks"
            if in_memory
            else "use smaller chunks (chunk=, CLI: --chunk) or fewer workers"
        )
        raise MemoryBudgetError(
            f"the sweep needs about {_human(need)} ({n_points} points x {n_load} loads x "
            f"{n_zeta} magnifications{field}), above the memory budget of {_human(have)}: "
            f"{advice}, sweep fewer points (fewer values or a coarser range num), fewer loads, "
            "fewer magnifications (output.zeta_per_decade) or p points (output.p_points); the "
            "budget is set by XPERSSON_MEMORY_BUDGET (e.g. '8 GB') or "
            "xpersson.memory.set_budget()"
        )
    return need
