"""Checks of the Dataset contributions of plugins and of the engine's core outputs."""

from __future__ import annotations

import contextlib
import math
from collections.abc import Iterator, Mapping
from typing import Any

import numpy as np

from ._arrays import quote
from ._failure import PluginFailure

__all__ = [
    "CORE_DIMS",
    "CORE_RANGES",
    "check_contributions",
    "check_core",
    "checked_variable",
    "guard_dataset",
]

#: Dimensions the core owns; any other Dataset dimension is a sweep (or plugin) dimension.
CORE_DIMS = ("p0", "zeta", "p", "q_psd")


# -- Dataset contributions -----------------------------------------------------------------------
def _check_coords(ds: Any, value: Any, name: str, who: object) -> None:
    """Every coordinate of a returned DataArray that the Dataset has must be the Dataset's,
    exactly (same dims, same values; NaN equal): it is never aligned (a shifted ``zeta`` would
    turn the variable into NaN)."""
    for c, coord in value.coords.items():
        if c not in ds.variables:
            continue
        mine, theirs = ds.variables[c], coord.variable
        same = mine.dims == theirs.dims and mine.shape == theirs.shape
        if same:
            a, b = np.asarray(mine.values), np.asarray(theirs.values)
            nan = a.dtype.kind in "fc" and b.dtype.kind in "fc"
            same = bool(np.array_equal(a, b, equal_nan=nan))
        if not same:
            raise PluginFailure(
                f"{_VarName(who, name)}: its coordinate {str(c)!r} differs from the solved "
                f"{str(c)!r} (dims {theirs.dims} vs {mine.dims}); return the variable on the "
                "solved coordinates (outputs are never aligned)",
                plugin=who,
                variable=name,
            )


def checked_variable(
    ds: Any, name: str, value: Any, spec: Any, who: object, sizes: Mapping[str, int] | None = None
) -> Any:
    """Turn one returned ``(dims, data)`` pair or DataArray into a checked DataArray
    (a pair becomes a coordinate-free :class:`xarray.Variable`; a float array on exactly the
    declared dims and the Dataset's sizes is given back as the pair ``(dims, ndarray)``, its
    dims a tuple: the caller makes its Variable).

    Checks, against the :class:`~xpersson.plugins.VarSpec`: dims (the declared ones, plus
    only sweep dimensions of ``ds``), sizes (those of ``ds`` for shared dims), a numeric or
    boolean dtype, finiteness (NaN only with ``nan_meaning``; never inf) and
    ``valid_min`` / ``valid_max``.

    ``sizes`` (optional) is ``dict(ds.sizes)`` when the caller has it.

    Raises
    ------
    PluginFailure
        Naming the plugin, the variable and the offending values.
    """
    import xarray as xr

    var = _VarName(who, name)  # formatted only for a message
    try:
        if isinstance(value, xr.DataArray):
            _check_coords(ds, value, name, who)
            # a shallow copy: the returned array becomes the Dataset's, as a pair's does (a deep
            # copy cost a 1000-load gap_pdf 2 MB of new pages, ~1.3 ms); the plugin's own
            # DataArray keeps its attrs (a new dict here) and its coordinates' index
            da = value.copy(deep=False)
            da.attrs = {}
            if any(c not in da.xindexes for c in da.coords):  # (reset_coords drops these)
                da = da.reset_coords(drop=True)
        else:  # a plain Variable (no coordinates to carry): cheaper than a DataArray
            dims, arr = value
            if isinstance(dims, str):
                dims = (dims,)
            dims = tuple(dims)
            arr = np.asarray(arr)
            if (
                arr.dtype.kind == "f"
                and dims == tuple(spec.dims)
                and len(dims) == arr.ndim
                and all(type(d) is str for d in dims)
                and arr.shape
                == tuple((sizes if sizes is not None else dict(ds.sizes)).get(d, -1) for d in dims)
            ):
                # the common case: exactly the declared dims, the Dataset's sizes, floats;
                # the remaining rule is the values' (finite, valid_min / valid_max), checked
                # on the array (the pair given back: the caller makes its Variable)
                _check_values(_Pair(dims, arr), ds, name, spec, var, who, arr)
                return dims, arr
            # a numeric ndarray is already what xarray would make of it: skip the conversion
            da = xr.Variable(dims, arr, fastpath=arr.dtype.kind in "iufb")
    except PluginFailure:
        raise
    except Exception as exc:
        raise PluginFailure(
            f"{var}: expected a DataArray or a (dims, data) pair with matching dims ({exc})",
            plugin=who,
            variable=name,
        ) from None
    declared = tuple(spec.dims)
    have = tuple(str(d) for d in da.dims)
    ds_sizes = ds.sizes
    sweep = {d for d in ds_sizes if d not in CORE_DIMS and d not in declared}
    missing = [d for d in declared if d not in have and not (d == "p0" and "p0" not in ds_sizes)]
    extra = [d for d in have if d not in declared and d not in sweep]
    if missing or extra:
        raise PluginFailure(
            f"{var} has dims {have}; declared {declared}"
            + (f" (missing {missing})" if missing else "")
            + (f" (undeclared {extra})" if extra else ""),
            plugin=who,
            variable=name,
        )
    sizes = dict(zip(have, da.shape, strict=True))
    wrong = [(d, sizes[d], ds_sizes[d]) for d in have if d in ds_sizes and sizes[d] != ds_sizes[d]]
    if wrong:
        d, got, want = wrong[0]
        raise PluginFailure(
            f"{var} has {got} entries along {d!r}; the Dataset has {want} (shape {da.shape} for "
            f"dims {have})",
            plugin=who,
            variable=name,
        )
    order = [d for d in have if d not in declared] + [d for d in declared if d in have]
    if tuple(order) != have:
        da = da.transpose(*order)
    _check_values(da, ds, name, spec, var, who)
    return da


