"""Adding variables to a Dataset without xarray's merge (one job: the pipeline's fast insert).

``Dataset.update`` and ``__setitem__`` merge and align every variable of the Dataset (~1 ms a
variable); a contribution that has nothing to align (its dims are the Dataset's, or new ones
that carry their own dimension coordinate) goes in as those methods end. Used by the assembly
(plugin outputs) and by the diagnostics (``theory_validity``, the P checks).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from ..cache import Cache

__all__ = ["cached_index", "direct_dataset", "insert_direct", "insert_or_set", "values_of"]


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
    fresh shallow copy carrying ``var``'s attrs.
    """
    attrs = tuple(sorted((k, str(v)) for k, v in var.attrs.items()))
    kind = f"{cls.__module__}.{cls.__qualname__}"  # the class by name (a string keys fastest)

    def compute() -> tuple[Any, xr.Variable]:
        values = np.asarray(var.values)
        if values.dtype.kind in "fiu" and values.dtype.itemsize > 2 and var.dims == (name,):
            # a pandas Index given: no duck-array probes (they import dask, pint, ...: ~0.3 s
            index = cls(pd.Index(values), name, coord_dtype=var.dtype)  # of a first solve)
        else:
            index = cls.from_variables({name: var}, options={})
        return index, index.create_variables({name: var})[name]

    index, variable = _INDEXES.get((kind, name, np.asarray(var.values), attrs), compute)
    out = variable.copy(deep=False)
    out.attrs = dict(var.attrs)
    return index, out


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


def insert_direct(ds: xr.Dataset, checked: Mapping[str, Any]) -> bool:
    """Insert checked variables whose dims the Dataset already has, or whose new dims carry
    their own dimension coordinate (e.g. ``gap_pdf`` on ``u``).

    Such an insertion has nothing to align (:func:`xpersson.checks.checked_variable` has
    checked the dims and sizes against ``ds``): the variables, and a new dimension's coordinate
    with its index, go into the Dataset as they are, which is what ``ds.update`` ends with,
    without its merge and alignment of every variable. Returns False (nothing inserted) when a
    variable carries any other coordinate, a new dimension without one or of conflicting
    sizes, or on an xarray without the internal mappings; :meth:`xarray.Dataset.update` then
    does the work.
    """
    parts = [getattr(ds, a, None) for a in ("_variables", "_dims", "_indexes", "_coord_names")]
    if not all(isinstance(p, dict | set) for p in parts):  # pragma: no cover - other xarray
        return False
    variables, dims, indexes, coord_names = parts
    new = _new_coords(ds, checked, dims)
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


def insert_or_set(ds: xr.Dataset, new: Mapping[str, xr.Variable]) -> None:
    """Add ``new`` by :func:`insert_direct`; a name the Dataset already has (a variable
    replaced), or a contribution that needs alignment, goes through ``Dataset.__setitem__``."""
    fresh = {k: v for k, v in new.items() if k not in ds.variables}
    if not (fresh and insert_direct(ds, fresh)):
        fresh = {}
    for name, value in new.items():
        if name not in fresh:
            ds[name] = value
