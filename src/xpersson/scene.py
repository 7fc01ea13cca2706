"""Scenes: parse, validate and resolve a TOML file or dict into plugins and SI arrays.

Everything is checked before any work starts: dimensionality and ranges of every quantity,
unknown keys (named in the error), plugin names, and the spectrum's own consistency
(``q_L < q_r <= q_1``). Errors are :class:`SceneError` and name the parameter as
``section.key``, its unit and the allowed range.
"""

from __future__ import annotations

import copy
import dataclasses
import math
import re
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .plugins import ParamSpec, Plugin, get_registry
from .plugins._registry import PluginError, Registry
from .units import UnitError, to_si

__all__ = ["Scene", "SceneError", "ResolvedScene", "load_scene", "set_value"]


class SceneError(ValueError):
    """A scene is malformed; the message names the offending parameter."""


# -- the core sections and their parameters ---------------------------------------------------
MAX_PRESSURE = 1e13
"""Largest modulus or pressure a scene may give [Pa] (beyond any solid; keeps f ~ E*^2 finite)."""
MAX_ZETA = 1e12
"""Largest magnification q_1/q_L a scene may ask for [1]."""
MAX_POINTS = 100_000
"""Longest list of loads, magnifications or pressures (as the range form's ``num``)."""
CORE: dict[str, dict[str, ParamSpec]] = {
    "material": {
        "E": ParamSpec(
            "Pa",
            bounds=(0, MAX_PRESSURE),
            inclusive=(False, True),
            sweepable=True,
            description="Young's modulus of the elastic solid",
        ),
        "nu": ParamSpec(
            "1",
            bounds=(-1, 0.5),
            inclusive=(False, True),
            sweepable=True,
            description="Poisson ratio",
        ),
    },
    "load": {
        "p0": ParamSpec(
            "Pa",
            bounds=(0, MAX_PRESSURE),
            inclusive=(False, True),
            sweepable=True,
            description="nominal pressure: scalar, list or {start, stop, num}",
        ),
    },
    "output": {
        "zeta_per_decade": ParamSpec(
            "1",
            default=10,
            bounds=(1, 1000),
            kind="int",
            description="log-spaced output magnifications per decade",
        ),
        "zeta": ParamSpec(
            "1",
            default=None,
            bounds=(1, MAX_ZETA),
            array=True,
            description="explicit output magnifications (>= 1)",
        ),
        "zeta_max": ParamSpec(
            "1",
            default=None,
            bounds=(1, MAX_ZETA),
            description="largest magnification (default q_1/q_L)",
        ),
        "pressure_pdf": ParamSpec(
            "1", default=False, kind="bool", description="store the pressure PDF P(zeta, p)"
        ),
        "p_points": ParamSpec(
            "1",
            default=256,
            bounds=(8, 100000),
            kind="int",
            description="points of the default pressure grid",
        ),
        "p_max": ParamSpec(
            "Pa",
            default=None,
            bounds=(0, MAX_PRESSURE),
            inclusive=(False, True),
            description="upper end of the pressure grid",
        ),
        "p": ParamSpec(
            "Pa",
            default=None,
            bounds=(-MAX_PRESSURE, MAX_PRESSURE),
            array=True,
            description="explicit pressure grid (increasing)",
        ),
    },
    "solver": {
        "method": ParamSpec(
            "1",
            default="auto",
            kind="string",
            description="engine method (auto: exact path where one exists)",
        ),
        "rtol": ParamSpec(
            "1",
            default=1e-6,
            bounds=(1e-12, 0.1),
            inclusive=(True, False),
            description="relative tolerance on the contact area",
        ),
        "atol": ParamSpec(
            "1",
            default=1e-12,
            bounds=(0, 0.1),
            description="absolute tolerance on the contact area",
        ),
        "walkers": ParamSpec(
            "1",
            default=None,
            bounds=(1, 1e9),
            kind="int",
            description="walkers of the Monte Carlo method 'markov'",
        ),
        "seed": ParamSpec(
            "1",
            default=None,
            bounds=(0, None),
            kind="int",
            description="random seed of the Monte Carlo method 'markov'",
        ),
    },
}
PLUGIN_SECTIONS = {"spectrum": "spectra", "coefficient": "coefficients", "boundary": "boundaries"}
DEFAULT_MODEL = {"coefficient": "elastic", "boundary": "elastic"}
TOP_LEVEL = {"title", "description", "analyses", "sweep", *CORE, *PLUGIN_SECTIONS}