class _VarName:
    """``"<plugin>: variable 'name'"`` for error messages, formatted only when one is raised."""

    __slots__ = ("who", "name")

    def __init__(self, who: object, name: str) -> None:
        self.who, self.name = who, name

    def __str__(self) -> str:
        return f"{self.who}: variable {self.name!r}"

    def __format__(self, spec: str) -> str:
        return format(str(self), spec)


class _Pair:
    """A checked ``(dims, data)`` pair's dims, as a Variable's (for an error message)."""

    __slots__ = ("dims",)

    def __init__(self, dims: tuple[str, ...], arr: np.ndarray) -> None:
        self.dims = dims


def _check_values(
    da: Any, ds: Any, name: str, spec: Any, var: Any, who: object, arr: Any = None
) -> None:
    """Finite values (NaN only with ``nan_meaning``) within ``valid_min`` / ``valid_max``:
    of ``arr``, else of ``da``'s values (``da``'s dims name them in a message)."""
    arr = np.asarray(da.values if arr is None else arr)
    kind = arr.dtype.kind
    if kind in "b":
        return
    if kind in "OUS":
        if spec.valid_min is not None or spec.valid_max is not None or spec.units != "1":
            raise PluginFailure(
                f"{var} has non-numeric dtype {arr.dtype}; expected numbers in {spec.units}",
                plugin=who,
                variable=name,
            )
        return
    if kind not in "iufc":
        raise PluginFailure(f"{var} has unsupported dtype {arr.dtype}", plugin=who, variable=name)
    if kind in "iuf" and (kind != "f" or spec.nan_meaning is None) and arr.size:
        if _within(arr, spec.valid_min, spec.valid_max):  # fast path, the same rule
            return
        # else: the detailed checks below find and quote the offending values

    def coords() -> dict[str, Any]:  # for the error message only (built when raising)
        return {
            "dims": tuple(da.dims),
            "values": {
                d: np.asarray(ds[d].values) for d in da.dims if d in ds.coords and ds[d].ndim == 1
            },
        }

    unit = "" if spec.units in ("1", "") else f" {spec.units}"
    if kind == "c":
        raise PluginFailure(f"{var} is complex; expected real values", plugin=who, variable=name)
    if kind == "f":
        inf = np.isinf(arr)
        nan = np.isnan(arr)
        bad = inf | (nan if spec.nan_meaning is None else np.zeros_like(nan))
        if bad.any():
            why = "" if spec.nan_meaning is None else " (NaN is allowed, inf is not)"
            raise PluginFailure(
                f"{var} has {int(bad.sum())} non-finite value(s){why}: "
                f"{quote(arr, bad, unit, coords())}",
                plugin=who,
                variable=name,
            )
    finite = np.isfinite(arr) if kind == "f" else np.ones(arr.shape, bool)
    for bound, op, word in (
        (spec.valid_min, np.less, "below valid_min"),
        (spec.valid_max, np.greater, "above valid_max"),
    ):
        if bound is None:
            continue
        out = finite & op(arr, bound)
        if out.any():
            raise PluginFailure(
                f"{var} has {int(out.sum())} value(s) {word} = {bound:g}{unit}: "
                f"{quote(arr, out, unit, coords())}",
                plugin=who,
                variable=name,
            )


