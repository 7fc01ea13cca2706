"""Checks of everything a plugin hands to the pipeline, and attribution of plugin exceptions.

Every plugin contribution is checked before it enters a Dataset: declared name, dims and
sizes, finite values (NaN only where the :class:`~xpersson.plugins.VarSpec` documents its
meaning with ``nan_meaning``; ``inf`` never) and the declared ``valid_min`` / ``valid_max``.
Coefficient arrays, walls and spectra are checked the same way. A violation, or an exception
raised inside a plugin, becomes a :class:`PluginFailure` naming the plugin, its distribution,
the call or variable and the offending values.
"""

from __future__ import annotations

import contextlib
import functools
import math
import weakref
from collections.abc import Iterator, Mapping
from typing import Any

import numpy as np

__all__ = [
    "PluginFailure",
    "plugin_label",
    "calling",
    "check_array",
    "check_spectrum",
    "check_walls",
    "checked_variable",
    "guard_dataset",
]

#: Dimensions the core owns; any other Dataset dimension is a sweep (or plugin) dimension.
CORE_DIMS = ("p0", "zeta", "p", "q_psd")
_SHOW = 3  # offending values quoted in a message


class PluginFailure(RuntimeError):
    """A plugin raised, or returned output that violates its declaration.

    When it wraps an exception raised inside a plugin, the instance is also an instance of
    that exception's class (``except ValueError`` still catches a plugin's ``ValueError``),
    with a message naming the plugin.

    Attributes
    ----------
    plugin : str
        Label of the plugin (group, registered name, distribution and version).
    variable : str or None
        The variable or call at fault.
    """

    def __init__(self, message: str, *, plugin: Any = "", variable: str | None = None) -> None:
        super().__init__(message)
        self.plugin = str(plugin)
        self.variable = variable

    def __reduce__(self) -> Any:  # picklable also in its per-cause subclasses (dask workers)
        cause = next((b for b in type(self).__bases__ if b is not PluginFailure), None)
        return (_rebuild, (cause, str(self), self.plugin, self.variable))


_FAILURES: dict[type, type] = {}


def _failure_class(cause: type | None) -> type:
    """``PluginFailure`` that is also a ``cause`` (cached; plain PluginFailure if impossible)."""
    if cause is None or cause is RuntimeError or issubclass(cause, PluginFailure):
        return PluginFailure
    if cause not in _FAILURES:
        try:
            _FAILURES[cause] = type(
                f"PluginFailure_{cause.__name__}", (PluginFailure, cause), {"__module__": __name__}
            )
        except TypeError:  # incompatible layout
            _FAILURES[cause] = PluginFailure
    return _FAILURES[cause]


def _rebuild(cause: type | None, message: str, plugin: str, variable: str | None) -> Any:
    return _make_failure(cause, message, plugin, variable)


def _make_failure(cause: type | None, message: str, plugin: Any, variable: str | None) -> Any:
    try:
        exc = _failure_class(cause)(message, plugin=plugin, variable=variable)
        if str(exc) == message:
            return exc
    except Exception:  # a cause class with an unusual constructor
        pass
    return PluginFailure(message, plugin=plugin, variable=variable)


_GROUP_WORD = {
    "spectra": "spectrum",
    "coefficients": "coefficient",
    "boundaries": "boundary",
    "analyses": "analysis",
}


class _Label:
    """A plugin's label, looked up (registry, distribution metadata) only when printed."""

    def __init__(self, group: str, plugin: Any, registry: Any, name: str | None) -> None:
        self._args = (group, plugin, registry, name)
        self._text: str | None = None

    def __str__(self) -> str:
        if self._text is None:
            self._text = _label_text(*self._args)
        return self._text

    def __format__(self, spec: str) -> str:
        return format(str(self), spec)

    def __repr__(self) -> str:
        return repr(str(self))


def plugin_label(group: str, plugin: Any, registry: Any = None, name: str | None = None) -> Any:
    """``"boundary plugin 'plastic' (distribution xpersson-plasticity 0.1.0)"``, lazily.

    Parameters
    ----------
    group : str
        Plugin group (``"boundaries"``, ...; singular forms accepted).
    plugin : object
        The plugin instance or class.
    registry : Registry, optional
        Where to look up the registered name and distribution.
    name : str, optional
        The name the scene used (preferred over the registry's).

    Returns
    -------
    object
        Formats as the label text; the (slow) distribution lookup runs only when an error
        message is built.
    """
    return _Label(group, plugin, registry, name)


def _label_text(group: str, plugin: Any, registry: Any, name: str | None) -> str:
    from .plugins._registry import DIRECT, get_registry, normalize_group

    cls = plugin if isinstance(plugin, type) else type(plugin)
    try:
        group = normalize_group(group)
        reg = registry if registry is not None else get_registry()
        reg_name, info = reg.name_of(group, cls)
        if info is not None and info.dist != DIRECT:
            dist = f"{info.dist} {info.version}".strip()
        else:
            dist = _distribution_of(cls.__module__)
    except Exception:  # a label must never fail
        dist, reg_name = "unknown", f"{cls.__module__}:{cls.__qualname__}"
    word = _GROUP_WORD.get(group, group)
    return f"{word} plugin {name or reg_name!r} (distribution {dist})"


@functools.lru_cache(maxsize=1)
def _packages() -> Mapping[str, list[str]]:
    from importlib.metadata import packages_distributions

    return packages_distributions()


def _distribution_of(module: str) -> str:
    """Distribution and version of a class passed directly (not registered by entry point)."""
    from importlib.metadata import version

    try:
        dists = _packages().get(module.partition(".")[0], [])
        if dists:
            return f"{dists[0]} {version(dists[0])}"
    except Exception:
        pass
    return f"none: class {module} passed directly"


