"""A run's Dataset before it is made (one job: build the Dataset once, in its final form).

A single-scene run adds its variables in steps (the core variables, the plugins' checked
outputs, the diagnostics, the model-error ancillaries) and, for one load, squeezes ``p0``.
Made as an :class:`xarray.Dataset` at the first step and changed at each, that meant an insert
per step and a second Dataset for the squeeze. A :class:`Draft` holds the same variables (plain
:class:`xarray.Variable` objects, in the Dataset's order), the dimension sizes and the
coordinate names, and answers what the pipeline's steps read of a Dataset (``variables``,
``sizes``, ``data_vars``, ``attrs``, ``name in``); :meth:`Draft.squeeze` drops a one-load
``p0`` (views: nothing is copied) and :meth:`Draft.dataset` makes the Dataset once.

The steps insert into it as into a Dataset (:func:`~xpersson.pipeline._insert.insert_direct`
reads the same four mappings); anything else a Dataset offers (an ``update`` that aligns, a
``ds[name]`` in an error message) makes the Dataset and reads or changes that, and the draft
takes its mappings back, so a rare path behaves exactly as on a Dataset.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
import xarray as xr

from ._insert import _DIRECT, cached_index, new_variable, values_of

__all__ = ["Draft"]


class Draft:
    """The variables, dimension sizes, indexes and coordinate names of a Dataset to be made.

    Parameters
    ----------
    variables : dict
        name -> :class:`xarray.Variable`, in the Dataset's order (kept, not copied).
    coord_names : set
        The names of ``variables`` that are coordinates.
    """

    __slots__ = ("_variables", "_dims", "_indexes", "_coord_names", "attrs")

    def __init__(self, variables: dict[str, xr.Variable], coord_names: set[str]) -> None:
        dims: dict[str, int] = {}
        seen: dict[tuple[str, ...], tuple[int, ...]] = {}  # dims -> shape (a run has ~5 kinds)
        for var in variables.values():  # (the slots: the properties cost ~0.4 us a read)
            if _DIRECT:
                key, shape = var._dims, var._data.shape  # noqa: SLF001
                if seen.get(key) != shape:  # (the dims of the same sizes: nothing new)
                    seen[key] = shape
                    dims.update(zip(key, shape, strict=True))
            else:  # pragma: no cover - an xarray whose Variable holds other state
                dims.update(zip(var.dims, var.shape, strict=True))
        self._variables, self._dims, self._coord_names = variables, dims, coord_names
        self._indexes: dict[str, Any] = {}  # made with the Dataset (new dims' by insert_direct)
        self.attrs: dict[str, Any] = {}

    @classmethod
    def of(cls, ds: xr.Dataset) -> Draft:
        """A draft over a Dataset's own mappings (read only: :meth:`dataset` copies them) and a
        copy of its attrs."""
        out = cls.__new__(cls)
        out._variables, out._dims = ds._variables, ds._dims  # noqa: SLF001 - see module doc
        out._indexes, out._coord_names = ds._indexes, ds._coord_names  # noqa: SLF001
        out.attrs = dict(ds.attrs)
        return out

    # -- what the pipeline's steps read of a Dataset -----------------------------------------
    @property
    def variables(self) -> Mapping[str, xr.Variable]:
        return self._variables

    @property
    def sizes(self) -> Mapping[str, int]:
        return self._dims

    dims = sizes

    @property
    def data_vars(self) -> set[str]:
        """The names of the data variables (a set: the steps only test membership)."""
        return self._variables.keys() - self._coord_names

    def __contains__(self, name: object) -> bool:
        return name in self._variables

    # -- anything else: on the Dataset, whose mappings the draft then takes back -------------
    def __getitem__(self, name: Any) -> Any:
        return self._on_dataset(lambda ds: ds[name])

    def __setitem__(self, name: Any, value: Any) -> None:
        self._on_dataset(lambda ds: ds.__setitem__(name, value))

    def update(self, other: Any) -> None:
        self._on_dataset(lambda ds: ds.update(other))

    def __getattr__(self, name: str) -> Any:  # e.g. ``coords`` in an error message
        if name.startswith("_"):  # a slot not set (a copy being made): not the Dataset's
            raise AttributeError(name)
        return self._on_dataset(lambda ds: getattr(ds, name))

    def _on_dataset(self, act: Any) -> Any:
        """``act(ds)`` on the Dataset of the draft, whose mappings (new ones, where ``act``
        replaced them, as ``Dataset.update`` does) the draft then takes back: what is done to
        the Dataset is done to the draft."""
        ds = self.dataset()
        try:
            return act(ds)
        finally:
            self._variables, self._dims = ds._variables, ds._dims  # noqa: SLF001 - module doc
            self._indexes, self._coord_names = ds._indexes, ds._coord_names  # noqa: SLF001
            self.attrs = ds.attrs

    # -- the Dataset ---------------------------------------------------------------------------
    def squeeze(self, own: bool = False) -> Draft:
        """Drop a one-load draft's ``p0`` dimension (as ``ds.isel(p0=0)``: every variable along
        it a view at ``p0 = 0``, ``p0`` a scalar coordinate without index), in place (the
        mappings are new: a draft :meth:`of` a Dataset leaves the Dataset as it is).

        ``own``: the variables are the draft's alone (a run's), so a squeezed one keeps its
        attrs and encoding dicts instead of copies (a Variable whose data is a numpy array with
        ``p0`` first is changed in place: its dims and data replaced)."""
        if own and _DIRECT:  # (the slots read directly: see __init__)
            self._variables = {
                name: _squeezed_own(var) if "p0" in var._dims else var  # noqa: SLF001
                for name, var in self._variables.items()
            }
        else:
            self._variables = {
                name: _squeezed(var, own) if "p0" in var.dims else var
                for name, var in self._variables.items()
            }
        self._dims = {d: n for d, n in self._dims.items() if d != "p0"}
        self._indexes = {k: v for k, v in self._indexes.items() if k != "p0"}
        return self

    def dataset(self) -> xr.Dataset:
        """The Dataset, made once: every dimension coordinate with its pandas index (shared
        between solves of equal values, :func:`~xpersson.pipeline._insert.cached_index`)."""
        from xarray.core.indexes import PandasIndex

        variables, indexes = dict(self._variables), dict(self._indexes)
        coords = self._coord_names
        for name, var in self._variables.items():  # in order: the indexes' order is kept
            if name in coords and var.dims == (name,) and name not in indexes:
                indexes[name], variables[name] = cached_index(PandasIndex, name, var)
        return xr.Dataset._construct_direct(  # noqa: SLF001 - one set of dims: nothing to align
            variables, set(self._coord_names), dict(self._dims), self.attrs, indexes
        )


def _squeezed_own(var: xr.Variable) -> xr.Variable:
    """:func:`_squeezed` of a Variable the draft owns (xarray's slots as :data:`_DIRECT`
    expects them): one whose data is a numpy array with
    ``p0`` first and whose view at ``p0 = 0`` is an array or a numpy scalar is changed in place
    (dims and data; the same attrs and encoding: what ``_squeezed(var, own=True)`` makes,
    without a new object); any other through :func:`_squeezed`."""
    dims, raw = var._dims, var._data  # noqa: SLF001 - see the module docstring
    if type(raw) is np.ndarray and dims[0] == "p0" and type(var) is xr.Variable:
        data = raw[0]
        if type(data) is np.ndarray or isinstance(data, np.generic):
            var._dims, var._data = dims[1:], data  # noqa: SLF001
            return var
    return _squeezed(var, True)


def _squeezed(var: xr.Variable, own: bool) -> xr.Variable:
    """``var`` at ``p0 = 0``, without that dimension: a view of its data (basic indexing)
    with copies of its attrs and encoding (as ``isel`` gives them; ``own``: its own dicts)."""
    dims = var._dims  # noqa: SLF001 - a tuple (the constructor's)
    raw = var._data  # noqa: SLF001 - a numpy array: indexed as it is (no conversion)
    if type(raw) is not np.ndarray:
        raw = np.asarray(values_of(var))
    if dims[0] == "p0":  # the common case: raw[0] is raw[0, ...]
        dims, data = dims[1:], raw[0]
    else:
        axis = dims.index("p0")
        dims, data = dims[:axis] + dims[axis + 1 :], raw[(slice(None),) * axis + (0,)]
    if type(data) is np.ndarray or isinstance(data, np.generic):  # a view, or a numpy scalar
        if own:
            return new_variable(dims, data, var._attrs, var._encoding)  # noqa: SLF001
        return new_variable(dims, data, dict(var.attrs), dict(var.encoding))
    # a Python object (an object array's): converted as xarray would, without its probe of
    data = np.asarray(data)  # dask, which imports dask.array
    return xr.Variable(dims, data, var.attrs, var.encoding, fastpath=data.dtype.kind not in "OMm")
