"""Checks of plain arrays (coefficient outputs), built spectra and walls."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..cache import Cache
from ._failure import PluginFailure, calling

__all__ = ["check_array", "check_spectrum", "check_walls", "quote"]

_SHOW = 3  # offending values quoted in a message


# -- plain arrays (coefficient, walls) -----------------------------------------------------------
def check_array(
    value: Any,
    who: object,
    what: str,
    shape: tuple[int, ...],
    *,
    nonnegative: bool = False,
    nondecreasing_axis: int | None = None,
    unit: str = "",
) -> np.ndarray:
    """Return ``value`` as a float array of ``shape`` after checking it.

    Raises
    ------
    PluginFailure
        Wrong shape, non-numeric, non-finite, negative (with ``nonnegative``) or decreasing
        along ``nondecreasing_axis``; the message quotes the offending values.
    """
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise PluginFailure(
            f"{who}: {what} returned a non-numeric value ({exc})", plugin=who, variable=what
        ) from None
    if arr.shape != shape:
        if (
            arr.size == math.prod(shape)
            and arr.ndim <= len(shape)
            and arr.ndim >= 1
            and (arr.shape == shape[len(shape) - arr.ndim :])
        ):
            arr = arr.reshape(shape)
        else:
            raise PluginFailure(
                f"{who}: {what} returned shape {arr.shape}, expected {shape}",
                plugin=who,
                variable=what,
            )
    if arr.size:  # the rule in two reductions (min and max propagate NaN and show +-inf)
        lo, hi = float(arr.min()), float(arr.max())
        if math.isfinite(lo) and math.isfinite(hi) and (lo >= 0 or not nonnegative):
            if not (nondecreasing_axis == 0 and arr.ndim == 1 and lo >= 0):
                _check_nondecreasing(arr, who, what, nondecreasing_axis)
            elif arr.size > 1 and float(np.min(arr[1:] - arr[:-1])) < -1e-12 * hi:
                _check_nondecreasing(arr, who, what, 0)  # raises, counting the steps down
            return arr  # (a non-negative row: its largest magnitude is its maximum)
    u = f" {unit}" if unit else ""  # a value breaks the rule: the checks below quote it
    bad = ~np.isfinite(arr)
    if bad.any():
        raise PluginFailure(
            f"{who}: {what} returned {int(bad.sum())} non-finite value(s): {quote(arr, bad, u)}",
            plugin=who,
            variable=what,
        )
    if nonnegative and np.any(arr < 0):
        raise PluginFailure(
            f"{who}: {what} returned {int((arr < 0).sum())} negative value(s) (must be >= 0): "
            f"{quote(arr, arr < 0, u)}",
            plugin=who,
            variable=what,
        )
    _check_nondecreasing(arr, who, what, nondecreasing_axis)
    return arr


def _check_nondecreasing(arr: np.ndarray, who: object, what: str, axis: int | None) -> None:
    """No step of finite ``arr`` along ``axis`` goes down by more than 1e-12 of the largest
    magnitude along it (round-off); ``None``: nothing to check."""
    if axis is not None and arr.shape[axis] > 1:
        d = np.diff(arr, axis=axis)
        scale = np.max(np.abs(arr), axis=axis, keepdims=True)
        down = d < -1e-12 * scale
        if down.any():
            raise PluginFailure(
                f"{who}: {what} decreases (must be non-decreasing in zeta) at "
                f"{int(down.sum())} step(s)",
                plugin=who,
                variable=what,
            )


def quote(arr: np.ndarray, mask: np.ndarray, unit: str = "", coords: Any = None) -> str:
    idx = np.argwhere(mask)[:_SHOW]
    parts = []
    for i in idx:
        where = _where(tuple(int(k) for k in i), coords)
        v = arr[tuple(i)]
        text = f"{float(v):.6g}" if np.isrealobj(v) else repr(v)
        parts.append(f"{text}{unit} at {where}")
    more = int(mask.sum()) - len(parts)
    return "; ".join(parts) + (f"; ... ({more} more)" if more > 0 else "")


def _where(index: tuple[int, ...], coords: Any) -> str:
    if coords is None:
        return f"index {index if len(index) != 1 else index[0]}"
    out = []
    for dim, k in zip(coords["dims"], index, strict=False):
        values = coords["values"].get(dim)
        if values is not None and k < len(values):
            out.append(f"{dim}={values[k]:.6g}")
        else:
            out.append(f"{dim}[{k}]")
    return ", ".join(out) or "the scalar"


# -- spectra -------------------------------------------------------------------------------------
def check_spectrum(psd: Any, who: object) -> None:
    """Check the numerical spectrum a spectrum plugin built (cut-offs, nodes, C >= 0, finite).

    Raises
    ------
    PluginFailure
        Naming the plugin and the attribute at fault.

    A spectrum with a content key (``cache_key()``, as every
    :class:`~xpersson.physics.PowerSpectrum`) whose content passed once is not checked again
    (cache ``"checks.spectrum"``); one without is checked every time.
    """
    if not callable(getattr(psd, "cache_key", None)):
        _check_spectrum(psd, who)
        return
    _CHECKED_SPECTRA.get(psd, lambda: _check_spectrum(psd, who))


_CHECKED_SPECTRA = Cache(
    "checks.spectrum",
    scope="spectrum",
    maxsize=256,
    doc="spectra (by content) whose numbers passed check_spectrum",
)


def _check_spectrum(psd: Any, who: object) -> None:
    with calling(who, "the built spectrum's q_L / q_1"):
        q_L, q_1 = float(psd.q_L), float(psd.q_1)
    if not (math.isfinite(q_L) and math.isfinite(q_1) and 0 < q_L < q_1):
        raise PluginFailure(
            f"{who}: the spectrum's cut-offs must satisfy 0 < q_L < q_1 (finite, 1/m); got "
            f"q_L={q_L!r} 1/m, q_1={q_1!r} 1/m",
            plugin=who,
            variable="q_L, q_1",
        )
    with calling(who, "nodes()"):
        nodes = np.asarray(psd.nodes(), dtype=float)
    if nodes.ndim != 1 or nodes.size < 2:
        raise PluginFailure(
            f"{who}: nodes() returned shape {nodes.shape}; expected 1-D with >= 2 wavevectors",
            plugin=who,
            variable="nodes",
        )
    check_array(
        nodes, who, "nodes()", nodes.shape, nonnegative=True, nondecreasing_axis=0, unit="1/m"
    )
    with calling(who, "C(q)"):
        c = psd.C(nodes)
    check_array(c, who, "C(q) at the spectrum's nodes", nodes.shape, nonnegative=True, unit="m4")
    for what, unit in (("h_rms", "m"), ("rms_slope", "1")):
        with calling(who, f"{what}()"):
            value = getattr(psd, what)()
        check_array(value, who, f"{what}()", (), nonnegative=True, unit=unit)


# -- walls ---------------------------------------------------------------------------------------
def check_walls(walls: Any, p0: float, who: object) -> tuple[Any, Any]:
    """Check a boundary's ``walls()`` return value: ``(Wall, Wall or None)``, p0 inside.

    Raises
    ------
    PluginFailure
        Wrong types, or a wall that does not leave the load ``p0`` [Pa] strictly inside at
        ``tau = 0``.
    """
    from ..engine import Wall

    if not isinstance(walls, tuple | list) or len(walls) != 2:
        raise PluginFailure(
            f"{who}: walls() must return (lower Wall, upper Wall or None); got "
            f"{type(walls).__name__}",
            plugin=who,
            variable="walls",
        )
    lower, upper = walls
    if not isinstance(lower, Wall) or not (upper is None or isinstance(upper, Wall)):
        raise PluginFailure(
            f"{who}: walls() must return (Wall, Wall or None); got ({type(lower).__name__}, "
            f"{type(upper).__name__})",
            plugin=who,
            variable="walls",
        )
    for side, wall in (("lower", lower), ("upper", upper)):
        if wall is None:
            continue
        if type(wall) is Wall and type(wall.position) is float:  # fixed: what at() gives
            pos = wall.position  # (no plugin code runs: nothing to call)
        else:
            with calling(who, f"the {side} wall's position at tau = 0"):
                pos = float(np.asarray(wall.at(np.zeros(1)), float)[0])
        if not math.isfinite(pos):
            raise PluginFailure(
                f"{who}: the {side} wall is at {pos!r} Pa at tau = 0 (must be finite)",
                plugin=who,
                variable=f"walls.{side}",
            )
        if (side == "lower" and not pos < p0) or (side == "upper" and not pos > p0):
            rel = "below" if side == "lower" else "above"
            raise PluginFailure(
                f"{who}: the {side} wall starts at {pos:g} Pa, not strictly {rel} the load "
                f"p0 = {p0:g} Pa",
                plugin=who,
                variable=f"walls.{side}",
            )
    return lower, upper