@contextlib.contextmanager
def calling(
    who: object, what: str, passthrough: tuple[type[BaseException], ...] = ()
) -> Iterator[None]:
    """Re-raise any exception of a plugin call as :class:`PluginFailure` naming the plugin.

    Parameters
    ----------
    who : str
        :func:`plugin_label` of the plugin.
    what : str
        The call, e.g. ``"f(zeta)"``.
    passthrough : tuple of exception types
        Exceptions the caller handles itself (re-raised unchanged).
    """
    try:
        yield
    except (PluginFailure, MemoryError, *passthrough):
        raise
    except Exception as exc:
        raise _make_failure(
            type(exc), f"{who}: {what} raised {type(exc).__name__}: {exc}", who, what
        ) from exc


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
    u = f" {unit}" if unit else ""
    bad = ~np.isfinite(arr)
    if bad.any():
        raise PluginFailure(
            f"{who}: {what} returned {int(bad.sum())} non-finite value(s): {_quote(arr, bad, u)}",
            plugin=who,
            variable=what,
        )
    if nonnegative and np.any(arr < 0):
        raise PluginFailure(
            f"{who}: {what} returned {int((arr < 0).sum())} negative value(s) (must be >= 0): "
            f"{_quote(arr, arr < 0, u)}",
            plugin=who,
            variable=what,
        )
    if nondecreasing_axis is not None and arr.shape[nondecreasing_axis] > 1:
        d = np.diff(arr, axis=nondecreasing_axis)
        scale = np.max(np.abs(arr), axis=nondecreasing_axis, keepdims=True)
        down = d < -1e-12 * scale
        if down.any():
            raise PluginFailure(
                f"{who}: {what} decreases (must be non-decreasing in zeta) at "
                f"{int(down.sum())} step(s)",
                plugin=who,
                variable=what,
            )
    return arr


def _quote(arr: np.ndarray, mask: np.ndarray, unit: str = "", coords: Any = None) -> str:
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

    A frozen spectrum (:meth:`xpersson.physics.psd.PowerSpectrum.freeze`: immutable, shared by
    the builds of equal parameters) that passed once is not checked again.
    """
    frozen = getattr(psd, "frozen", False) is True
    if frozen and id(psd) in _CHECKED_SPECTRA and _CHECKED_SPECTRA[id(psd)]() is psd:
        return
    _check_spectrum(psd, who)
    if frozen:
        try:
            ref = weakref.ref(psd)
        except TypeError:  # pragma: no cover - not weak-referenceable: checked every time
            return
        if len(_CHECKED_SPECTRA) > 256:
            _CHECKED_SPECTRA.clear()
        _CHECKED_SPECTRA[id(psd)] = ref


_CHECKED_SPECTRA: dict[int, Any] = {}


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
    from .engine import Wall

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


# -- Dataset contributions -----------------------------------------------------------------------
def checked_variable(
    ds: Any, name: str, value: Any, spec: Any, who: object, sizes: Mapping[str, int] | None = None
) -> Any:
    """Turn one returned ``(dims, data)`` pair or DataArray into a checked DataArray
    (a pair becomes a coordinate-free :class:`xarray.Variable`).

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
            da = value.copy()
            da.attrs = {}
            da = da.reset_coords(drop=True) if da.coords else da
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
                # the remaining rule is the values' (finite, valid_min / valid_max)
                da = xr.Variable(dims, arr, fastpath=True)
                _check_values(da, ds, name, spec, var, who)
                return da
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


def _check_values(da: Any, ds: Any, name: str, spec: Any, var: Any, who: object) -> None:
    arr = np.asarray(da.values)
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
        # fast path, the same rule in two reductions: min and max propagate NaN and show +-inf
        lo_v, hi_v = float(arr.min()), float(arr.max())
        if (
            math.isfinite(lo_v)
            and math.isfinite(hi_v)
            and (spec.valid_min is None or lo_v >= spec.valid_min)
            and (spec.valid_max is None or hi_v <= spec.valid_max)
        ):
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
                f"{_quote(arr, bad, unit, coords())}",
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
                f"{_quote(arr, out, unit, coords())}",
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
        data = v.data
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
        for data in frozen:
            data.flags.writeable = True


def check_contributions(
    ds: Any, values: Any, specs: Mapping[str, Any], who: object
) -> dict[str, Any]:
    """Check a plugin's returned mapping ``{name: value}``; return ``{name: DataArray}``."""
    if not isinstance(values, Mapping):
        raise PluginFailure(
            f"{who} returned {type(values).__name__}; expected a mapping "
            f"name -> DataArray or (dims, data)",
            plugin=who,
        )
    out = {}
    sizes = dict(ds.sizes)
    for name, value in values.items():
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
    import dataclasses

    from .schema import CORE_VARIABLES

    def clean(name: str, lo: float | None, hi: float | None) -> bool:
        # two reductions, no temporaries: min and max propagate NaN, and +-inf shows in them
        arr = np.asarray(ds.variables[name].values)
        if arr.size == 0:
            return True
        a_min, a_max = float(arr.min()), float(arr.max())
        return bool(
            math.isfinite(a_min)
            and math.isfinite(a_max)
            and (lo is None or a_min >= lo)
            and (hi is None or a_max <= hi)
        )

    names = [n for n in CORE_RANGES if n in ds.variables]
    if all(clean(n, *CORE_RANGES[n]) for n in names):  # one pass over the arrays: the rule
        return {}
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
