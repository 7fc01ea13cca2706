"""The ``xpersson plugins`` sub-command: list and describe installed plugins.

``xpersson plugins list [--group G] [--json] [--check]`` reads entry-point metadata only and
imports no plugin module (status ``"not loaded"``) unless ``--check`` asks to import every
plugin and report the broken ones. ``xpersson plugins show GROUP NAME`` imports one plugin and
prints its parameters (units, defaults, bounds), outputs, references, version and summary.

Results go to stdout, messages to stderr. This module imports neither numpy, xarray nor scipy.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import sys
import warnings
from collections.abc import Iterator, Sequence
from typing import Any, TextIO

from .plugins import (
    GROUP_NAMES,
    PluginError,
    PluginInfo,
    Registry,
    get_registry,
    normalize_group,
)

__all__ = ["register", "main", "cmd_list", "cmd_show", "describe"]


def register(subparsers: Any) -> argparse.ArgumentParser:
    """Add the ``plugins`` sub-command to an argparse sub-parser collection.

    Parameters
    ----------
    subparsers
        The object returned by ``ArgumentParser.add_subparsers()``.

    Returns
    -------
    argparse.ArgumentParser
        The ``plugins`` parser; every leaf sets ``func(args) -> int`` (exit code).
    """
    p = subparsers.add_parser(
        "plugins",
        help="list and describe installed plugins",
        description="List and describe the installed xpersson plugins (entry points).",
    )
    p.set_defaults(func=_usage(p))
    sub = p.add_subparsers(dest="plugins_command", metavar="{list,show}")

    pl = sub.add_parser("list", help="list plugins (imports none unless --check)")
    pl.add_argument("--group", "-g", type=_group, help=f"one of {', '.join(GROUP_NAMES)}")
    pl.add_argument("--json", action="store_true", help="machine-readable output")
    pl.add_argument(
        "--check", action="store_true", help="import every plugin and report broken ones"
    )
    pl.add_argument(
        "--time-limit",
        type=float,
        default=IMPORT_TIME_LIMIT,
        metavar="S",
        help=f"with --check: seconds an import may take (default {IMPORT_TIME_LIMIT:g}); "
        "a slower one is reported broken",
    )
    pl.set_defaults(func=cmd_list)

    ps = sub.add_parser("show", help="describe one plugin (imports it)")
    ps.add_argument("group", type=_group, help=f"one of {', '.join(GROUP_NAMES)}")
    ps.add_argument("name", help="plugin name or dist:name")
    ps.add_argument("--json", action="store_true", help="machine-readable output")
    ps.set_defaults(func=cmd_show)
    return p


IMPORT_TIME_LIMIT = 60.0
"""Seconds a plugin import may take under ``plugins list --check``."""


def _group(text: str) -> str:
    try:
        return normalize_group(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def _usage(parser: argparse.ArgumentParser) -> Any:
    def run(args: argparse.Namespace) -> int:
        parser.print_help(sys.stderr)
        return 2

    return run


def cmd_list(
    args: argparse.Namespace, registry: Registry | None = None, out: TextIO | None = None
) -> int:
    """``xpersson plugins list``; returns 1 with ``--check`` if a plugin is broken."""
    out = out or sys.stdout
    reg = registry or get_registry()
    with _warnings_to_stderr():
        limit = getattr(args, "time_limit", IMPORT_TIME_LIMIT)
        if not limit > 0:
            print("xpersson: --time-limit must be > 0 seconds", file=sys.stderr)
            return 2
        infos = reg.check(args.group, limit) if args.check else list(reg.infos(args.group))
    if args.json:
        json.dump([i.as_dict() for i in infos], out, indent=2)
        out.write("\n")
    else:
        _table(infos, out)
    broken = [i for i in infos if i.error]
    for i in broken:
        print(f"error: {i.group} plugin {i.qualified}: {i.error}", file=sys.stderr)
    return 1 if (args.check and broken) else 0


@contextlib.contextmanager
def _warnings_to_stderr() -> Iterator[None]:
    """Report warnings (duplicate names, skipped entry points) as plain stderr messages."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            yield
        finally:
            for w in caught:
                print(f"warning: {w.message}", file=sys.stderr)


def _table(infos: list[PluginInfo], out: TextIO) -> None:
    head = ("group", "name", "distribution", "version", "status")
    rows = [(i.group, i.name, i.dist, i.version, i.status) for i in infos]
    if not rows:
        print("no plugins found", file=sys.stderr)
        return
    widths = [max(len(r[k]) for r in [head, *rows]) for k in range(len(head) - 1)]
    for r in [head, *rows]:
        cells = [c.ljust(w) for c, w in zip(r[:-1], widths, strict=True)]
        out.write("  ".join([*cells, r[-1]]).rstrip() + "\n")


