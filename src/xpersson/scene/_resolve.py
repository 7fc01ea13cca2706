"""Resolution: a scene's sections checked and converted into plugins and SI arrays.

Everything is checked before any work starts (see :mod:`xpersson.scene`). Resolution also
captures what a run needs of the registry: the plugins' labels for messages and their
provenance records (:attr:`ResolvedScene.labels`, :attr:`ResolvedScene.plugin_records`).
"""

from __future__ import annotations

import dataclasses
import math
import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from ..checks import calling, check_spectrum, plugin_label
from ..errors import SceneError
from ..plugins import ParamSpec, Plugin, PluginError, Registry
from ._convert import (
    archived_section,
    convert_param,
    convert_params,
    jsonable,
    loads,
    resolved_loads,
)
from ._core import (
    CORE,
    DEFAULT_MODEL,
    MAX_ZETA,
    PLUGIN_SECTIONS,
    ResolvedScene,
    log_grid,
)
from ._geometry import check_plugins, geometry_part, is_flat, pressure_grid
from ._shape import check_method, check_sections

__all__ = ["analysis_plan", "plugin_message", "plugin_records", "resolve_scene", "with_spectrum"]


def _plugin(
    section: str,
    raw: Mapping[str, Any] | None,
    registry: Registry,
    base: Path | None = None,
    memo: dict[Any, Any] | None = None,
) -> tuple[Plugin, str, dict[str, Any]]:
    """The plugin instance of a scene section, its name and its converted parameters
    (``memo``: values converted before, by parameter, type and value; see :func:`_convert`)."""
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
    except (PluginError, TypeError) as exc:
        raise SceneError(f"{section}.model: {exc}") from None
    params = _convert(cls.parameters, raw, section, memo)
    params = _absolute_paths(cls.parameters, params, base)
    try:
        inst = cls(**params)
    except (ValueError, TypeError) as exc:
        raise SceneError(plugin_message(section, cls, exc)) from None
    name = model if isinstance(model, str) else registry.name_of(group, cls)[0]
    return inst, name, params


def _convert(
    specs: Mapping[str, ParamSpec],
    raw: Mapping[str, Any],
    section: str,
    memo: dict[Any, Any] | None,
) -> dict[str, Any]:
    """:func:`convert_params`, each hashable value converted once per ``memo`` (a sweep over
    one spectrum parameter converts the others once: the same values, the same results)."""
    if memo is None:
        return convert_params(specs, raw, section)
    if not set(raw) <= set(specs) or any(s.required and n not in raw for n, s in specs.items()):
        return convert_params(specs, raw, section)  # its messages
    out: dict[str, Any] = {}
    for name, spec in specs.items():
        if name not in raw:
            out[name] = spec.default
            continue
        value = raw[name]
        if type(value) not in (str, float, int, bool):  # a list, a Quantity: each time
            out[name] = convert_param(spec, value, f"{section}.{name}")
            continue
        key = (section, name, type(value), value)
        if key not in memo:
            memo[key] = convert_param(spec, value, f"{section}.{name}")
        out[name] = memo[key]
    return out


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


def _build_spectrum(spectrum: Plugin, who: Any) -> Any:
    """Build the numerical spectrum and check it (cut-offs, nodes, C finite and >= 0)."""
    try:
        with calling(who, "build()", passthrough=(ValueError,)):
            psd = spectrum.build()
    except ValueError as exc:
        raise SceneError(plugin_message("spectrum", type(spectrum), exc)) from None
    check_spectrum(psd, who)
    ratio = float(psd.q_1) / float(psd.q_L)
    if ratio > MAX_ZETA:
        raise SceneError(
            f"spectrum: q_1/q_L = {ratio:g} exceeds the largest magnification "
            f"{MAX_ZETA:g}; allowed q_1/q_L in (1, {MAX_ZETA:g}]"
        )
    return psd


