"""Rows of a block's points from a run at the equivalent loads (:mod:`.batched`): each
point's loads picked back in its order, every Pa^n output scaled by (E*_k / E*_ref)^n, a row
every point holds kept one row (a view); split from :mod:`.batched`."""

from __future__ import annotations

import re
from collections.abc import Callable
from typing import Any

import numpy as np
import xarray as xr

__all__ = ["pressure_power", "repeated_row", "repeats", "scaled_rows"]


# units that carry one power of pressure: Pa, and N = Pa m^2, J = Pa m^3, W = Pa m^3 s^-1
# (under contact similarity forces, energies and powers scale with E* like a pressure)
_PA = re.compile(r"(?<![A-Za-z])(?:Pa|N|J|W)(?:\^?(-?\d+))?(?![A-Za-z])")


def pressure_power(units: Any) -> int:
    """The power of pressure in a CF unit string (``"Pa^2"`` or ``"Pa2"`` -> 2, ``"Pa^-1 m"``
    -> -1, ``"J m^-2"`` -> 1 (J = Pa m^3), ``"1"`` -> 0)."""
    if not isinstance(units, str):
        return 0
    return sum(int(m.group(1) or 1) for m in _PA.finditer(units))


def repeats(arr: np.ndarray, dtype: Any) -> bool:
    """Whether ``arr`` (rows, C order) is one row repeated as a view (stride 0 along the
    rows, :func:`repeated_row`) of ``dtype``."""
    return arr.dtype == dtype and arr.ndim > 0 and arr.shape[0] > 1 and arr.strides[0] == 0


def scaled_rows(
    var: Any,
    estar: np.ndarray,
    ref: np.ndarray,
    inverse: np.ndarray,
    names: list[str],
    template: xr.Dataset,
    into: Callable[[list[str]], dict[str, np.ndarray]] | None = None,
) -> dict[str, np.ndarray] | None:
    """Rows of the P sub-points' M points each (``(P * M, *point shape)``, sub-point major) of
    a run at the equivalent loads: each point's loads back in its order (``inverse[s]``: index
    in the run of load (k, j) of sub-point s), every Pa^n output scaled by (E*_k / E*_ref,s)^n.

    ``var(name) -> (dims, values, units)``: ``values`` with a leading sub-point axis (of length
    P, or 1 where the run shares the variable between its points), ``dims`` without it.
    ``estar``: (P, M) [Pa]; ``ref``: (P,) [Pa]; ``inverse``: (P, M * n_loads). ``into(names)``:
    name -> a C-ordered ``(P * M, *point shape)`` array the rows of those variables are written
    into (the same values, one pass fewer; asked once, for the variables whose rows are
    written: not those every point holds as one row, :func:`repeated_row`), returned as that
    variable's rows.
    """
    P, M = estar.shape
    n_loads = inverse.shape[1] // M
    todo = []
    for n in names:
        dims, arr, units = var(n)
        if dims != template.variables[n].dims:
            return None
        power = 0 if n == "E" or arr.dtype.kind != "f" else pressure_power(units)
        row = None if power else repeated_row(arr, dims, n_loads)
        todo.append((n, dims, arr, power, row))
    dests = into([t[0] for t in todo if t[4] is None]) if into is not None else {}
    scale = (estar / ref[:, None]).ravel()
    same = bool(np.all(inverse == inverse[:1]))
    out = {}
    for n, dims, arr, power, row in todo:
        if row is not None:  # every point holds this row: a view, no rows written
            out[n] = np.broadcast_to(row, (P * M, *row.shape))
        else:
            out[n] = _rows_of(arr, dims, power, dests.get(n), scale, inverse, same, M)
    return out


