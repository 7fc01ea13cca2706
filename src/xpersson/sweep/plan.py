"""Sweep plans: the swept parameters of a scene, their dimensions and points (see
:mod:`xpersson.sweep`)."""

from __future__ import annotations

import copy
import itertools
import math
import re
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..plugins import ParamSpec, PluginError, Registry, get_registry
from ..scene import (
    CORE,
    DEFAULT_MODEL,
    PLUGIN_SECTIONS,
    Scene,
    SceneError,
    is_sweep_value,
    sweep_values,
)

__all__ = ["SweepParam", "SweepPlan", "expand", "cf_units"]

# parameters the core stores as variables of the same name (the coordinate replaces them)
_SELF_NAMED = {"material.E": "E", "material.nu": "nu"}


@dataclass(frozen=True)
class SweepParam:
    """One swept parameter.

    Attributes
    ----------
    path : str
        Dotted scene path, e.g. ``"material.E"`` or ``"analyses.leakage.fluid_pressure"``.
    name : str
        Its Dataset name (dimension name, or coordinate name inside a zipped group).
    spec : ParamSpec
        The declaration (unit, range, description).
    values : numpy.ndarray
        The values in the spec's SI unit.
    """

    path: str
    name: str
    spec: ParamSpec
    values: np.ndarray

    def scene_value(self, i: int) -> Any:
        """Value ``i`` as a scene entry (a string with unit, or a bare number)."""
        v = self.values[i]
        if self.spec.kind == "int":
            return int(v)
        if self.spec.unit in ("1", ""):
            return float(v)
        return f"{float(v)!r} {self.spec.unit}"


@dataclass(frozen=True)
class SweepPlan:
    """The points of a sweep: one dimension per group of zipped parameters.

    Attributes
    ----------
    scene : Scene
        The scene as written (with its lists and ranges).
    groups : list of list of SweepParam
        One entry per dimension; several parameters in a group are zipped.
    """

    scene: Scene
    groups: list[list[SweepParam]]
    base: dict[str, Any] = field(repr=False, default_factory=dict)

    @property
    def dims(self) -> tuple[str, ...]:
        """Sweep dimension names (outer to inner)."""
        return tuple(g[0].name for g in self.groups)

    @property
    def shape(self) -> tuple[int, ...]:
        """Number of values along each sweep dimension."""
        return tuple(len(g[0].values) for g in self.groups)

    @property
    def size(self) -> int:
        """Number of points."""
        return math.prod(self.shape)

    @property
    def params(self) -> list[SweepParam]:
        """All swept parameters, in dimension order."""
        return [p for g in self.groups for p in g]

    def point_data(self, index: tuple[int, ...]) -> dict[str, Any]:
        """Scene dict of one point (every swept parameter replaced by its scalar value)."""
        data = copy.deepcopy(self.base)
        for group, i in zip(self.groups, index, strict=True):
            for param in group:
                _set_path(data, param.path, param.scene_value(i))
        return data

    def point_scene(self, index: tuple[int, ...]) -> Scene:
        """The :class:`~xpersson.Scene` of one point.

        Only the tables on a swept path are copied; the other tables are the plan's base
        (a deep copy of the scene made at :func:`expand`), shared read-only by every point
        scene: no deep copy of the whole tree per point."""
        data = dict(self.base)
        for group, i in zip(self.groups, index, strict=True):
            for param in group:
                _set_path(data, param.path, param.scene_value(i), copy_tables=True)
        return Scene._shared(data, self.scene.source)

    def indices(self) -> Iterator[tuple[int, ...]]:
        """All point indices in C order (last dimension fastest)."""
        return itertools.product(*(range(n) for n in self.shape))

    def coords(self) -> dict[str, tuple[str, np.ndarray, dict[str, Any]]]:
        """Coordinates of the sweep: name -> (dim, values, CF attrs)."""
        out = {}
        for group in self.groups:
            for param in group:
                attrs = {
                    "units": cf_units(param.spec.unit),
                    "long_name": param.spec.description or param.path,
                    "xpersson_parameter": param.path,
                }
                out[param.name] = (group[0].name, np.asarray(param.values), attrs)
        return out

    def scene_lists(self) -> dict[str, Any]:
        """The scene with every swept parameter as a list of SI values (re-solvable)."""
        data = copy.deepcopy(self.base)
        for param in self.params:
            _set_path(data, param.path, [param.scene_value(i) for i in range(len(param.values))])
        data["sweep"] = copy.deepcopy(self.scene.data.get("sweep", {}))
        data["sweep"]["order"] = [p.path for p in self.params]
        return data


