"""Conversion of scene values: kinds, units, ranges, sweep values; JSON-able records."""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

import numpy as np

from ..cache import Cache
from ..errors import SceneError, UnitError
from ..specs import ParamSpec
from ..units import strings_to_si, to_si
from ._core import CORE, MAX_POINTS

__all__ = [
    "RANGE_KEYS",
    "archived_section",
    "convert_param",
    "convert_params",
    "is_sweep_value",
    "jsonable",
    "loads",
    "resolved_loads",
    "sweep_values",
]


def convert_param(spec: ParamSpec, value: Any, where: str) -> Any:
    """Convert one scene value according to its spec, checking kind and range.

    Parameters
    ----------
    spec : ParamSpec
        The parameter's declaration (kind, unit, bounds).
    value : object
        The scene's value (a quantity string or number in ``spec.unit``, a bool, a string ...).
    where : str
        ``section.key`` for messages.

    Returns
    -------
    object
        The value in SI units (float or array for quantities), or as given for other kinds.

    Raises
    ------
    SceneError
        Wrong kind, unit or range; the message names ``where``, the unit and the range.
    """
    if spec.kind in ("bool", "string", "path", "choice"):
        return _convert_literal(spec, value, where)
    if type(value) in (str, float, int) and not spec.array:  # one number: converted once
        try:  # keyed on the spec's content key (bytes: the key's fast path) and the value
            key = (spec.cache_key(), value)
        except TypeError:  # a declaration holding a value without a content key
            return _convert_number(spec, value, where)
        return _NUMBERS.get(key, lambda: _convert_number(spec, value, where))
    return _convert_number(spec, value, where)


_NUMBERS = Cache(
    "scene.numbers",
    scope="process",
    maxsize=4096,
    doc="a scene's number or quantity text in SI by its ParamSpec (a float or an int)",
)


def _convert_number(spec: ParamSpec, value: Any, where: str) -> Any:
    """:func:`convert_param` of a quantity or int parameter (checked; raises naming ``where``:
    an error is never kept, so every failing value raises its own message)."""
    if spec.sweepable and is_sweep_value(spec, value):
        raise SceneError(
            f"{where}: several values sweep this parameter; solve the scene with "
            "xpersson.solve (each point is resolved on its own)"
        )
    if spec.kind == "int":
        if isinstance(value, bool) or not isinstance(value, int | float) or value != int(value):
            raise SceneError(f"{where}: expected an integer in {spec.range_text()}, got {value!r}")
        if not spec.in_bounds(value):
            raise SceneError(f"{where}: {value} is outside the allowed range {spec.range_text()}")
        return int(value)
    return _convert_quantity(spec, value, where)


def _convert_literal(spec: ParamSpec, value: Any, where: str) -> Any:
    """A bool, string, path or choice value, checked (returned as given)."""
    if spec.kind == "bool":
        if not isinstance(value, bool):
            raise SceneError(f"{where}: expected true or false, got {value!r}")
        return value
    if spec.kind in ("string", "path"):
        if not isinstance(value, str):
            if isinstance(value, type):  # a class passed directly (Python API)
                return value
            raise SceneError(f"{where}: expected a string, got {value!r}")
        return value
    if value not in spec.choices:
        raise SceneError(f"{where}: {value!r} is not allowed; {spec.range_text()}")
    return value


def _convert_quantity(spec: ParamSpec, value: Any, where: str) -> Any:
    """A quantity (or array of quantities) in SI units, finite and inside the spec's range."""
    try:
        val = to_si(value, spec.unit, where, array=spec.array)
    except UnitError as exc:  # the unit's message, and what the parameter allows
        raise SceneError(f"{exc}; allowed range {spec.range_text()}") from None
    vals = np.atleast_1d(val)
    if spec.array and vals.size == 0:
        raise SceneError(f"{where}: empty list; give at least one value in {spec.range_text()}")
    if spec.array and vals.size > MAX_POINTS:
        raise SceneError(f"{where}: {vals.size} values; at most {MAX_POINTS} are allowed")
    if not np.all(np.isfinite(vals)):
        raise SceneError(
            f"{where}: must be finite, got {value!r}; allowed range {spec.range_text()}"
        )
    if vals.size > 8:  # an array (a zeta grid): checked at once
        bad = vals[~_in_bounds(spec, np.asarray(vals, float))].tolist()
    else:
        bad = [v for v in vals if not spec.in_bounds(float(v))]
    if bad:
        raise SceneError(
            f"{where}: {bad[0]:g} {'' if spec.unit == '1' else spec.unit} is outside the allowed "
            f"range {spec.range_text()}"
        )
    return val


def convert_params(
    specs: Mapping[str, ParamSpec], values: Mapping[str, Any], section: str
) -> dict[str, Any]:
    """Convert a section's values; unknown keys and missing required ones are errors."""
    unknown = sorted(set(values) - set(specs))
    if unknown:
        raise SceneError(
            f"{section}.{unknown[0]}: unknown parameter; allowed in [{section}]: "
            f"{', '.join(sorted(specs)) or 'none'}"
        )
    out: dict[str, Any] = {}
    for name, spec in specs.items():
        where = f"{section}.{name}"
        if name in values:
            out[name] = convert_param(spec, values[name], where)
        elif spec.required:
            raise SceneError(
                f"{where}: required ({spec.description or spec.unit}); "
                f"allowed range {spec.range_text()}"
            )
        else:
            out[name] = spec.default
    return out