def _copy_tree(obj: Any) -> Any:
    """A deep copy of a scene tree: tables and lists rebuilt, immutable leaves shared."""
    if isinstance(obj, dict):
        return {k: _copy_tree(v) for k, v in obj.items()}
    if isinstance(obj, list):
        return [_copy_tree(v) for v in obj]
    if obj is None or type(obj) in (str, int, float, bool):
        return obj
    return copy.deepcopy(obj)


@dataclass
class Scene:
    """A scene as written by the user (a nested dict), plus where it came from.

    Use :func:`load_scene` for files, ``Scene(dict)`` for dicts; :meth:`resolve` checks
    everything and returns a :class:`ResolvedScene`.
    """

    data: dict[str, Any]
    source: str | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.data, Mapping):
            raise SceneError(f"a scene must be a mapping of sections, got {type(self.data)}")
        self.data = _copy_tree(dict(self.data))

    def with_values(self, **dotted: Any) -> Scene:
        """Copy with ``section.key`` values replaced: ``with_values(**{"load.p0": "1 MPa"})``."""
        new = Scene(self.data, self.source)
        for key, value in dotted.items():
            set_value(new.data, key, value)
        return new

    def resolve(self, registry: Registry | None = None) -> ResolvedScene:
        """Validate and resolve; raises :class:`SceneError` before any work."""
        return _resolve(self, registry or get_registry())


@dataclass
class ResolvedScene:
    """A validated scene: plugin instances and SI arrays (no pint)."""

    scene: Scene
    spectrum: Plugin
    coefficient: Plugin
    boundary: Plugin
    analyses: list[tuple[str, Plugin]]
    psd: Any
    E: float
    nu: float
    p0: np.ndarray
    p0_scalar: bool
    zeta: np.ndarray
    pressure_pdf: bool
    p: np.ndarray | None
    p_points: int
    p_max: float | None
    rtol: float
    atol: float
    method: Any
    plugin_names: dict[str, str] = field(default_factory=dict)
    resolved: dict[str, Any] = field(default_factory=dict)
    solver_options: dict[str, Any] = field(default_factory=dict)

    @property
    def E_star(self) -> float:
        return self.E / (1.0 - self.nu**2)


def load_scene(path: str | Path) -> Scene:
    """Read a TOML scene file.

    Parameters
    ----------
    path : str or pathlib.Path
        The ``.toml`` file.

    Raises
    ------
    SceneError
        The file is missing or is not valid TOML.
    """
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8")
    except OSError as exc:
        raise SceneError(f"cannot read scene file {str(p)!r}: {exc.strerror}") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(f"{p}: invalid TOML: {exc}") from None
    return Scene(data, source=str(p.resolve()))


def set_value(data: dict[str, Any], dotted: str, value: Any) -> None:
    """Set ``data[section][key] = value`` from a dotted name (creating the section)."""
    parts = dotted.split(".")
    if len(parts) < 2 or not all(parts):
        raise SceneError(f"--set needs section.key=value, got {dotted!r}")
    node = data
    for part in parts[:-1]:
        nxt = node.setdefault(part, {})
        if not isinstance(nxt, dict):
            raise SceneError(f"{dotted}: {part!r} is not a table")
        node = nxt
    node[parts[-1]] = value


def parse_cli_value(text: str) -> Any:
    """Interpret a ``--set`` value: a TOML value if it parses, else the raw string."""
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        return text


# -- resolution ---------------------------------------------------------------------------------
def convert_param(spec: ParamSpec, value: Any, where: str) -> Any:
    """Convert one scene value according to its spec, checking kind and range."""
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
    if spec.kind == "choice":
        if value not in spec.choices:
            raise SceneError(f"{where}: {value!r} is not allowed; {spec.range_text()}")
        return value
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
    try:
        val = to_si(value, spec.unit, where, array=spec.array)
    except UnitError as exc:
        raise SceneError(str(exc)) from None
    vals = np.atleast_1d(val)
    if spec.array and vals.size == 0:
        raise SceneError(f"{where}: empty list; give at least one value in {spec.range_text()}")
    if spec.array and vals.size > MAX_POINTS:
        raise SceneError(f"{where}: {vals.size} values; at most {MAX_POINTS} are allowed")
    if not np.all(np.isfinite(vals)):
        raise SceneError(f"{where}: must be finite, got {value!r}")
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
    if isinstance(value, list | tuple):
        return True
    return isinstance(value, Mapping) and bool(value) and set(value) <= set(RANGE_KEYS)


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
    if not value:
        raise SceneError(f"{where}: empty list; give at least one value in {spec.range_text()}")
    if len(value) > MAX_POINTS:
        raise SceneError(
            f"{where}: {len(value)} values; at most {MAX_POINTS} are allowed (as for {where}.num)"
        )
    return np.array([convert_param(spec, v, f"{where}[{i}]") for i, v in enumerate(value)])