def _set_path(data: dict[str, Any], path: str, value: Any, copy_tables: bool = False) -> None:
    """Set a dotted path; ``copy_tables`` copies each table on the way (shares nothing)."""
    parts = path.split(".")
    node = data
    for part in parts[:-1]:
        child = node.get(part)
        child = {} if child is None else dict(child) if copy_tables else child
        node[part] = child
        node = child
    node[parts[-1]] = value


#: Unprefixed SI symbols :func:`cf_units` writes without pint (pint's symbol is the same).
_SI_SYMBOLS = frozenset({"Pa", "m", "s", "K", "N", "J", "W", "mol"})
_FACTOR = re.compile(r"([A-Za-z]+)(?:\*\*(-?\d+))?")


def _simple_cf(unit: str) -> str | None:
    """:func:`cf_units` of a product / quotient of unprefixed SI symbols, each at most once
    (``"Pa*s"``, ``"1/m"``, ``"J/m**2"``), in the order written (as pint keeps it); ``None``
    for anything else (parentheses, prefixes, other names: pint reads those)."""
    terms, seen, sign = [], set(), 1
    for i, tok in enumerate(re.split(r"(?<!\*)([*/])(?!\*)", unit.replace(" ", ""))):
        if tok in ("*", "/"):
            sign = 1 if tok == "*" else -1
            continue
        if tok == "1" and i == 0:
            continue
        m = _FACTOR.fullmatch(tok)
        if m is None or m.group(1) not in _SI_SYMBOLS or m.group(1) in seen:
            return None
        seen.add(m.group(1))
        p = sign * int(m.group(2) or 1)
        terms.append(m.group(1) if p == 1 else f"{m.group(1)}^{p}")
    return " ".join(terms) or None


def cf_units(unit: str) -> str:
    """UDUNITS string of a pint unit (``"1/m"`` -> ``"m^-1"``, ``"m**4"`` -> ``"m^4"``).

    Simple SI units are written directly (:func:`_simple_cf`): a sweep's first run does not
    build pint's registry for its coordinates' attributes (about 0.3 s once per process)."""
    if unit in ("1", "", "dimensionless"):
        return "1"
    simple = _simple_cf(unit)
    if simple is not None:
        return simple
    from ..units import ureg

    u = ureg().Unit(unit)
    terms = []
    for name, power in u._units.items():  # noqa: SLF001 - pint's unit container
        sym = ureg().get_symbol(name)
        p = int(power) if float(power).is_integer() else power
        terms.append(sym if p == 1 else f"{sym}^{p}")
    return " ".join(terms) or "1"


def _section_specs(
    data: Mapping[str, Any], registry: Registry
) -> Iterator[tuple[str, dict[str, ParamSpec], Mapping[str, Any], type | None]]:
    """(path prefix, parameter specs, values, plugin class) of every section with parameters,
    in the order the scene gives them."""
    sections = list(data)
    for section in PLUGIN_SECTIONS:  # default models count too (at the end)
        if section not in sections and section in DEFAULT_MODEL:
            sections.append(section)
    for section in sections:
        raw = data.get(section)
        if section in data and not isinstance(raw, Mapping):
            continue  # (not a table, None included: the scene's check names it)
        if section == "material":
            yield "material", CORE["material"], raw, None
        elif section in PLUGIN_SECTIONS:
            raw = raw or {}
            model = raw.get("model", DEFAULT_MODEL.get(section))
            if model is None:
                continue
            try:
                cls = registry.resolve(PLUGIN_SECTIONS[section], model)
            except (PluginError, TypeError) as exc:
                raise SceneError(f"{section}.model: {exc}") from None
            yield section, cls.parameters, {k: v for k, v in raw.items() if k != "model"}, cls
        elif section == "analyses":
            for name, params in raw.items():
                if not isinstance(params, Mapping):
                    continue
                try:
                    cls = registry.resolve("analyses", name)
                except (PluginError, TypeError) as exc:
                    raise SceneError(f"analyses.{name}: {exc}") from None
                yield f"analyses.{name}", cls.parameters, params, cls


