"""An in-memory sweep's arrays filled block by block, as the blocks arrive.

Each block's Dataset is copied into preallocated arrays of the sweep's shape and dropped at once,
so the peak memory of a sweep is its result plus the blocks in flight (the blocks a scheduler
has sent back, one block's intermediate arrays), not the result twice over (every block kept,
then a combined copy).

Where the blocks do not fit one layout (other variables, other non-sweep coordinates, another
dtype, a sweep dimension that does not lead a variable in the order of the sweep) the blocks
taken so far are cut back out of the arrays (exactly the values they brought) and the caller
joins the Datasets with :func:`xarray.combine_nested` (:func:`.combine.combine`).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import xarray as xr

from ..pipeline import direct_dataset
from .stacking import BlockResult, _point_shaped, variable

__all__ = ["Filling", "region_rows", "same_memory", "sweep_region"]


class Filling:
    """The sweep's variables as preallocated arrays, filled by :meth:`add`.

    Parameters
    ----------
    plan : SweepPlan
        The sweep (its dimensions and shape).

    Attributes
    ----------
    absorbed : list of BlockResult
        The results whose Datasets were copied in (their ``dataset`` is ``None`` since).
    template : xarray.Dataset or None
        The lowest-numbered absorbed block's Dataset cut to one point (coordinates and
        attributes for blocks where every point failed, and the sweep's global attributes).
    """

    def __init__(self, plan: Any) -> None:
        self.dims, self.shape = tuple(plan.dims), tuple(plan.shape)
        self.absorbed: list[BlockResult] = []
        self.template: xr.Dataset | None = None
        self._number = -1
        self._vars: dict[str, Any] = {}  # name -> ("const", Variable) | ("swept", ...)
        self._order: list[str] = []
        self._coords: set[str] = set()
        self.broken = False
        self._rows: dict[str, np.ndarray] = {}  # name -> the row every point holds (prepare)
        #: name -> an array of the sweep's shape (then the point's) that batched blocks write
        #: their rows into (:meth:`rows`); adopted by the fill, whose copy is then skipped
        self.sink: dict[str, np.ndarray] = {}
        #: name -> the row every point added so far holds, where the blocks brought it as one
        #: repeated row (a view: :func:`repeated`) and its array was not written (its pages
        #: never touched); written out (:meth:`_write_out`) when a block brings other values
        self._repeat: dict[str, np.ndarray] = {}
        self._kept: dict[str, Any] = {}  # name -> (Variable, array, axes) after restore

    def rows(self, name: str, block: Any, point_shape: tuple[int, ...], dtype: Any) -> Any:
        """A writable ``(block.size, *point_shape)`` view of the sweep's array of ``name`` for
        a block's rows (``None`` where the block's region of it is not one contiguous run):
        rows written there are in place, :meth:`add` does not copy them again."""
        if self._vars:  # the fill's own arrays: written where their layout is the sweep's
            entry = self._vars.get(name)
            if entry is None or entry[0] != "swept" or entry[4] != list(range(len(self.shape))):
                return None
            self._write_out(name)  # the block writes its rows there: the array holds values
            return region_rows(self._vars[name][2], block, point_shape, dtype)
        full = self.sink.get(name)
        if full is None or full.dtype != dtype or full.shape[len(self.shape) :] != point_shape:
            full = self.sink[name] = np.empty(self.shape + tuple(point_shape), dtype)
        return region_rows(full, block, point_shape, dtype)

    def reserve(self, specs: dict[str, tuple[tuple[int, ...], Any]]) -> None:
        """Make the sweep's arrays of the variables ``specs`` names (name -> (point shape,
        dtype)) that :meth:`rows` would make one by one, together (:func:`empty_arrays`)."""
        if self._vars:
            return
        need = {}
        for name, (point_shape, dtype) in specs.items():
            full = self.sink.get(name)
            if (
                full is None
                or full.dtype != dtype
                or full.shape[len(self.shape) :] != tuple(point_shape)
            ):
                need[name] = (self.shape + tuple(point_shape), dtype)
        self.sink.update(empty_arrays(need))

    def prepare(self, ds: xr.Dataset, rows: dict[str, np.ndarray] | None = None) -> bool:
        """The arrays laid out from a block's Dataset ``ds`` (the probe's) before any block is
        added (the :attr:`sink` arrays adopted): blocks may then arrive without the variables
        written into them in place, or without those whose every point holds ``rows[name]``
        (:meth:`add`'s ``written``)."""
        self._rows = dict(rows or {})
        if not self._vars and not self._allocate(ds):
            self.broken = True
        return not self.broken

    def add(self, res: BlockResult, written: Any = ()) -> None:
        """Copy a block's Dataset in and drop it from ``res`` (nothing when it has none);
        ``written``: the variables its worker dropped, as written into the :attr:`sink` arrays
        (a list, or ``{name: "shm"}``) or as holding at every point the row given to
        :meth:`prepare` (``{name: "same"}``: filled in here from it)."""
        ds = res.dataset
        if ds is None:
            return
        if self.broken or (not self._vars and not self._allocate(ds, repeats=not written)):
            self.broken = True
            if written:  # its worker dropped them for the arrays: back into its Dataset
                res.dataset = self._rejoined(ds, res.block, written)
            return
        if not self._fits(ds, written):
            res.dataset = self._whole(ds, res.block, written, copy=True)
            self.restore()
            return
        sl = sweep_region(res.block)
        for name, entry in self._vars.items():
            if entry[0] == "swept":
                _, _, full, filled, axes = entry
                sub = tuple(sl[a] for a in axes)
                if name in self._repeat and not (
                    name not in written and _same_row(ds.variables[name], axes, self._repeat[name])
                ):
                    self._write_out(name)
                full = self._vars[name][2]
                if name in self._repeat:  # this block holds the row again: nothing written
                    pass
                elif name not in written:
                    src, dst = ds.variables[name].values, full[sub]
                    if not same_memory(src, dst):  # rows written in place (:meth:`rows`): kept
                        dst[...] = src
                elif isinstance(written, dict) and written[name] == "same":
                    full[sub] = self._rows[name]
                filled[sub] = True
        if self.template is None or res.block.number < self._number:
            whole = self._whole(ds, res.block, written)
            self.template, self._number = _point_shaped(whole, res.block), res.block.number
        res.dataset = None
        self.absorbed.append(res)

    def _whole(self, ds: xr.Dataset, block: Any, written: Any, copy: bool = False) -> xr.Dataset:
        """A block's Dataset with the variables its worker dropped back (views of the arrays,
        or copies; rows every point holds: broadcast from it)."""
        if not written:
            return ds
        sl = sweep_region(block)
        back = {}
        for name in written:
            self._write_out(name)
            _, ref, full, _, axes = self._vars[name]
            part = full[tuple(sl[a] for a in axes)]
            if isinstance(written, dict) and written[name] == "same":
                part = np.broadcast_to(self._rows[name], part.shape).copy()
            elif copy:
                part = part.copy()
            back[name] = variable(ref.dims, part, dict(ref.attrs))
        return ds.assign(back)[[n for n in self._order if n in ds or n in back]]

    def _write_out(self, name: str) -> None:
        """Write the repeated row of ``name`` into its array (made now if it has none) at the
        points filled so far (the others are written by their blocks)."""
        row = self._repeat.pop(name, None)
        if row is not None:
            kind, ref, full, filled, axes = self._vars[name]
            if full is None:
                full = np.empty(self._shape_of(name), dtype=ref.dtype)
                self._vars[name] = (kind, ref, full, filled, axes)
            full[filled] = row

    def _shape_of(self, name: str) -> tuple[int, ...]:
        """The shape of the sweep's array of a swept variable."""
        _, ref, _, _, axes = self._vars[name]
        return tuple(self.shape[a] for a in axes) + ref.shape[len(axes) :]

    def _allocate(self, ds: xr.Dataset, repeats: bool = False) -> bool:
        """The arrays from the first block's layout; ``False`` where it does not fit one.
        ``repeats``: a variable the block holds as one repeated row (:func:`repeated`) keeps
        that row instead of an array (:attr:`_repeat`; made by :meth:`_write_out`); the new
        arrays are made together (:func:`empty_arrays`)."""
        need: dict[str, tuple[tuple[int, ...], Any]] = {}
        for name, var in ds.variables.items():
            swept = [d for d in var.dims if d in self.dims]
            if not swept:
                self._vars[name] = ("const", var.copy(deep=False))
                continue
            k = len(swept)
            if tuple(var.dims[:k]) != tuple(swept) or swept != [d for d in self.dims if d in swept]:
                return False
            axes = [self.dims.index(d) for d in swept]
            shape = tuple(self.shape[a] for a in axes) + var.shape[k:]
            full = self.sink.get(name)
            whole = axes == list(range(len(self.shape)))  # every sweep dim, in order
            row = repeated(var, k) if repeats else None
            fits = full is not None and full.dtype == var.dtype and full.size == math.prod(shape)
            if whole and fits:
                full = full.reshape(shape)  # the rows batched blocks wrote (a view)
            elif row is not None:
                full = None  # one row so far: no array
            else:
                need[name] = (shape, var.dtype)
            filled = np.zeros(shape[:k], dtype=bool)
            self._vars[name] = ("swept", var, full, filled, axes)
            if row is not None:
                self._repeat[name] = row
        for name, full in empty_arrays(need).items():
            self._vars[name] = self._vars[name][:2] + (full,) + self._vars[name][3:]
        self._order = list(ds.data_vars)
        self._coords = set(ds.coords)
        return True

    def _fits(self, ds: xr.Dataset, written: Any = ()) -> bool:
        """Whether a block has the first block's variables, dims, dtypes and constants
        (``written``: variables its worker wrote into the arrays, not in ``ds``)."""
        if set(ds.variables).union(written) != set(self._vars) or any(
            self._vars[n][0] != "swept" or n in ds.variables for n in written
        ):
            return False
        for name, entry in self._vars.items():
            if name in written:
                continue
            var, ref = ds.variables[name], entry[1]
            if var.dims != ref.dims or var.dtype != ref.dtype:
                return False
            if entry[0] == "const":
                values = ref.values
                if not np.array_equal(var.values, values, equal_nan=values.dtype.kind in "fc"):
                    return False
            elif var.shape[len(entry[4]) :] != ref.shape[len(entry[4]) :]:
                return False
        return True

    def _rejoined(self, ds: xr.Dataset, block: Any, written: Any) -> xr.Dataset:
        """A block's Dataset with the variables its worker wrote into the arrays (or found the
        same at every point) put back, once the fill has stopped (:meth:`restore`): before,
        a block arriving then lost them, and a sweep on worker processes held NaN for its
        points (fuzz.py --sweeps --parallel processes, 2026-12-01)."""
        sl = sweep_region(block)
        back = {}
        for name in written:
            got = self._kept.get(name)
            if got is None:
                raise RuntimeError(
                    f"sweep: block {block.number}'s {name!r} was written into the shared "
                    "arrays before the fill knew it; solve again without a scheduler"
                )
            ref, full, axes = got
            if isinstance(written, dict) and written[name] == "same":
                part = np.broadcast_to(self._rows[name], full[tuple(sl[a] for a in axes)].shape)
            else:
                part = full[tuple(sl[a] for a in axes)]
            back[name] = variable(ref.dims, part.copy(), dict(ref.attrs))
        return ds.assign(back)

    def restore(self) -> None:
        """Give the absorbed results their Datasets back (cut from the arrays) and stop."""
        for name in list(self._repeat):
            self._write_out(name)
        self._kept = {  # the swept arrays, for blocks that arrive after (:meth:`_rejoined`)
            name: (e[1], e[2], e[4]) for name, e in self._vars.items() if e[0] == "swept"
        }
        for res in self.absorbed:
            sl = sweep_region(res.block)
            variables = {}
            for name, entry in self._vars.items():
                if entry[0] == "const":
                    variables[name] = entry[1]
                else:
                    _, ref, full, _, axes = entry
                    part = full[tuple(sl[a] for a in axes)].copy()
                    variables[name] = variable(ref.dims, part, dict(ref.attrs))
            res.dataset = self._dataset(variables, {} if self.template is None else self.template)
        self.absorbed, self._vars, self.broken, self._repeat = [], {}, True, {}

    def _dataset(self, variables: dict[str, Any], attrs: Any) -> xr.Dataset:
        attrs = dict(getattr(attrs, "attrs", attrs))
        ds = direct_dataset(  # the first block's order, without xarray's merge
            {n: variables[n] for n in self._order},
            {n: v for n, v in variables.items() if n in self._coords},
            attrs,
        )
        if ds is not None:
            return ds
        ds = xr.Dataset(  # pragma: no cover - other xarray versions
            {n: v for n, v in variables.items() if n not in self._coords},
            coords={n: v for n, v in variables.items() if n in self._coords},
            attrs=attrs,
        )
        return ds[self._order]  # pragma: no cover

    def _values(self, name: str) -> np.ndarray:
        """The sweep's array of ``name``: a read-only view of its repeated row, if it is one
        (as the engine's exact zeros are in a plain solve), else the array."""
        row = self._repeat.get(name)
        if row is None:
            return self._vars[name][2]
        return np.broadcast_to(row, self._shape_of(name))

    def dataset(self) -> xr.Dataset | None:
        """The sweep's Dataset, or ``None`` (the blocks did not fit one layout, or a point was
        never filled: the absorbed results have their Datasets back)."""
        if self.broken or not self._vars:
            return None
        if not all(e[3].all() for e in self._vars.values() if e[0] == "swept"):
            self.restore()
            return None
        variables = {
            name: entry[1]
            if entry[0] == "const"
            else variable(entry[1].dims, self._values(name), dict(entry[1].attrs))
            for name, entry in self._vars.items()
        }
        return self._dataset(variables, self.template)


def empty_arrays(specs: dict[str, tuple[tuple[int, ...], Any]]) -> dict[str, np.ndarray]:
    """Empty arrays of these shapes and dtypes, the numeric ones views of one buffer.

    One allocation instead of one per array: numpy asks the system for huge pages for a
    buffer of 4 MiB or more (``madvise``), so a sweep's arrays are first written with a page
    fault per 2 MiB rather than per 4 KiB page (an E x H sweep of 1e4 points: 24 MB of rows,
    about 6000 faults or 12 ms on a virtual machine). The arrays then live as long as the
    last of them (a variable dropped from the result frees its memory with the others).
    """
    out: dict[str, np.ndarray] = {}
    offsets: dict[str, int] = {}
    total = 0
    for name, (shape, dtype) in specs.items():
        dtype = np.dtype(dtype)
        if dtype.kind not in "biuf":
            out[name] = np.empty(shape, dtype)
            continue
        offsets[name] = total = -(-total // 64) * 64  # aligned for any numeric dtype
        total += math.prod(shape) * dtype.itemsize
    buffer = np.empty(total, np.uint8)
    for name, start in offsets.items():
        shape, dtype = specs[name]
        size = math.prod(shape) * np.dtype(dtype).itemsize
        out[name] = buffer[start : start + size].view(dtype).reshape(shape)
    return out


def repeated(var: xr.Variable, k: int) -> np.ndarray | None:
    """The row of a block's numeric variable (``k`` leading sweep dimensions, more than one
    point) that is one row repeated as a view (stride 0 along those dimensions), or ``None``."""
    values = var.values
    if values.dtype.kind not in "biuf" or math.prod(values.shape[:k]) < 2:
        return None
    if any(n > 1 and st != 0 for n, st in zip(values.shape[:k], values.strides[:k], strict=True)):
        return None
    return values[(0,) * k + (...,)]


def _same_row(var: xr.Variable, axes: list[int], row: np.ndarray) -> bool:
    """Whether a block's variable is ``row`` repeated (:func:`repeated`), bit for bit."""
    got = repeated(var, len(axes))
    if got is None or got.shape != row.shape or got.dtype != row.dtype:
        return False
    return np.ascontiguousarray(got).tobytes() == np.ascontiguousarray(row).tobytes()


def sweep_region(block: Any) -> tuple[slice, ...]:
    """A block's region of the sweep grid."""
    return tuple(slice(a, b) for a, b in zip(block.start, block.stop, strict=True))


def region_rows(
    full: np.ndarray, block: Any, point_shape: tuple[int, ...], dtype: Any
) -> np.ndarray | None:
    """The writable ``(block.size, *point_shape)`` view of a block's region of ``full`` (an
    array of the sweep's shape, then the point's), or ``None`` (another dtype or point size,
    or not one contiguous run)."""
    ndim = len(block.start)
    if full.dtype != dtype or math.prod(full.shape[ndim:]) != math.prod(point_shape):
        return None
    region = full[sweep_region(block)]
    if not region.flags.c_contiguous:
        return None
    return region.reshape((block.size, *point_shape))


def same_memory(a: np.ndarray, b: np.ndarray) -> bool:
    """Whether two arrays are the same values in memory (same start, shape and strides)."""
    a, b = np.asarray(a), np.asarray(b)
    return (
        a.shape == b.shape
        and a.dtype == b.dtype
        and a.strides == b.strides
        and a.__array_interface__["data"][0] == b.__array_interface__["data"][0]
    )