def _loads(value: Any, tensile: bool = False) -> tuple[np.ndarray, bool]:
    spec = CORE["load"]["p0"]
    if tensile:  # the boundary accepts tensile loads (adhesion) and checks their range itself
        spec = dataclasses.replace(spec, bounds=(None, None))
    if is_sweep_value(spec, value):
        arr = sweep_values(spec, value, "load.p0")
        if not isinstance(value, Mapping) and np.any(np.diff(arr) <= 0):
            raise SceneError("load.p0: loads must be strictly increasing")
        return arr, False
    return np.array([convert_param(spec, value, "load.p0")]), True


def _plugin(
    section: str, raw: Mapping[str, Any] | None, registry: Registry, base: Path | None = None
) -> tuple[Plugin, str, dict[str, Any]]:
    group = PLUGIN_SECTIONS[section]
    raw = dict(raw or {})
    model = raw.pop("model", DEFAULT_MODEL.get(section))
    if model is None:
        raise SceneError(
            f"{section}.model: required; choose one of "
            f"{', '.join(registry.names(group)) or 'none installed'}"
        )
    try:
        cls = registry.resolve(group, model)
    except PluginError as exc:
        raise SceneError(f"{section}.model: {exc}") from None
    except TypeError as exc:
        raise SceneError(f"{section}.model: {exc}") from None
    params = convert_params(cls.parameters, raw, section)
    params = _absolute_paths(cls.parameters, params, base)
    try:
        inst = cls(**params)
    except (ValueError, TypeError) as exc:
        raise SceneError(plugin_message(section, cls, exc)) from None
    name = model if isinstance(model, str) else registry.name_of(group, cls)[0]
    return inst, name, params


def plugin_message(section: str, cls: Any, exc: BaseException) -> str:
    """``"section.param: ..."`` when a plugin's message starts with one of its parameters."""
    msg = str(exc)
    head = re.split(r"[\s:=]", msg, maxsplit=1)[0]
    if head in getattr(cls, "parameters", {}):
        return f"{section}.{msg}"
    return f"{section}: {msg}"


def _absolute_paths(
    specs: Mapping[str, ParamSpec], params: dict[str, Any], base: Path | None
) -> dict[str, Any]:
    """Paths in a scene file are relative to the file's folder."""
    out = dict(params)
    for name, spec in specs.items():
        value = out.get(name)
        if spec.kind == "path" and isinstance(value, str):
            path = Path(value).expanduser()
            if not path.is_absolute() and base is not None:
                path = base / path
            out[name] = str(path)
    return out


def _build_spectrum(spectrum: Plugin, name: str, registry: Registry) -> Any:
    """Build the numerical spectrum and check it (cut-offs, nodes, C finite and >= 0)."""
    from . import _checks

    who = _checks.plugin_label("spectra", spectrum, registry, name)
    try:
        with _checks.calling(who, "build()", passthrough=(ValueError,)):
            psd = spectrum.build()
    except ValueError as exc:
        raise SceneError(plugin_message("spectrum", type(spectrum), exc)) from None
    _checks.check_spectrum(psd, who)
    ratio = float(psd.q_1) / float(psd.q_L)
    if ratio > MAX_ZETA:
        raise SceneError(
            f"spectrum: q_1/q_L = {ratio:g} exceeds the largest magnification "
            f"{MAX_ZETA:g}; allowed q_1/q_L in (1, {MAX_ZETA:g}]"
        )
    return psd


def _check_method(method: Any) -> None:
    from .engine import EngineMethod
    from .engine._methods import METHODS

    if isinstance(method, type):
        if not issubclass(method, EngineMethod):
            raise SceneError(
                f"solver.method: {method!r} is not an xpersson.engine.EngineMethod subclass"
            )
        return
    if method != "auto" and method not in METHODS:
        raise SceneError(
            f"solver.method: {method!r} is not an engine method; one of "
            f"{', '.join(['auto', *sorted(METHODS)])}"
        )