def _taken_names(data: Mapping[str, Any], classes: list[type]) -> set[str]:
    from ..schema import COORDS, CORE_VARIABLES

    taken = set(COORDS) | set(CORE_VARIABLES) | {"point_status"}
    for cls in classes:
        taken |= set(getattr(cls, "outputs", {}) or {})
    return taken


def expand(scene: Scene, registry: Registry | None = None) -> SweepPlan | None:
    """Find the swept parameters of a scene; ``None`` when it sweeps nothing but loads.

    Raises
    ------
    SceneError
        A list given to a parameter that is not sweepable, a malformed ``[sweep]`` table,
        zipped lists of different lengths, or a dimension name collision.
    """
    reg = registry or get_registry()
    data = scene.data
    found, classes = _swept(data, reg)
    table = _sweep_table(data)
    if not found:
        if table:
            raise SceneError(
                "sweep: the scene sweeps no parameter (give a list or a range to a "
                "sweepable parameter; load.p0 is the load dimension already)"
            )
        return None
    geometry = data.get("geometry")
    if isinstance(geometry, Mapping) and geometry.get("model", "flat") != "flat":
        raise SceneError(
            f"sweep: a scene with a finite body (geometry {geometry.get('model')!r}) sweeps "
            f"only its forces (load.force); solve one scene per {found[0][0]} value"
        )
    mode = table.get("mode", "product")
    if mode not in ("product", "zip"):
        raise SceneError(f"sweep.mode: {mode!r} is not allowed; one of 'product', 'zip'")

    taken = _taken_names(data, classes)
    params: dict[str, SweepParam] = {}
    used: dict[str, str] = {}
    for path, spec, value in found:
        values = sweep_values(spec, value, path)
        name = _dim_name(path, spec, taken, used)
        used[name] = path
        params[path] = SweepParam(path, name, spec, values)

    zips = table.get("zip", [])
    if mode == "zip":
        if zips:
            raise SceneError("sweep.zip: give either mode = 'zip' (all zipped) or zip groups")
        zips = [list(params)]
    groups = _groups(params, _zip_groups(zips, params))
    _order(groups, table.get("order", []), params)
    for group in groups:
        _check_group(group)
    base = copy.deepcopy(dict(data))
    base.pop("sweep", None)
    return SweepPlan(scene=scene, groups=groups, base=base)


_ONE_VALUE = frozenset((str, float, int, bool))
"""Types of a value that is never a list or a range (:func:`is_sweep_value` is false)."""


def _swept(
    data: Mapping[str, Any], reg: Registry
) -> tuple[list[tuple[str, ParamSpec, Any]], list[type]]:
    """(path, spec, value) of every parameter given a list or a range, and the plugin classes
    of the scene's sections."""
    found: list[tuple[str, ParamSpec, Any]] = []
    classes: list[type] = []
    for prefix, specs, values, cls in _section_specs(data, reg):
        if cls is not None:
            classes.append(cls)
        for key, value in values.items():
            if type(value) in _ONE_VALUE:  # (most values: no declaration looked up)
                continue
            spec = specs.get(key)
            if spec is None or not is_sweep_value(spec, value):
                continue
            path = f"{prefix}.{key}"
            if not spec.sweepable:
                raise SceneError(
                    f"{path}: this parameter is not sweepable; give one value ({spec.range_text()})"
                )
            found.append((path, spec, value))
    return found, classes