RANGE_KEYS = ("start", "stop", "num", "spacing")


def is_sweep_value(spec: ParamSpec, value: Any) -> bool:
    """Whether ``value`` asks for several values of a scalar parameter (a list or a range
    table ``{start, stop, num[, spacing]}``)."""
    if spec.array or spec.kind not in ("quantity", "int"):
        return False
    if isinstance(value, list | tuple) or _is_quantity_array(value):
        return True
    return isinstance(value, Mapping) and bool(value) and set(value) <= set(RANGE_KEYS)


def _is_quantity_array(value: Any) -> bool:
    """A pint Quantity (of any registry) holding an array: several values with one unit."""
    magnitude = getattr(value, "magnitude", None)
    return hasattr(value, "units") and magnitude is not None and np.ndim(magnitude) >= 1


def _in_bounds(spec: ParamSpec, values: np.ndarray) -> np.ndarray:
    """:meth:`ParamSpec.in_bounds` for an array at once (NaN is never in bounds)."""
    lo, hi = spec.bounds
    ok = ~np.isnan(values)
    if lo is not None:
        ok &= (values >= lo) if spec.inclusive[0] else (values > lo)
    if hi is not None:
        ok &= (values <= hi) if spec.inclusive[1] else (values < hi)
    return ok


def sweep_values(spec: ParamSpec, value: Any, where: str) -> np.ndarray:
    """The values of a list or range table ``{start, stop, num, spacing}`` in SI units.

    ``spacing`` is ``"log"`` (default, as for ``load.p0``) or ``"linear"``; every value is
    checked against the parameter's range.
    """
    if isinstance(value, Mapping):
        unknown = sorted(set(value) - set(RANGE_KEYS))
        if unknown:
            raise SceneError(f"{where}.{unknown[0]}: unknown key; allowed: {list(RANGE_KEYS)}")
        for k in ("start", "stop", "num"):
            if k not in value:
                raise SceneError(f"{where}.{k}: required for a range")
        start = convert_param(spec, value["start"], f"{where}.start")
        stop = convert_param(spec, value["stop"], f"{where}.stop")
        num = value["num"]
        if isinstance(num, bool) or not isinstance(num, int) or not 1 <= num <= MAX_POINTS:
            raise SceneError(f"{where}.num: expected an integer in [1, {MAX_POINTS}], got {num!r}")
        spacing = value.get("spacing", "log")
        if spacing not in ("log", "linear"):
            raise SceneError(f"{where}.spacing: {spacing!r} is not allowed; one of 'log', 'linear'")
        if stop < start:
            raise SceneError(f"{where}: stop must be >= start")
        if spacing == "log" and start <= 0:
            raise SceneError(f"{where}: a log-spaced range needs start > 0; use spacing = 'linear'")
        grid = np.geomspace(start, stop, num) if spacing == "log" else np.linspace(start, stop, num)
        if spec.kind == "int":
            grid = np.unique(np.round(grid).astype(int))
        bad = grid[~_in_bounds(spec, np.asarray(grid, float))]
        if bad.size:
            raise SceneError(
                f"{where}: {float(bad[0]):g} is outside the allowed range {spec.range_text()}"
            )
        return grid
    if _is_quantity_array(value):  # Quantity([1, 2], "MPa") -> [Quantity(1, "MPa"), ...]
        value = [value[i] for i in range(len(value))]
    if not len(value):
        raise SceneError(f"{where}: empty list; give at least one value in {spec.range_text()}")
    if len(value) > MAX_POINTS:
        raise SceneError(
            f"{where}: {len(value)} values; at most {MAX_POINTS} are allowed (as for {where}.num)"
        )
    fast = _strings_in_bounds(spec, value)
    if fast is not None:
        return fast
    return np.array([convert_param(spec, v, f"{where}[{i}]") for i, v in enumerate(value)])


def _strings_in_bounds(spec: ParamSpec, value: Any) -> np.ndarray | None:
    """A list of quantity strings converted at once (:func:`~xpersson.units.strings_to_si`:
    one unit parse per distinct unit), or ``None`` where a value needs the value-by-value path
    (another kind of value, a unit pint must parse, a value out of range: its message)."""
    if spec.kind != "quantity" or spec.unit in ("1", "") or type(value) is not list:
        return None
    got = strings_to_si(value, spec.unit)
    if got is None:
        return None
    arr = got
    if not np.all(np.isfinite(arr)) or not np.all(_in_bounds(spec, arr)):
        return None
    return arr