@contextlib.contextmanager
def guard_dataset(ds: Any, who: object) -> Iterator[Any]:
    """Hand an analysis ``ds`` with read-only numpy buffers; catch it changing the Dataset.

    The buffers are read-only for the duration of the call, so an in-place write raises inside
    the plugin (and is attributed to it); replacing, deleting or adding a variable of the
    Dataset is reported as a :class:`PluginFailure` (the run stops, so the changed Dataset never
    reaches the user). No copy is made: the check compares the variable objects themselves.
    """
    before = dict(ds.variables)
    index_names = set(ds.xindexes)
    frozen = []
    for name, v in before.items():
        if name in index_names:  # pandas-backed: immutable, checked by identity below
            continue
        data = getattr(v, "_data", None)  # a numpy array as it is (``.data``: ~1 us a read)
        data = data if isinstance(data, np.ndarray) else v.data
        if isinstance(data, np.ndarray) and data.flags.writeable:
            data.flags.writeable = False
            frozen.append(data)
    try:
        yield ds
        after = ds.variables
        added = [n for n in after if n not in before]
        if added:
            raise PluginFailure(
                f"{who} added {added} to the Dataset it was handed; analyses must return new "
                f"variables (declared in their outputs), never modify the Dataset",
                plugin=who,
                variable=str(added[0]),
            )
        touched = [n for n, v in before.items() if after.get(n) is not v]
        if touched:  # name the variables whose values changed (xarray may rebuild others)
            changed = [
                n
                for n in touched
                if n not in after
                or not (
                    after[n].equals(before[n])
                    if n in index_names
                    else after[n].data is before[n].data
                )
            ]
            vname = (changed or touched)[0]
            raise PluginFailure(
                f"{who} replaced or removed the Dataset variable {vname!r}; analyses must "
                f"return new variables, never modify existing ones",
                plugin=who,
                variable=vname,
            )
    finally:
        # the arrays owning their memory first: numpy makes a view writable again only once
        # its owner is (a variable may be a view of another, e.g. ``mu_visc`` the last column
        # of ``mu_visc_cumulative``); a view whose owner is read-only elsewhere (a cached
        # value) stays read-only, as its memory is
        for data in sorted(frozen, key=lambda a: isinstance(a.base, np.ndarray)):
            with contextlib.suppress(ValueError):
                data.flags.writeable = True