def _zeta_grid(out: Mapping[str, Any], zeta_support: float) -> np.ndarray:
    zmax = out["zeta_max"]
    if zmax is not None and zmax > zeta_support * (1 + 1e-12):
        raise SceneError(
            f"output.zeta_max: {zmax:g} exceeds the spectrum's range q_1/q_L = {zeta_support:g}; "
            f"allowed [1, {zeta_support:g}]"
        )
    zmax = min(zmax or zeta_support, zeta_support)
    if out["zeta"] is not None:
        z = np.unique(np.asarray(out["zeta"], float))
        if z[-1] > zeta_support * (1 + 1e-12):
            raise SceneError(
                f"output.zeta: {z[-1]:g} exceeds q_1/q_L = {zeta_support:g}; allowed [1, "
                f"{zeta_support:g}]"
            )
        if z[0] > 1.0:
            z = np.concatenate([[1.0], z])
        return z
    n = max(1, math.ceil(out["zeta_per_decade"] * math.log10(zmax) - 1e-9)) if zmax > 1 else 0
    if n == 0:
        return np.array([1.0])
    z = np.geomspace(1.0, zmax, n + 1)
    z[0], z[-1] = 1.0, zmax
    return z


def _resolve(scene: Scene, registry: Registry) -> ResolvedScene:
    data = scene.data
    unknown = sorted(set(data) - TOP_LEVEL)
    if unknown:
        raise SceneError(
            f"{unknown[0]}: unknown section or key; allowed: {', '.join(sorted(TOP_LEVEL))}"
        )
    if "sweep" in data:
        raise SceneError(
            "sweep: a sweep scene is solved point by point; use xpersson.solve "
            "(or xpersson.sweep.expand to list its points)"
        )
    for key in ("title", "description"):
        if key in data and not isinstance(data[key], str):
            raise SceneError(f"{key}: must be a string")
    for sec in (*CORE, *PLUGIN_SECTIONS, "analyses"):
        if sec in data and not isinstance(data[sec], Mapping):
            raise SceneError(f"{sec}: must be a table, got {type(data[sec]).__name__}")
    if "spectrum" not in data:
        raise SceneError("spectrum: required section (e.g. model = 'self_affine')")
    if "load" not in data or "p0" not in data["load"]:
        raise SceneError("load.p0: required (nominal pressure, e.g. '1 MPa')")
    material = convert_params(CORE["material"], data.get("material", {}), "material")
    load_raw = dict(data["load"])
    p0_raw = load_raw.pop("p0")
    if load_raw:
        raise SceneError(f"load.{sorted(load_raw)[0]}: unknown parameter; allowed in [load]: p0")
    p0, scalar = _loads(p0_raw, tensile=True)  # sign checked once the boundary is known
    out = convert_params(CORE["output"], data.get("output", {}), "output")
    solver = convert_params(CORE["solver"], data.get("solver", {}), "solver")
    if out["p"] is not None and np.any(np.diff(out["p"]) <= 0):
        raise SceneError("output.p: the pressure grid must be strictly increasing")
    if out["p"] is not None and out["p"].size < 2:
        raise SceneError(
            "output.p: give at least 2 pressures (a grid to integrate P over) in "
            + CORE["output"]["p"].range_text()
        )
    _check_method(solver["method"])

    names: dict[str, str] = {}
    plugins: dict[str, Plugin] = {}
    resolved: dict[str, Any] = {k: data[k] for k in ("title", "description") if k in data}
    for section in PLUGIN_SECTIONS:
        base = Path(scene.source).parent if scene.source else None
        inst, name, params = _plugin(section, data.get(section), registry, base)
        plugins[section], names[section] = inst, name
        resolved[section] = {"model": name, **_jsonable(params, type(inst).parameters)}
    if not getattr(type(plugins["boundary"]), "tensile_loads", False) and np.any(p0 <= 0):
        _loads(p0_raw)  # raises the range error of a compressive-only boundary
    psd = _build_spectrum(plugins["spectrum"], names["spectrum"], registry)
    archived = getattr(plugins["spectrum"], "archived_params", None)
    if callable(archived):  # file-based spectra: the table itself goes into the archive
        spec_cls = type(plugins["spectrum"])
        resolved["spectrum"] = {
            "model": names["spectrum"],
            **_jsonable(archived(psd), spec_cls.parameters),
        }
    zeta = _zeta_grid(out, float(psd.q_1 / psd.q_L))

    requested = data.get("analyses", {})
    analyses: list[tuple[str, Plugin]] = []
    for name, params in requested.items():
        if not isinstance(params, Mapping):
            raise SceneError(f"analyses.{name}: must be a table of the analysis' parameters")
    resolved["analyses"] = {}
    if requested:
        from .plugins._analyses import plan_analyses  # noqa: PLC0415 - only when asked for

        try:
            from .schema import COORDS, CORE_VARIABLES  # noqa: PLC0415

            available = set(CORE_VARIABLES) | set(COORDS)
            for section in ("coefficient", "boundary"):
                available |= set(type(plugins[section]).outputs)
            plan = plan_analyses(requested, available, registry)
        except (PluginError, ValueError) as exc:
            raise SceneError(f"analyses: {exc}") from None
        for name, cls, raw in plan:
            params = convert_params(cls.parameters, raw, f"analyses.{name}")
            try:
                inst = cls(**params)
                inst.check_scene(plugins["coefficient"], plugins["boundary"])
                analyses.append((name, inst))
            except (ValueError, TypeError) as exc:
                msg = plugin_message(f"analyses.{name}", cls, exc)
                raise SceneError(
                    f"{msg} (scene: boundary {names['boundary']!r}, "
                    f"coefficient {names['coefficient']!r})"
                ) from None
            # the instance's parameters: defaults it resolved (e.g. a gamma) are recorded too
            resolved["analyses"][name] = _jsonable(dict(inst.params), cls.parameters)
    resolved["material"] = _jsonable(material, CORE["material"])
    resolved["load"] = {"p0": _resolved_loads(p0_raw, p0, scalar)}
    resolved["output"] = _jsonable(out, CORE["output"])
    resolved["output"].pop("zeta_per_decade", None)
    resolved["output"]["zeta"] = np.asarray(zeta, float).tolist()
    resolved["solver"] = _jsonable(solver, CORE["solver"])
    return ResolvedScene(
        scene=scene,
        spectrum=plugins["spectrum"],
        coefficient=plugins["coefficient"],
        boundary=plugins["boundary"],
        analyses=analyses,
        psd=psd,
        E=material["E"],
        nu=material["nu"],
        p0=p0,
        p0_scalar=scalar,
        zeta=zeta,
        pressure_pdf=bool(out["pressure_pdf"]) or out["p"] is not None,
        p=None if out["p"] is None else np.asarray(out["p"], float),
        p_points=int(out["p_points"]),
        p_max=out["p_max"],
        rtol=float(solver["rtol"]),
        atol=float(solver["atol"]),
        method=solver["method"],
        plugin_names=names,
        resolved=resolved,
        solver_options={k: int(solver[k]) for k in ("walkers", "seed") if solver[k] is not None},
    )


