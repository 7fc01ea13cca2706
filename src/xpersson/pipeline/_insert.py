"""Adding variables to a Dataset without xarray's merge (one job: the pipeline's fast insert).

``Dataset.update`` and ``__setitem__`` merge and align every variable of the Dataset (~1 ms a
variable); a contribution that has nothing to align (its dims are the Dataset's, or new ones
that carry their own dimension coordinate) goes in as those methods end. Used by the assembly
(plugin outputs) and by the diagnostics (``theory_validity``, the P checks).
"""

from __future__ import annotations

import copy
from collections.abc import Mapping
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from ..cache import Cache

__all__ = [
    "cached_index",
    "direct_dataset",
    "insert_direct",
    "insert_or_set",
    "nan_meaning",
    "new_variable",
    "values_of",
]


def _slots(cls: type) -> set[str]:
    return {s for c in cls.__mro__ for s in getattr(c, "__slots__", ())}


#: The Variable's state is these four slots (xarray 2023.x to 2026.x): :func:`new_variable` sets
#: them directly; on an xarray whose Variable holds anything else it calls the constructor.
_DIRECT = _slots(xr.Variable) == {"_dims", "_data", "_attrs", "_encoding"}


def new_variable(
    dims: tuple[str, ...],
    data: np.ndarray,
    attrs: dict[str, Any] | None = None,
    encoding: dict[str, Any] | None = None,
) -> xr.Variable:
    """``xr.Variable(dims, data, attrs, encoding, fastpath=True)`` of a numpy array (or a numpy
    scalar, kept as it is, as that constructor keeps it), without the constructor's checks
    (about 0.3 us instead of 3.5: a solve makes some 50 of them).

    ``attrs`` and ``encoding`` are taken as they are (the constructor copies them: pass a dict
    of the caller's own); ``dims`` must be a tuple of ``data.ndim`` names (a
    ``ValueError`` otherwise, as the constructor raises).
    """
    numpy = type(data) is np.ndarray or isinstance(data, np.generic)
    if not (_DIRECT and numpy and type(dims) is tuple):
        return xr.Variable(dims, data, attrs, encoding, fastpath=True)
    if len(dims) != data.ndim:
        raise ValueError(f"dimensions {dims} must have the same length as {data.ndim}")
    var = object.__new__(xr.Variable)
    var._dims, var._data = dims, data  # noqa: SLF001 - see the docstring
    var._attrs, var._encoding = attrs, encoding  # noqa: SLF001
    return var


def values_of(var: xr.Variable) -> np.ndarray:
    """``var.values`` of a Variable; of an index variable (a dimension coordinate) read from
    its pandas index directly (the same array, without xarray's conversion: ~11 us a read)."""
    data = getattr(var, "_data", None)
    index = getattr(data, "array", None)
    if isinstance(index, pd.Index) and type(index) is pd.Index and index.dtype.kind in "fiu":
        out = np.asarray(index)
        if out.dtype == var.dtype:
            return out
    return var.values


_INDEXES = Cache(
    "pipeline.coord_index",
    scope="process",
    maxsize=64,
    doc="pandas index and index variable of a dimension coordinate, by name, values, attrs",
)


def cached_index(cls: Any, name: str, var: xr.Variable) -> tuple[Any, xr.Variable]:
    """The index of a dimension coordinate and its index variable, reused for equal values.

    Solves of one scene share their zeta / q_psd (and often p0) coordinates; the pandas index
    is immutable, so Datasets may share it (as ``isel`` and ``copy`` do). The variable is a
    fresh shallow copy carrying ``var``'s attrs (which the index does not depend on: they are
    not part of the key; the encoding, which the variable keeps, is).
    """
    kind = _KINDS.get(cls)
    if kind is None:
        kind = _KINDS[cls] = f"{cls.__module__}.{cls.__qualname__}"  # a string keys fastest
    encoding = var._encoding or None  # noqa: SLF001 - a read: the encoding is rarely set

    def compute() -> tuple[Any, xr.Variable]:
        values = np.asarray(var.values)
        if values.dtype.kind in "fiu" and values.dtype.itemsize > 2 and var.dims == (name,):
            # a pandas Index given: no duck-array probes (they import dask, pint, ...: ~0.3 s
            index = cls(pd.Index(values), name, coord_dtype=var.dtype)  # of a first solve)
        else:
            index = cls.from_variables({name: var}, options={})
        return index, index.create_variables({name: var})[name]

    index, variable = _INDEXES.get((kind, name, values_of(var), encoding), compute)
    return index, _shallow_copy(variable, dict(var.attrs))


_KINDS: dict[type, str] = {}
#: Variable classes whose state is the four slots of :data:`_DIRECT`.
_PLAIN_SLOTS = {c for c in (xr.Variable, xr.IndexVariable) if _slots(c) == _slots(xr.Variable)}


def _shallow_copy(var: xr.Variable, attrs: dict[str, Any]) -> xr.Variable:
    """``var.copy(deep=False)`` with ``attrs`` (the same data object; the encoding copied)."""
    if not (_DIRECT and type(var) in _PLAIN_SLOTS):
        out = var.copy(deep=False)
        out.attrs = attrs
        return out
    out = object.__new__(type(var))
    out._dims, out._data = var._dims, var._data  # noqa: SLF001 - see new_variable
    out._attrs, out._encoding = attrs, copy.copy(var._encoding)  # noqa: SLF001
    return out