def check_contributions(
    ds: Any, values: Any, specs: Mapping[str, Any], who: object
) -> dict[str, Any]:
    """Check a plugin's returned mapping ``{name: value}``; return ``{name: checked}``, each
    a DataArray, a Variable or a ``(dims, ndarray)`` pair (:func:`checked_variable`)."""
    if not isinstance(values, Mapping):
        raise PluginFailure(
            f"{who} returned {type(values).__name__}; expected a mapping "
            f"name -> DataArray or (dims, data)",
            plugin=who,
        )
    sizes = dict(ds.sizes)
    plain = _plain_pairs(values, specs, ds.variables, sizes)
    if plain is not None and _clean(
        [arr for _, arr in plain.values()],
        [(specs[n].valid_min, specs[n].valid_max) for n in plain],
    ):
        return plain  # every value the common case, and clean: the same pairs, one pass
    out = {}
    for name, value in values.items():  # in order: the first failure raises its own message
        if name not in specs:
            raise PluginFailure(
                f"{who} returned {name!r} without declaring it in its outputs "
                f"(declared: {sorted(specs)})",
                plugin=who,
                variable=str(name),
            )
        if name in ds.variables:
            raise PluginFailure(
                f"{who} returned {name!r}, which the Dataset already has (a "
                f"core or another plugin's variable); choose another name",
                plugin=who,
                variable=name,
            )
        out[name] = checked_variable(ds, name, value, specs[name], who, sizes)
    return out


def _plain_pairs(
    values: Mapping[str, Any],
    specs: Mapping[str, Any],
    have: Mapping[str, Any],
    sizes: Mapping[str, int],
) -> dict[str, tuple[tuple[str, ...], np.ndarray]] | None:
    """``{name: (dims, ndarray)}`` when every value of a contribution is the common case of
    :func:`checked_variable` (a ``(dims, data)`` pair of floats on exactly the declared dims
    and the Dataset's sizes, a declared name the Dataset lacks, NaN not allowed), else None.
    The dims are the declaration's own tuple (equal to the plugin's; checked once with the
    declaration, :class:`~xpersson.specs.VarSpec`)."""
    out = {}
    for name, value in values.items():
        spec = specs.get(name) if type(name) is str else None
        if spec is None or name in have or type(value) is not tuple or len(value) != 2:
            return None
        declared = spec.__dict__.get("_plain_dims")  # (None: NaN allowed, or unusual dims)
        dims, arr = value
        if type(dims) is not tuple:
            if isinstance(dims, str):
                dims = (dims,)
            else:
                try:
                    dims = tuple(dims)
                except TypeError:
                    return None
        if type(arr) is not np.ndarray:
            arr = np.asarray(arr)
        if (
            declared is None
            or arr.dtype.kind != "f"
            or dims != declared
            or arr.shape != tuple([sizes.get(d, -1) for d in declared])  # (also the ndim)
        ):
            return None
        out[name] = (declared, arr)
    return out


def _clean(arrays: list[np.ndarray], bounds: list[tuple[Any, Any]]) -> bool:
    """Whether every float array of ``arrays`` is finite and within its ``(valid_min,
    valid_max)`` of ``bounds`` (None: no bound): the rule of :func:`_check_values` on floats
    (:func:`_within`). The small arrays are reduced together: copied into one buffer whose
    per-array minima and maxima two ``reduceat`` calls give (NaN propagates, and a bound of
    None is the largest finite float, which +-inf fails, as ``isfinite`` does in
    :func:`_within`); the large ones one by one. False may also mean "not decided here" (an
    array that is not float64 or float32, a bound a float does not hold exactly): the caller
    then checks each array on its own, with its messages."""
    small: list[np.ndarray] = []
    lows: list[float] = []
    highs: list[float] = []
    starts: list[int] = []
    at = 0
    for arr, (vmin, vmax) in zip(arrays, bounds, strict=True):
        kind = arr.dtype
        if kind.kind != "f" or kind.itemsize > 8:
            return False
        n = arr.size
        if not n:
            continue
        if n > _ONE_PASS:
            if not _within(arr, vmin, vmax):
                return False
            continue
        lo = -_LARGEST if vmin is None else vmin if type(vmin) is float else _bound(vmin)
        hi = _LARGEST if vmax is None else vmax if type(vmax) is float else _bound(vmax)
        if lo is None or hi is None or lo != lo or hi != hi:  # (a NaN bound: not here)
            return False
        small.append(arr.ravel())
        lows.append(lo if lo > -_LARGEST else -_LARGEST)  # (-inf: the finite values)
        highs.append(hi if hi < _LARGEST else _LARGEST)
        starts.append(at)
        at += n
    if len(small) <= _FEW:  # a few: two reductions each, without the buffer's set-up
        return all(_within(a, lo, hi) for a, lo, hi in zip(small, lows, highs, strict=True))
    buf = np.concatenate(small)
    low = np.minimum.reduceat(buf, starts)
    high = np.maximum.reduceat(buf, starts)
    return bool((low >= lows).all()) and bool((high <= highs).all())