def _zeta_grid(out: Mapping[str, Any], zeta_support: float) -> np.ndarray:
    """The output magnifications: explicit, or log-spaced up to ``zeta_max`` (from 1)."""
    zmax = out["zeta_max"]
    if zmax is not None and zmax > zeta_support * (1 + 1e-12):
        raise SceneError(
            f"output.zeta_max: {zmax:g} exceeds the spectrum's range q_1/q_L = {zeta_support:g}; "
            f"allowed [1, {zeta_support:g}]"
        )
    zmax = min(zmax or zeta_support, zeta_support)
    if out["zeta"] is not None:
        z = np.array(out["zeta"], float)
        if z.ndim != 1 or not bool(np.all(z[1:] > z[:-1])):  # sorted and distinct: as given
            z = np.unique(z)
        if z[-1] > zeta_support * (1 + 1e-12):
            raise SceneError(
                f"output.zeta: {z[-1]:g} exceeds q_1/q_L = {zeta_support:g}; allowed [1, "
                f"{zeta_support:g}]"
            )
        if z[0] > 1.0:
            z = np.concatenate([[1.0], z])
        return z
    n = max(1, math.ceil(out["zeta_per_decade"] * math.log10(zmax) - 1e-9)) if zmax > 1 else 0
    return np.array([1.0]) if n == 0 else log_grid(n, zmax)


def _check_power(psd: Any, zeta: np.ndarray) -> None:
    """Every output interval adds roughness: the diffusion time grows strictly in zeta.

    A band where the PSD carries no power (a map with a short-wavelength cutoff, round-off
    above it) leaves ``int q^3 C`` flat in floating point and the solve undefined there.
    """
    q = zeta * float(psd.q_L)
    flat = np.flatnonzero(np.diff(np.asarray(psd.I3(q), dtype=float)) <= 0)
    if flat.size:
        a, b = q[flat[0]], q[flat[-1] + 1]
        raise SceneError(
            f"spectrum: the PSD carries no power (int q^3 C does not grow) between q = {a:.4g} "
            f"and {b:.4g} 1/m, so the contact does not change over output.zeta "
            f"{zeta[flat[0]]:.4g}..{zeta[flat[-1] + 1]:.4g}; set spectrum.q_1 <= {a:.4g} 1/m "
            "(or output.zeta_max) to end the spectrum where its roughness ends"
        )


def _core_sections(data: Mapping[str, Any]) -> dict[str, Any]:
    """The converted core sections: material, loads (raw and Pa), output and solver."""
    material = convert_params(CORE["material"], data.get("material", {}), "material")
    load_raw = dict(data["load"])
    load_raw.pop("force", None)  # a finite body's (checked by check_load_keys)
    p0_raw = load_raw.pop("p0", "1 Pa")  # a body's pressures are a grid (see resolve_scene)
    if load_raw:
        raise SceneError(f"load.{sorted(load_raw)[0]}: unknown parameter; allowed in [load]: p0")
    p0, scalar = loads(p0_raw, tensile=True)  # sign checked once the boundary is known
    out = convert_params(CORE["output"], data.get("output", {}), "output")
    solver = convert_params(CORE["solver"], data.get("solver", {}), "solver")
    if out["p"] is not None and np.any(np.diff(out["p"]) <= 0):
        raise SceneError("output.p: the pressure grid must be strictly increasing")
    if out["p"] is not None and out["p"].size < 2:
        raise SceneError(
            "output.p: give at least 2 pressures (a grid to integrate P over) in "
            + CORE["output"]["p"].range_text()
        )
    check_method(solver["method"])
    return {
        "material": material,
        "p0_raw": p0_raw,
        "p0": p0,
        "scalar": scalar,
        "output": out,
        "solver": solver,
    }


def analysis_plan(
    requested: Mapping[str, Any], sections: Mapping[str, type], registry: Registry
) -> list[tuple[str, type, dict[str, Any]]]:
    """:func:`xpersson.plugins.plan_analyses` of a scene's analyses (providers first) for its
    plugin classes (``sections``: section -> class, whose outputs are there already)."""
    from ..plugins import plan_analyses  # noqa: PLC0415 - only when asked for
    from ..schema import COORDS, CORE_VARIABLES  # noqa: PLC0415

    available = set(CORE_VARIABLES) | set(COORDS)
    for section in ("coefficient", "boundary"):
        available |= set(sections[section].outputs)  # type: ignore[attr-defined]
    try:
        return plan_analyses(requested, available, registry)
    except (PluginError, ValueError) as exc:
        raise SceneError(f"analyses: {exc}") from None