def _sweep_table(data: Mapping[str, Any]) -> Mapping[str, Any]:
    """The scene's ``[sweep]`` table, its keys checked."""
    table = data.get("sweep", {})
    if not isinstance(table, Mapping):
        raise SceneError("sweep: must be a table (mode = 'product' | 'zip', zip = [[...]])")
    unknown = sorted(set(table) - {"mode", "zip", "order"})
    if unknown:
        raise SceneError(f"sweep.{unknown[0]}: unknown key; allowed: mode, zip, order")
    return table


def _zip_groups(zips: Any, params: dict[str, SweepParam]) -> dict[str, int]:
    """Zip group number of every zipped parameter path (checked)."""
    if not isinstance(zips, list) or not all(isinstance(g, list) for g in zips):
        raise SceneError("sweep.zip: expected a list of lists of dotted parameter names")
    grouped: dict[str, int] = {}
    for gi, group in enumerate(zips):
        for path in group:
            if path == "load.p0":
                raise SceneError("sweep.zip: load.p0 is the load dimension and cannot be zipped")
            if path not in params:
                raise SceneError(
                    f"sweep.zip: {path!r} is not a swept parameter of this scene; swept: "
                    f"{', '.join(params) or 'none'}"
                )
            if path in grouped:
                raise SceneError(f"sweep.zip: {path!r} appears in two groups")
            grouped[path] = gi
    return grouped


def _groups(params: dict[str, SweepParam], grouped: dict[str, int]) -> list[list[SweepParam]]:
    """One group per dimension, in the order of the parameters' first appearance."""
    groups: list[list[SweepParam]] = []
    placed: dict[int, list[SweepParam]] = {}
    for path, param in params.items():
        gi = grouped.get(path)
        if gi is None:
            groups.append([param])
        elif gi not in placed:
            placed[gi] = [param]
            groups.append(placed[gi])
        else:
            placed[gi].append(param)
    return groups


def _order(groups: list[list[SweepParam]], order: Any, params: dict[str, SweepParam]) -> None:
    """Sort the groups (in place) as ``sweep.order`` lists their parameters."""
    if not isinstance(order, list) or any(p not in params for p in order):
        bad = (
            next((p for p in order if p not in params), order) if isinstance(order, list) else order
        )
        raise SceneError(
            f"sweep.order: {bad!r} is not a swept parameter of this scene; swept: "
            f"{', '.join(params)}"
        )
    rank = {path: i for i, path in enumerate(order)}
    groups.sort(key=lambda g: min(rank.get(p.path, len(rank)) for p in g))


def _check_group(group: list[SweepParam]) -> None:
    """Zipped parameters have as many values; the values indexing a dimension are distinct."""
    n = {len(p.values) for p in group}
    if len(n) > 1:
        raise SceneError(
            "sweep.zip: zipped parameters need the same number of values; got "
            + ", ".join(f"{p.path}: {len(p.values)}" for p in group)
        )
    index = group[0].values
    if len(np.unique(index)) != len(index):
        raise SceneError(
            f"{group[0].path}: swept values must be distinct (they index the "
            f"dimension {group[0].name!r})"
        )


def _dim_name(path: str, spec: ParamSpec, taken: set[str], used: dict[str, str]) -> str:
    if spec.dim is not None:
        if spec.dim in used:
            raise SceneError(
                f"{path}: its dimension {spec.dim!r} is already the dimension of {used[spec.dim]}"
            )
        if spec.dim in taken:
            raise SceneError(
                f"{path}: its declared dimension {spec.dim!r} collides with a "
                "Dataset variable of that name"
            )
        return spec.dim
    if path in _SELF_NAMED:
        return _SELF_NAMED[path]
    key = path.rsplit(".", 1)[-1]
    for name in (key, path.replace(".", "_")):
        if name not in taken and name not in used:
            return name
    other = used.get(key) or used.get(path.replace(".", "_"))
    raise SceneError(
        f"{path}: dimension name {path.replace('.', '_')!r} is already used"
        + (f" by {other}" if other else " by the Dataset")
    )