def _resolved_loads(raw: Any, p0: np.ndarray, scalar: bool) -> Any:
    """``load.p0`` of the resolved scene: re-loads to exactly ``p0``.

    A range table stays a range table (its end points are the first and last loads exactly,
    ``geomspace``/``linspace`` reproduce the values in between): a 1000-load sweep costs no
    1000 formatted strings in the scene and its JSON. Lists and scalars: one string per load.
    """
    values = np.asarray(p0, float).tolist()
    if isinstance(raw, Mapping) and len(values) == raw.get("num"):
        return {
            "start": f"{values[0]!r} Pa",
            "stop": f"{values[-1]!r} Pa",
            "num": len(values),
            "spacing": raw.get("spacing", "log"),
        }
    loads = [f"{v!r} Pa" for v in values]
    return loads[0] if scalar else loads


def _jsonable(
    params: Mapping[str, Any], specs: Mapping[str, ParamSpec] | None = None
) -> dict[str, Any]:
    """JSON-able copy of resolved values; dimensional quantities as ``"value unit"`` strings so
    that the resolved scene re-loads as a scene."""
    out: dict[str, Any] = {}
    for k, v in params.items():
        spec = (specs or {}).get(k)
        dimensional = spec is not None and spec.kind == "quantity" and spec.unit not in ("1", "")
        if v is None:
            continue
        if dimensional and isinstance(v, np.ndarray):
            out[k] = [f"{float(x)!r} {spec.unit}" for x in v]
        elif dimensional and isinstance(v, int | float):
            out[k] = f"{float(v)!r} {spec.unit}"
        elif isinstance(v, np.ndarray):
            out[k] = [float(x) for x in v]
        elif isinstance(v, type):
            out[k] = f"{v.__module__}:{v.__qualname__}"
        elif isinstance(v, np.generic):
            out[k] = v.item()
        else:
            out[k] = v
    return out