_FEW = 3
"""At most this many small arrays are reduced one by one (a buffer pays from about four)."""
_LARGEST = float(np.finfo(float).max)
"""The largest finite float64: a missing bound (every finite value is within it)."""


def _bound(value: Any) -> float | None:
    """A bound that is not a float as the float it compares as; None for one a float does not
    hold exactly (then the arrays are checked one by one)."""
    if type(value) is int and abs(value) <= 2**53:
        return float(value)
    return None


def _within(arr: np.ndarray, lo: float | None, hi: float | None) -> bool:
    """Whether every value of the numeric array ``arr`` is finite and within ``[lo, hi]``
    (None: no bound; an empty array: True), in two reductions and no temporaries: min and
    max propagate NaN, and +-inf shows in them."""
    if arr.size == 0:
        return True
    a_min, a_max = float(arr.min()), float(arr.max())
    return bool(
        math.isfinite(a_min)
        and math.isfinite(a_max)
        and (lo is None or a_min >= lo)
        and (hi is None or a_max <= hi)
    )


#: arrays of at most this many values are checked together (a copy of them into one buffer)
_ONE_PASS = 4096


# -- the engine's own outputs --------------------------------------------------------------------
#: admissible ranges of the core variables the engine fills (name -> (valid_min, valid_max))
CORE_RANGES: dict[str, tuple[float | None, float | None]] = {
    "area_fraction": (0.0, 1.0),
    "non_contact_fraction": (0.0, 1.0),
    "error_estimate": (0.0, None),
    "P": (0.0, None),
}


def check_core(ds: Any, who: object = "engine") -> dict[int, str]:
    """Check the engine's core outputs in ``ds`` (dims ``p0``, ...) per load.

    Same checks as for plugin outputs (:func:`_check_values`: finite, ``valid_min`` /
    ``valid_max``) against :data:`CORE_RANGES`. A load that fails gets ``solver_status``
    ``balance_violated`` (unless already not ``success``); the values are left as they are.

    Returns
    -------
    dict
        Load index -> message, for each failing load (empty when every load passes).
    """

    names = [n for n in CORE_RANGES if n in ds.variables]
    if all(_within(np.asarray(ds.variables[n].values), *CORE_RANGES[n]) for n in names):
        return {}
    import dataclasses

    from ..schema import CORE_VARIABLES

    messages: dict[int, str] = {}
    status = ds["solver_status"].values.copy()
    for i in range(ds.sizes["p0"]):
        for name in names:
            lo, hi = CORE_RANGES[name]
            spec = dataclasses.replace(CORE_VARIABLES[name], valid_min=lo, valid_max=hi)
            da = ds[name].isel(p0=i)
            try:
                _check_values(da, ds, name, spec, f"{who}: variable {name!r}", who)
            except PluginFailure as exc:
                messages[i] = f"core output check failed: {exc}"
                if status[i] == "success":
                    status[i] = "balance_violated"
                break
    ds["solver_status"].values = status
    return messages