def loads(value: Any, tensile: bool = False) -> tuple[np.ndarray, bool]:
    """``load.p0`` in Pa and whether it was a scalar (``tensile`` lifts the sign bound)."""
    # the boundary accepts tensile loads (adhesion) and checks their range itself
    spec = _TENSILE if tensile else CORE["load"]["p0"]
    return increasing_values(spec, value, "load.p0", "loads")


#: ``load.p0`` without its sign bound (one declaration: its content key is made once).
_TENSILE = dataclasses.replace(CORE["load"]["p0"], bounds=(None, None))


def increasing_values(
    spec: ParamSpec, value: Any, where: str, what: str
) -> tuple[np.ndarray, bool]:
    """A load-like entry ``where`` in SI (strictly increasing when a list; ``what`` names its
    values in the message) and whether it was a scalar."""
    if is_sweep_value(spec, value):
        arr = sweep_values(spec, value, where)
        if not isinstance(value, Mapping) and np.any(np.diff(arr) <= 0):
            raise SceneError(f"{where}: {what} must be strictly increasing")
        return arr, False
    return np.array([convert_param(spec, value, where)]), True


def resolved_loads(raw: Any, p0: np.ndarray, scalar: bool) -> Any:
    """``load.p0`` of the resolved scene: re-loads to exactly ``p0``.

    A range table stays a range table (its end points are the first and last loads exactly,
    ``geomspace``/``linspace`` reproduce the values in between): a 1000-load sweep costs no
    1000 formatted strings in the scene and its JSON. A list of strings all in pascals
    (``"... Pa"``, e.g. ``"1000.0 Pa"``, ``"1e3 Pa"``) is kept as written: those texts
    resolved to ``p0`` and re-load to exactly ``p0``, at no formatting cost. Other lists
    and scalars: one string ``"<repr> Pa"`` per load.
    """
    if type(raw) is list and len(raw) == len(p0) and _in_pascal(raw):
        return list(raw)
    values = np.asarray(p0, float).tolist()
    if isinstance(raw, Mapping) and len(values) == raw.get("num"):
        return {
            "start": f"{values[0]!r} Pa",
            "stop": f"{values[-1]!r} Pa",
            "num": len(values),
            "spacing": raw.get("spacing", "log"),
        }
    # one join and one split: 1000 loads cost a third less than a formatted string each
    texts = (" Pa\n".join(map(repr, values)) + " Pa").split("\n")
    return texts[0] if scalar else texts


def _in_pascal(texts: list[Any]) -> bool:
    """Whether every item of ``texts`` (which resolved to the loads already) is a string
    ending ``" Pa"`` on one line: one join and two counts over all values."""
    try:
        joined = "\n".join(texts) + "\n"
    except TypeError:  # a value that is not a string
        return False
    return joined.count(" Pa\n") == len(texts) == joined.count("\n")


def jsonable(
    params: Mapping[str, Any], specs: Mapping[str, ParamSpec] | None = None
) -> dict[str, Any]:
    """JSON-able copy of resolved values; dimensional quantities as ``"value unit"`` strings so
    that the resolved scene re-loads as a scene."""
    out: dict[str, Any] = {}
    specs = specs or {}
    for k, v in params.items():
        if v is None:
            continue
        spec = specs.get(k)
        dimensional = spec is not None and spec.kind == "quantity" and spec.unit not in ("1", "")
        kind = type(v)
        if kind is float or kind is int or kind is bool or kind is str:  # the common values
            out[k] = f"{float(v)!r} {spec.unit}" if dimensional and kind is not str else v
            continue
        if dimensional and isinstance(v, np.ndarray):
            fast = v.ndim == 1 and v.dtype.kind in "fiub"  # Python floats, as float(x) gives
            values = np.asarray(v, float).tolist() if fast else [float(x) for x in v]
            out[k] = [f"{x!r} {spec.unit}" for x in values]
        elif dimensional and isinstance(v, int | float):
            out[k] = f"{float(v)!r} {spec.unit}"
        elif isinstance(v, np.ndarray):
            fast = v.ndim == 1 and v.dtype.kind in "fiub"  # Python floats, as float(x) gives
            out[k] = np.asarray(v, float).tolist() if fast else [float(x) for x in v]
        elif isinstance(v, type):
            out[k] = f"{v.__module__}:{v.__qualname__}"
        elif isinstance(v, np.generic):
            out[k] = v.item()
        else:
            out[k] = v
    return out


def archived_section(
    name: str, inst: Any, params: Mapping[str, Any], own: bool = True
) -> dict[str, Any]:
    """The scene section of the plugin ``inst`` (named ``name``; its converted ``params``) as
    the archive records it: where a ``kind="path"`` parameter names a file and the plugin has
    ``archived_params()`` (``own``; a spectrum's, ``archived_params(psd)``, is applied with
    its grid), the parameters that method gives (the file's table inline: no machine-specific
    path goes into an archive, and the archive rebuilds the plugin without the file)."""
    specs = type(inst).parameters
    archived = getattr(inst, "archived_params", None)
    if (
        own
        and callable(archived)
        and any(spec.kind == "path" and params.get(k) is not None for k, spec in specs.items())
    ):
        params = archived()
    return {"model": name, **jsonable(params, specs)}