def _analyses(
    requested: Mapping[str, Any], plugins: Mapping[str, Any], names: Any, registry: Registry
) -> list[tuple[str, Plugin]]:
    """The requested analyses and their providers, planned, instantiated and checked."""
    for name, params in requested.items():
        if not isinstance(params, Mapping):
            raise SceneError(f"analyses.{name}: must be a table of the analysis' parameters")
    if not requested:
        return []
    plan = analysis_plan(requested, {s: type(p) for s, p in plugins.items()}, registry)
    analyses: list[tuple[str, Plugin]] = []
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
    return analyses


def plugin_records(
    plugins: Mapping[str, Plugin],
    names: Mapping[str, str],
    analyses: list[tuple[str, Plugin]],
    registry: Registry,
    body: Any = None,
) -> tuple[tuple[tuple[dict[str, Any], str | None], ...], str]:
    """``(provenance record, name)`` of every plugin: spectrum, coefficient, boundary,
    analyses, a finite body's geometry (the records are the registry's shared read-only ones),
    and their JSON text (the registry's, made once per record and name: ``json.dumps`` of the
    list, sorted keys)."""
    items = [(PLUGIN_SECTIONS[s], names.get(s), type(plugins[s])) for s in PLUGIN_SECTIONS]
    items += [("analyses", name, type(inst)) for name, inst in analyses]
    if body is not None:
        items.append(("geometries", body.name, type(body.geometry)))
    records = tuple((registry.provenance(group, cls), name) for group, name, cls in items)
    texts = [registry.provenance_json(group, cls, name) for group, name, cls in items]
    return records, "[" + ", ".join(texts) + "]"


def resolve_scene(scene: Any, registry: Registry) -> ResolvedScene:
    """Validate and resolve a :class:`~xpersson.scene.Scene` (see :meth:`Scene.resolve`)."""
    data = scene.data
    check_sections(data)
    core = _core_sections(data)
    out, solver, p0 = core["output"], core["solver"], core["p0"]

    body = None
    if not is_flat(data):
        E_star = core["material"]["E"] / (1.0 - core["material"]["nu"] ** 2)
        body = geometry_part(data, registry, E_star)
        p0 = core["p0"] = pressure_grid(body, E_star)
        core["scalar"] = False
    names: dict[str, str] = {}
    plugins: dict[str, Plugin] = {}
    resolved = {k: data[k] for k in ("title", "description", "metadata") if k in data}
    for section in PLUGIN_SECTIONS:
        base = Path(scene.source).parent if scene.source else None
        inst, name, params = _plugin(section, data.get(section), registry, base)
        plugins[section], names[section] = inst, name
        resolved[section] = archived_section(name, inst, params, section != "spectrum")
    if body is not None:
        check_plugins(plugins, body.name)
    if not getattr(type(plugins["boundary"]), "tensile_loads", False) and np.any(p0 <= 0):
        loads(core["p0_raw"])  # raises the range error of a compressive-only boundary
    labels: dict[str, Any] = {
        s: plugin_label(s, plugins[s], registry, names[s]) for s in PLUGIN_SECTIONS
    }
    psd, zeta = _spectrum_and_grid(plugins["spectrum"], labels["spectrum"], out, resolved, names)

    analyses = _analyses(data.get("analyses", {}), plugins, names, registry)
    resolved["analyses"] = {}
    for name, inst in analyses:
        labels[f"analyses.{name}"] = plugin_label("analyses", inst, registry, name)
        # the instance's parameters: defaults it resolved (e.g. a gamma) are recorded too
        resolved["analyses"][name] = jsonable(dict(inst.params), type(inst).parameters)
    resolved["material"] = jsonable(core["material"], CORE["material"])
    resolved["load"] = {"p0": resolved_loads(core["p0_raw"], p0, core["scalar"])}
    records, records_json = plugin_records(plugins, names, analyses, registry, body)
    if body is not None:
        resolved["geometry"], resolved["load"] = body.resolved, {"force": body.force_resolved}
        labels["geometry"] = plugin_label("geometry", body.geometry, registry, body.name)
    resolved["output"] = jsonable(out, CORE["output"])
    resolved["output"].pop("zeta_per_decade", None)
    if resolved["output"].get("model_error") is True:  # the default: archives stay as before
        resolved["output"].pop("model_error")
    resolved["output"]["zeta"] = np.asarray(zeta, float).tolist()
    resolved["solver"] = jsonable(solver, CORE["solver"])
    return ResolvedScene(
        scene=scene,
        spectrum=plugins["spectrum"],
        coefficient=plugins["coefficient"],
        boundary=plugins["boundary"],
        analyses=analyses,
        psd=psd,
        E=core["material"]["E"],
        nu=core["material"]["nu"],
        p0=p0,
        p0_scalar=core["scalar"],
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
        labels=labels,
        plugin_records=records,
        plugin_records_json=records_json,
        plugin_time_limit=solver["plugin_time_limit"],
        geometry=None if body is None else body.geometry,
        force=None if body is None else body.force,
        force_scalar=body is not None and body.scalar,
    )