def _rows_of(
    arr: np.ndarray,
    dims: tuple[str, ...],
    power: int,
    dest: np.ndarray | None,
    scale: np.ndarray,
    inverse: np.ndarray,
    same: bool,
    M: int,
) -> np.ndarray:
    """:func:`scaled_rows` of one variable (``dest``: the array to write them into, or
    ``None``)."""
    P = inverse.shape[0]
    if dest is not None and power and "p0" not in dims and _scaled_into(dest, arr, scale, power, P):
        return dest  # copied and scaled in one pass
    if dest is not None and _rows_into(dest, arr, dims, inverse, same):
        arr, fresh = dest, True
    elif "p0" in dims:
        axis = dims.index("p0")
        moved = np.moveaxis(arr, axis + 1, 1)  # (P or 1, run loads, rest)
        if moved.shape[0] == 1:
            picked = moved[0][inverse]
        elif same:  # every sub-point at the same equivalent loads: one index along them
            picked = moved[:, inverse[0]]
        else:
            picked = np.take_along_axis(moved, inverse.reshape(P, -1, *[1] * (arr.ndim - 2)), 1)
        picked = picked.reshape(P * M, inverse.shape[1] // M, *moved.shape[2:])
        arr, fresh = np.moveaxis(picked, 1, axis + 1), True
    else:
        wide = np.broadcast_to(arr[:, None], (P, M, *arr.shape[1:]))
        arr = wide.reshape(P * M, *arr.shape[1:])
        fresh = not np.shares_memory(arr, wide)
    if power:
        factor = scale.reshape((-1,) + (1,) * (arr.ndim - 1)) ** power
        if fresh:  # picked or reshaped above: scaled in place, no second array
            np.multiply(arr, factor, out=arr)
        else:
            arr = arr * factor
    return arr


def repeated_row(arr: np.ndarray, dims: tuple[str, ...], n_loads: int) -> np.ndarray | None:
    """The row every point of a run at the equivalent loads holds, where the run's array
    (leading sub-point axis, then ``dims``) repeats one value along its sub-points and loads:
    those axes of length 1 or stride 0 (a broadcast: the engine's exact zeros of the balances,
    a coordinate shared by the run); ``None`` otherwise (no value is compared)."""
    axes = [0, *([1 + dims.index("p0")] if "p0" in dims else [])]
    if any(arr.shape[a] > 1 and arr.strides[a] != 0 for a in axes) or 0 in arr.shape:
        return None
    row = arr[0]
    if "p0" in dims:
        axis = dims.index("p0")
        one = row[(slice(None),) * axis + (slice(0, 1),)]
        row = np.broadcast_to(one, row.shape[:axis] + (n_loads,) + row.shape[axis + 1 :])
    return row


def _scaled_into(dest: np.ndarray, arr: np.ndarray, scale: np.ndarray, power: int, P: int) -> bool:
    """:func:`scaled_rows`' rows of a variable without loads written into ``dest`` (``(P * M,
    *point shape)``, C order) already scaled, ``arr[s] * scale[s, m]^power``: the numbers of
    a broadcast copy scaled in place, in one pass; ``False`` (nothing written) for another
    layout or dtype."""
    if dest.dtype != arr.dtype or not dest.flags.c_contiguous or arr.shape[0] not in (1, P):
        return False
    rest, lead = arr.shape[1:], arr.shape[0]
    if dest.shape != (scale.size, *rest):
        return False
    factor = (scale**power).reshape(lead, -1, *[1] * len(rest))
    np.multiply(arr[:, None], factor, out=dest.reshape(lead, -1, *rest))
    return True


def _rows_into(
    dest: np.ndarray, arr: np.ndarray, dims: tuple[str, ...], inverse: np.ndarray, same: bool
) -> bool:
    """:func:`scaled_rows`' unscaled rows of one variable written into ``dest`` (``(P * M,
    *point shape)``, C order) by one gather or one broadcast copy; ``False`` (nothing written)
    where the layout needs the general path (``p0`` not the first point dimension, sub-points
    at different equivalent loads, another dtype)."""
    if dest.dtype != arr.dtype or not dest.flags.c_contiguous:
        return False
    P = inverse.shape[0]
    if "p0" not in dims:
        if arr.shape[0] not in (1, P):
            return False
        rest = arr.shape[1:]
        np.copyto(dest.reshape(P, -1, *rest), arr[:, None])  # broadcast over each P's M rows
        return True
    if dims.index("p0") != 0:
        return False
    rest = arr.shape[2:]
    if arr.shape[0] == 1:  # one run shared by every sub-point: one gather of all rows
        np.take(arr[0], inverse.ravel(), axis=0, out=dest.reshape(-1, *rest), mode="clip")
        return True
    if not same:
        return False
    np.take(arr, inverse[0], axis=1, out=dest.reshape(P, -1, *rest), mode="clip")
    return True