def describe(group: str, name: str, registry: Registry | None = None) -> dict[str, Any]:
    """Everything ``plugins show`` prints, as a JSON-ready dict (imports the plugin)."""
    reg = registry or get_registry()
    group = normalize_group(group)
    cls = reg.load(group, name)
    info = reg.info(group, name)
    params = {}
    for pname, spec in cls.parameters.items():  # type: ignore[attr-defined]
        params[pname] = {
            "unit": spec.unit,
            "default": "REQUIRED" if spec.required else _jsonable(spec.default),
            "range": spec.range_text(),
            "sweepable": spec.sweepable,
            "description": spec.description,
        }
        if spec.example is not None:
            params[pname]["example"] = _jsonable(spec.example)
    outputs = {
        vname: {"dims": list(v.dims), "units": v.units, "long_name": v.long_name}
        for vname, v in cls.outputs.items()  # type: ignore[attr-defined]
    }
    desc: dict[str, Any] = {
        "group": group,
        "name": info.name,
        "distribution": info.dist,
        "version": info.version,
        "class": info.value,
        "api_version": cls.api_version,  # type: ignore[attr-defined]
        "summary": cls.summary,  # type: ignore[attr-defined]
        "references": list(cls.references),  # type: ignore[attr-defined]
        "parameters": params,
        "outputs": outputs,
    }
    if group in ("boundaries", "coefficients"):
        desc["traits"] = sorted(getattr(cls, "traits", ()))
    if group == "analyses":
        desc["requires"] = list(cls.requires)  # type: ignore[attr-defined]
        desc["provides"] = list(cls.provides)  # type: ignore[attr-defined]
        desc["boundary_traits"] = sorted(getattr(cls, "boundary_traits", ()))
        desc["coefficient_traits"] = sorted(getattr(cls, "coefficient_traits", ()))
        desc["boundaries"] = _supported(cls, reg, "boundaries")
        desc["coefficients"] = _supported(cls, reg, "coefficients")
        desc["body_quantities"] = {
            n: {
                "local": q.local,
                "combine": q.combine,
                "units": q.units,
                "long_name": q.long_name,
                "unbounded": getattr(q, "unbounded", None),
            }
            for n, q in cls.body_quantities.items()  # type: ignore[attr-defined]
        }
    return desc


def _supported(cls: Any, reg: Registry, group: str) -> dict[str, list[str]]:
    """Installed plugins of ``group`` the analysis accepts / refuses (by their declared traits)."""
    out: dict[str, list[str]] = {"supported": [], "refused": []}
    supports = getattr(cls, "supports", None)
    for name in reg.names(group):
        try:
            other = reg.load(group, name)
        except PluginError:
            continue
        kw = {"boundary" if group == "boundaries" else "coefficient": other}
        ok = supports is None or supports(**kw) is None
        out["supported" if ok else "refused"].append(name)
    return out


def _jsonable(value: Any) -> Any:
    if value is None or isinstance(value, bool | int | float | str):
        return value
    return repr(value)


def cmd_show(
    args: argparse.Namespace, registry: Registry | None = None, out: TextIO | None = None
) -> int:
    """``xpersson plugins show GROUP NAME``; returns 1 if the plugin is unknown or broken."""
    out = out or sys.stdout
    try:
        with _warnings_to_stderr():
            d = describe(args.group, args.name, registry)
    except PluginError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1
    if getattr(args, "json", False):
        json.dump(d, out, indent=2)
        out.write("\n")
        return 0
    w = out.write
    w(f"{d['group']} plugin {d['name']!r}: {d['summary']}\n")
    w(f"  class:        {d['class']}\n")
    w(f"  distribution: {d['distribution']} {d['version']}\n")
    w(f"  api_version:  {d['api_version']}\n")
    w("  references:   " + (", ".join(d["references"]) or "none") + "\n")
    if "traits" in d:
        w("  traits:       " + (", ".join(d["traits"]) or "none") + "\n")
    if "requires" in d:
        w("  requires:     " + (", ".join(d["requires"]) or "nothing") + "\n")
        w("  provides:     " + (", ".join(d["provides"]) or "nothing") + "\n")
        for kind, plural in (("boundary", "boundaries"), ("coefficient", "coefficients")):
            sup = d[plural]
            need = ", ".join(d[f"{kind}_traits"]) or "none"
            w(f"  {kind} traits needed: {need}\n")
            w(f"    supported {plural}: " + (", ".join(sup["supported"]) or "none installed"))
            if sup["refused"]:
                w("; refused: " + ", ".join(sup["refused"]))
            w("\n")
    w("parameters:\n" if d["parameters"] else "parameters: none\n")
    for pname, p in d["parameters"].items():
        default = p["default"] if p["default"] == "REQUIRED" else f"default {p['default']!r}"
        if "example" in p:
            default += f" (e.g. {p['example']!r})"
        sweep = ", sweepable" if p["sweepable"] else ""
        w(f"  {pname} [{p['unit']}]: {default}, range {p['range']}{sweep}\n")
        if p["description"]:
            w(f"      {p['description']}\n")
    w("outputs:\n" if d["outputs"] else "outputs: none\n")
    for vname, v in d["outputs"].items():
        w(f"  {vname}({', '.join(v['dims'])}) [{v['units']}]: {v['long_name']}\n")
    if d.get("body_quantities"):
        w("integrated over a [geometry] body (per force):\n")
        for vname, v in d["body_quantities"].items():
            more = f"; unbounded where {v['unbounded']} says full_contact" if v["unbounded"] else ""
            how = f"{v['combine']} of {v['local']}{more}"
            w(f"  {vname} [{v['units']}]: {v['long_name']} ({how})\n")
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    """Stand-alone entry: ``python -m xpersson.cli_plugins list`` (same as ``xpersson plugins``)."""
    parser = argparse.ArgumentParser(prog="xpersson")
    register(parser.add_subparsers(dest="command", required=True))
    args = parser.parse_args(["plugins", *(argv if argv is not None else sys.argv[1:])])
    return int(args.func(args))


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