def _spectrum_and_grid(
    spectrum: Plugin,
    label: Any,
    out: Mapping[str, Any],
    resolved: dict[str, Any],
    names: Mapping[str, str],
    memo: dict[Any, Any] | None = None,
) -> tuple[Any, np.ndarray]:
    """The built and checked spectrum and the output grid on it (a file-based spectrum's
    table replaces ``resolved["spectrum"]``; ``memo``: the grid of each ``q_1/q_L`` made
    once per sweep, read only)."""
    psd = _build_spectrum(spectrum, label)
    archived = getattr(spectrum, "archived_params", None)
    if callable(archived):  # file-based spectra: the table itself goes into the archive
        resolved["spectrum"] = {
            "model": names["spectrum"],
            **jsonable(archived(psd), type(spectrum).parameters),
        }
    support = float(psd.q_1 / psd.q_L)
    if memo is None:
        zeta = _zeta_grid(out, support)
    else:
        if ("[zeta]", support) not in memo:
            memo[("[zeta]", support)] = _zeta_grid(out, support)
            memo[("[zeta]", support)].flags.writeable = False
        zeta = memo[("[zeta]", support)]
    _check_power(psd, zeta)
    return psd, zeta


def _output_once(
    raw: Mapping[str, Any], memo: dict[Any, Any] | None
) -> tuple[dict[str, Any], dict[Any, Any] | None]:
    """``[output]`` converted once per sweep (``memo``; the same section at every point of a
    spectral sweep) and the memo of its grids (``None``: a section other than the first)."""
    if memo is None:
        return convert_params(CORE["output"], raw, "output"), None
    if "[output]" not in memo:
        memo["[output]"] = (raw, convert_params(CORE["output"], raw, "output"))
    first, out = memo["[output]"]
    if raw is not first and raw != first:
        return convert_params(CORE["output"], raw, "output"), None
    return out, memo


def with_spectrum(
    rs: ResolvedScene, scene: Any, registry: Registry, memo: dict[Any, Any] | None = None
) -> ResolvedScene:
    """``scene`` resolved as :func:`resolve_scene` would, when it differs from the scene of
    ``rs`` (resolved with the same registry) only in its ``[spectrum]`` section: only the
    spectrum, its checks and the output grid are made again; the other sections' plugins,
    conversions and checks are those of ``rs`` (a sweep over spectrum parameters). ``memo``
    (a dict kept between the calls of one sweep) converts each spectrum value once."""
    data = scene.data
    base = Path(scene.source).parent if scene.source else None
    inst, name, params = _plugin("spectrum", data.get("spectrum"), registry, base, memo)
    names = {**rs.plugin_names, "spectrum": name}
    labels = {**rs.labels, "spectrum": plugin_label("spectrum", inst, registry, name)}
    resolved = {
        **rs.resolved,
        "spectrum": {"model": name, **jsonable(params, type(inst).parameters)},
    }
    out, grids = _output_once(data.get("output", {}), memo)
    psd, zeta = _spectrum_and_grid(inst, labels["spectrum"], out, resolved, names, grids)
    resolved["output"] = {**rs.resolved["output"], "zeta": np.asarray(zeta, float).tolist()}
    records, records_json = rs.plugin_records, rs.plugin_records_json
    if type(inst) is not type(rs.spectrum) or name != rs.plugin_names.get("spectrum"):
        records, records_json = plugin_records(
            {"spectrum": inst, "coefficient": rs.coefficient, "boundary": rs.boundary},
            names,
            rs.analyses,
            registry,
        )
    return dataclasses.replace(
        rs,
        scene=scene,
        spectrum=inst,
        psd=psd,
        zeta=zeta,
        plugin_names=names,
        resolved=resolved,
        labels=labels,
        plugin_records=records,  # the same plugin classes and names: the same records
        plugin_records_json=records_json,
    )
