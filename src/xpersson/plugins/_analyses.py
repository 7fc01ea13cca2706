"""The analysis planner: which analyses run, and in which order.

A scene asks for some analyses by name (``[analyses.<name>]`` tables). Each analysis declares
the Dataset variables it ``requires`` and ``provides``. :func:`plan_analyses` adds, transitively,
the registered analyses that provide any required variable the core does not compute, and
orders everything so that providers run before consumers.

Registered analyses are imported only when a requirement is not met by the core and the
requested analyses; a broken analysis plugin is then skipped with a warning.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from typing import Any

from ._registry import PluginError, Registry, get_registry

__all__ = ["plan_analyses", "PlanError"]

GROUP = "analyses"


class PlanError(ValueError):
    """The requested analyses cannot be planned (cycle, conflict, unsatisfiable requirement)."""


def plan_analyses(
    requested: Mapping[Any, Mapping[str, Any] | None],
    available: set[str] | frozenset[str],
    registry: Registry | None = None,
) -> list[tuple[str, type, dict[str, Any]]]:
    """Plan the analyses of a scene.

    Parameters
    ----------
    requested : Mapping
        Analyses the scene asks for: name (``"name"`` or ``"dist:name"``; a class is also
        accepted) -> raw parameters (as given in the scene, not yet converted).
    available : set of str
        Variables the core Dataset already holds (they satisfy requirements by themselves).
    registry : Registry, optional
        Where names are looked up and providers are searched (default registry if omitted).

    Returns
    -------
    list of (name, class, params)
        Every analysis to run, providers before consumers. ``params`` is a copy of the raw
        parameters for requested analyses and ``{}`` for analyses added as providers.

    Raises
    ------
    PlanError
        A dependency cycle (the message lists it), two analyses providing one variable (the
        message names both), an unsatisfiable requirement (the message names the variable
        and the analysis), or a provider that would need parameters the scene does not give.
    PluginError
        A requested analysis is unknown or broken.
    """
    reg = registry if registry is not None else get_registry()
    available = set(available)
    selected: dict[str, tuple[type, dict[str, Any]]] = {}
    provider: dict[str, str] = {}

    def add(name: str, cls: type, params: dict[str, Any]) -> None:
        for other, (ocls, _) in selected.items():
            if ocls is cls:
                raise PlanError(
                    f"analysis {cls.__qualname__} requested twice ({other!r}, {name!r})"
                )
        selected[name] = (cls, params)
        for var in cls.provides:  # type: ignore[attr-defined]
            if var in provider:
                raise PlanError(
                    f"variable {var!r} is provided by two analyses, {provider[var]!r} and "
                    f"{name!r}; request only one of them"
                )
            provider[var] = name

    for key, raw in requested.items():
        cls = reg.resolve(GROUP, key)
        name = key if isinstance(key, str) else reg.name_of(GROUP, cls)[0]
        add(name, cls, dict(raw or {}))

    candidates: dict[str, list[tuple[str, type]]] | None = None
    queue = list(selected)
    while queue:
        consumer = queue.pop(0)
        for var in selected[consumer][0].requires:  # type: ignore[attr-defined]
            if var in available or var in provider:
                continue
            if candidates is None:
                candidates = _provider_index(reg)
            found = [
                (n, c)
                for n, c in candidates.get(var, [])
                if not any(c is sc for sc, _ in selected.values())
            ]
            if not found:
                others = _plugin_providers(reg, var)
                hint = (
                    "; it is provided by " + ", ".join(others) + ": select one in the scene"
                    if others
                    else ""
                )
                raise PlanError(
                    f"analysis {consumer!r} requires variable {var!r}, which neither the core, "
                    f"the scene's coefficient and boundary, nor any installed analysis "
                    f"provides{hint}"
                )
            if len(found) > 1:
                names = " and ".join(repr(n) for n, _ in found)
                raise PlanError(
                    f"variable {var!r} (required by analysis {consumer!r}) is provided by "
                    f"two analyses, {names}; request the one to use in the scene"
                )
            pname, pcls = found[0]
            missing = [p for p, spec in pcls.parameters.items() if spec.required]  # type: ignore[attr-defined]
            if missing:
                raise PlanError(
                    f"analysis {pname!r} (needed for variable {var!r} required by {consumer!r}) "
                    f"needs parameter(s) {missing}; request it as [analyses.{pname}]"
                )
            add(pname, pcls, {})
            queue.append(pname)

    return [(n, *selected[n]) for n in _order(selected, provider, available)]


def _plugin_providers(reg: Registry, var: str) -> list[str]:
    """Installed coefficients/boundaries that declare ``var`` among their outputs."""
    out = []
    for group, section in (("coefficients", "coefficient"), ("boundaries", "boundary")):
        for name in reg.names(group):
            try:
                cls = reg.load(group, name)
            except PluginError:
                continue
            if var in getattr(cls, "outputs", {}):
                out.append(f"{section} {name!r} ({reg.info(group, name).dist})")
    return out


def _provider_index(reg: Registry) -> dict[str, list[tuple[str, type]]]:
    """Load every registered analysis (skipping broken ones) and index them by variable."""
    index: dict[str, list[tuple[str, type]]] = {}
    for name, bucket in reg.entries(GROUP).items():
        for info in bucket:
            spec = name if len(bucket) == 1 else info.qualified
            try:
                cls = reg.load(GROUP, spec)
            except PluginError as exc:
                warnings.warn(f"skipping broken analysis plugin: {exc}", stacklevel=3)
                continue
            for var in cls.provides:  # type: ignore[attr-defined]
                index.setdefault(var, []).append((spec, cls))
    return index


def _order(
    selected: dict[str, tuple[type, dict[str, Any]]],
    provider: dict[str, str],
    available: set[str],
) -> list[str]:
    """Depth-first topological order (providers first), stable in selection order."""
    deps = {
        name: [
            (var, provider[var])
            for var in cls.requires  # type: ignore[attr-defined]
            if var not in available and var in provider
        ]
        for name, (cls, _) in selected.items()
    }
    order: list[str] = []
    state: dict[str, int] = {}  # 1 = on the stack, 2 = done
    stack: list[tuple[str, str | None]] = []  # (analysis, variable that led here)

    def visit(name: str, via: str | None) -> None:
        if state.get(name) == 2:
            return
        if state.get(name) == 1:
            start = next(i for i, (n, _) in enumerate(stack) if n == name)
            loop = stack[start:] + [(name, via)]
            chain = " -> ".join(n for n, _ in loop)
            why = "; ".join(
                f"{a} requires {v!r} from {b}"
                for (a, _), (b, v) in zip(loop[:-1], loop[1:], strict=True)
            )
            raise PlanError(f"dependency cycle among analyses: {chain} ({why})")
        state[name] = 1
        stack.append((name, via))
        for var, dep in deps[name]:
            visit(dep, var)
        stack.pop()
        state[name] = 2
        order.append(name)

    for name in selected:
        visit(name, None)
    return order