def direct_dataset(
    variables: Mapping[str, xr.Variable],
    coords: Mapping[str, xr.Variable],
    attrs: Mapping[str, Any] | None = None,
) -> xr.Dataset | None:
    """``xr.Dataset(variables, coords=coords, attrs=attrs)`` without xarray's merge, for
    variables and coordinates that share one set of dimensions (nothing to align): each
    dimension coordinate gets its pandas index (:func:`cached_index`); the variables in the
    order ``xr.Dataset`` gives them (data variables, then coordinates). ``None`` on an xarray
    without the direct constructor (the caller then builds it with ``xr.Dataset``)."""
    try:
        from xarray.core.indexes import PandasIndex

        cvars = dict(coords)
        indexes = {}
        for name, var in cvars.items():
            if var.dims == (name,):
                indexes[name], cvars[name] = cached_index(PandasIndex, name, var)
        dims: dict[str, int] = {}
        for var in (*variables.values(), *cvars.values()):
            dims.update(zip(var.dims, var.shape, strict=True))
        return xr.Dataset._construct_direct(  # noqa: SLF001 - see docstring
            {**variables, **cvars}, set(cvars), dims, dict(attrs or {}), indexes
        )
    except (AttributeError, TypeError, ImportError):  # pragma: no cover - other xarray versions
        return None


def insert_direct(ds: xr.Dataset, checked: Mapping[str, Any], aligned: bool = False) -> bool:
    """Insert checked variables whose dims the Dataset already has, or whose new dims carry
    their own dimension coordinate (e.g. ``gap_pdf`` on ``u``).

    Such an insertion has nothing to align (:func:`xpersson.checks.checked_variable` has
    checked the dims and sizes against ``ds``): the variables, and a new dimension's coordinate
    with its index, go into the Dataset as they are, which is what ``ds.update`` ends with,
    without its merge and alignment of every variable. Returns False (nothing inserted) when a
    variable carries any other coordinate, a new dimension without one or of conflicting
    sizes, or on an xarray without the internal mappings; :meth:`xarray.Dataset.update` then
    does the work. ``aligned``: every value is a Variable on the Dataset's own dimensions with
    its sizes (checked by the caller): nothing to look for.
    """
    parts = [getattr(ds, a, None) for a in ("_variables", "_dims", "_indexes", "_coord_names")]
    if not all(isinstance(p, dict | set) for p in parts):  # pragma: no cover - other xarray
        return False
    variables, dims, indexes, coord_names = parts
    new = {} if aligned else _new_coords(ds, checked, dims)
    if new is None:
        return False
    if new:
        try:
            from xarray.core.indexes import PandasIndex
        except ImportError:  # pragma: no cover - other xarray versions
            return False
        for name, var in new.items():
            indexes[name], variables[name] = cached_index(PandasIndex, name, var)
            coord_names.add(name)
            dims[name] = var.shape[0]
    for name, da in checked.items():
        variables[name] = getattr(da, "variable", da)  # DataArray -> its Variable
    return True


def _new_coords(
    ds: xr.Dataset, checked: Mapping[str, Any], sizes: Mapping[str, int]
) -> dict[str, xr.Variable] | None:
    """The new dimensions' coordinates of ``checked`` (see :func:`insert_direct`; ``sizes``:
    the Dataset's dimension sizes), or None when the contribution needs
    :meth:`xarray.Dataset.update`."""
    new: dict[str, xr.Variable] = {}
    for da in checked.values():
        coords = {} if isinstance(da, xr.Variable) else da.coords
        for c in coords:
            var = coords[c].variable
            if c in sizes or c in ds.variables or c in checked or var.dims != (c,):
                return None  # an existing dim's coordinate, or not a dimension coordinate
            if c in new and not new[c].identical(var):
                return None
            new[c] = var
        for d, n in zip(da.dims, da.shape, strict=True):
            if sizes.get(d, n) != n or (d not in sizes and d not in coords):
                return None
    return new


def insert_or_set(ds: xr.Dataset, new: Mapping[str, xr.Variable], aligned: bool = False) -> None:
    """Add ``new`` by :func:`insert_direct`; a name the Dataset already has (a variable
    replaced), or a contribution that needs alignment, goes through ``Dataset.__setitem__``.
    ``aligned``: every variable of ``new`` is on the Dataset's own dimensions with its sizes
    (:func:`insert_direct`)."""
    have = ds.variables
    fresh = {k: v for k, v in new.items() if k not in have}
    if not (fresh and insert_direct(ds, fresh, aligned=aligned)):
        fresh = {}
    for name, value in new.items():
        if name not in fresh:
            ds[name] = value


def nan_meaning(name: str) -> str:
    """The sentence of a model-error band's ``comment`` that says what its NaN means (CF: every
    NaN documented)."""
    return (
        f"NaN means: {name}_model_error_status is not_verified (the campaign did not cover "
        f"this regime) or {name} is NaN there"
    )
