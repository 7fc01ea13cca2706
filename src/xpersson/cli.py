"""Command-line interface: ``xpersson run | validate | info | plot | reproduce | plugins``.

Results go to files, messages to stderr. Heavy modules (xarray, scipy) are imported inside the
sub-commands, so ``xpersson --help`` stays fast.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence
from typing import Any

__all__ = ["main"]


def _err(msg: str) -> None:
    print(msg, file=sys.stderr)


def _parse_sets(items: Sequence[str]) -> dict[str, Any]:
    from .scene import SceneError, parse_cli_value

    out: dict[str, Any] = {}
    for item in items:
        key, sep, value = item.partition("=")
        if not sep or not key.strip():
            raise SceneError(f"--set expects section.key=value, got {item!r}")
        out[key.strip()] = parse_cli_value(value.strip())
    return out


def _load(args: argparse.Namespace) -> Any:
    from .scene import load_scene

    scene = load_scene(args.scene)
    sets = _parse_sets(args.set or [])
    return scene.with_values(**sets) if sets else scene


def _cmd_run(args: argparse.Namespace) -> int:
    from pathlib import Path

    out = Path(args.output)
    as_parts = args.output.endswith(("/", "\\")) or out.is_dir()
    if out.exists() and not args.overwrite and not (as_parts and not any(out.iterdir())):
        _err(f"xpersson: {out} exists; add --overwrite to replace it")
        return 2
    scene = _load(args)
    from . import io
    from .api import solve

    progress = False if args.quiet else (True if args.progress else None)
    if as_parts:
        from .sweep import expand

        if expand(scene) is None:
            _err(
                f"xpersson: {args.output} is a folder, but the scene sweeps no parameter; "
                "give a .nc file"
            )
            return 2
    ds = solve(
        scene,
        scheduler=_scheduler(args.scheduler),
        progress=progress,
        output=out if as_parts else None,
        chunk=args.chunk,
        workers=args.workers,
    )
    if as_parts:
        _err(
            f"xpersson: wrote {out}/ ({len(list(out.glob('part-*.nc')))} parts; open with "
            f"xpersson.open_dataset) (status: {ds.attrs['status']})"
        )
    else:
        command = "xpersson " + " ".join(sys.argv[1:]) if sys.argv[1:] else "xpersson run"
        ds.attrs["history"] = f"{ds.attrs['history']} ({command})"
        io.to_netcdf(ds, out, overwrite=args.overwrite)
        _err(f"xpersson: wrote {out} (status: {ds.attrs['status']})")
    if ds.attrs["status"] != "success":
        _err(f"xpersson: {ds.attrs['status_message']}")
        return 3
    return 0


def _scheduler(text: str | None) -> str | None:
    return None if text in (None, "serial") else text


def _cmd_validate(args: argparse.Namespace) -> int:
    scene = _load(args)
    from .sweep import expand

    plan = expand(scene)
    if plan is not None:
        from .sweep import resolve_points

        points = resolve_points(plan, None)
        rs = points[0]
        sweep = ", ".join(f"{p.path} -> {p.name} ({len(p.values)})" for p in plan.params)
        _err(
            f"xpersson: {args.scene} is valid: a sweep of {plan.size} points ({sweep}), "
            f"{rs.p0.size} load(s) each, {rs.zeta.size} zeta points, plugins "
            f"{rs.plugin_names}"
        )
        if args.json:
            print(json.dumps(plan.scene_lists(), indent=1, sort_keys=True))
        return 0
    rs = scene.resolve()
    _err(
        f"xpersson: {args.scene} is valid: {rs.p0.size} load(s), {rs.zeta.size} zeta points "
        f"from 1 to {rs.zeta[-1]:g}, plugins {rs.plugin_names}"
        + (f", analyses {[n for n, _ in rs.analyses]}" if rs.analyses else "")
    )
    if args.json:
        print(json.dumps(rs.resolved, indent=1, sort_keys=True))
    return 0


def _cmd_info(args: argparse.Namespace) -> int:
    from . import io

    ds = io.open_dataset(args.archive)
    print(f"{args.archive}: {ds.attrs.get('title', '')}")
    print(f"  source: {ds.attrs.get('source')}, created {ds.attrs.get('date_created')}")
    print(f"  status: {ds.attrs.get('status')} ({ds.attrs.get('status_message')})")
    print("  dimensions: " + ", ".join(f"{k}={v}" for k, v in ds.sizes.items()))
    for name, var in {**ds.coords, **ds.data_vars}.items():
        dims = ",".join(var.dims)
        print(
            f"  {name:28s} ({dims}) [{var.attrs.get('units', '?')}] "
            f"{var.attrs.get('long_name', '')}"
        )
    plugins = json.loads(ds.attrs.get("xpersson_plugins", "[]"))
    for p in plugins:
        print(f"  plugin {p['group']}/{p['name']}: {p['distribution']} {p['version']}")
    _print_areas(ds)
    return 0


SHOWN_LOADS = 10
"""Loads listed by ``xpersson info`` (the rest are counted)."""


def _print_areas(ds: Any) -> None:
    """Every area fraction of the archive (core and boundary) at zeta_max, per load."""
    names = [
        n
        for n, v in ds.data_vars.items()
        if "zeta" in v.dims
        and v.attrs.get("units") == "1"
        and (n.endswith("area_fraction") or n in ("area_fraction", "total_contact_fraction"))
    ]
    if not names or "zeta" not in ds.dims:
        return
    loads = ds["p0"].values.ravel() if "p0" in ds.coords else []
    n_loads = len(loads)
    shown = min(n_loads, SHOWN_LOADS) if n_loads else 1
    print(
        f"  area fractions at zeta_max = {float(ds['zeta'][-1]):.6g}"
        + (
            f" (first {shown} of {n_loads} loads; {n_loads - shown} more not shown)"
            if n_loads > shown
            else ""
        )
    )
    if n_loads:
        print(f"    {'p0 [Pa]':28s} " + " ".join(f"{v:.6g}" for v in loads[:shown]))
    for name in names:
        values = ds[name].isel(zeta=-1).values.ravel()[:shown]
        label = f"{name}"
        print(
            f"    {label:28s} "
            + " ".join(f"{v:.6g}" for v in values)
            + f"  ({ds[name].attrs.get('long_name', '')})"
        )


def _cmd_reproduce(args: argparse.Namespace) -> int:
    from pathlib import Path

    from . import io
    from .api import solve
    from .scene import Scene

    out = Path(args.output)
    if out.exists() and not args.overwrite:
        _err(f"xpersson: {out} exists; add --overwrite to replace it")
        return 2
    old = io.open_dataset(args.archive)
    scene = Scene(json.loads(old.attrs["xpersson_scene"]), source=None)
    ds = solve(scene)
    io.to_netcdf(ds, out, overwrite=args.overwrite)
    same = all(
        name in ds
        and ds[name].shape == old[name].shape
        and bool((abs(ds[name] - old[name]) <= 1e-12 + 1e-9 * abs(old[name])).all())
        for name in ("area_fraction",)
    )
    _err(
        f"xpersson: wrote {out}; area_fraction {'matches' if same else 'DIFFERS FROM'} "
        f"{args.archive}"
    )
    return 0 if same else 4


def _cmd_plot(args: argparse.Namespace) -> int:
    from . import io, plot

    ds = io.open_dataset(args.archive)
    try:
        out = plot.save(ds, args.kind, args.output, dpi=args.dpi)
    except plot.MatplotlibMissingError as exc:  # one line, no traceback
        _err(f"xpersson: {exc}")
        return 2
    _err(f"xpersson: wrote {out} ({args.kind})")
    return 0


def build_parser() -> argparse.ArgumentParser:
    """The argparse parser of the ``xpersson`` command."""
    parser = argparse.ArgumentParser(
        prog="xpersson",
        description="Persson's multiscale contact theory: solve TOML scenes to netCDF archives.",
    )
    parser.add_argument("--version", action="store_true", help="print the version and exit")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")

    run = sub.add_parser("run", help="solve a scene and write a netCDF archive")
    run.add_argument("scene", help="scene TOML file")
    run.add_argument(
        "-o",
        "--output",
        required=True,
        help="output .nc file, or DIR/ for a sweep written as netCDF parts",
    )
    run.add_argument(
        "--set",
        action="append",
        metavar="KEY=VALUE",
        help="override a scene value, e.g. --set 'load.p0=\"1 MPa\"'",
    )
    run.add_argument("--overwrite", action="store_true", help="replace an existing output")
    run.add_argument(
        "--scheduler",
        default=None,
        metavar="S",
        help="where sweep points run: serial (default), threads, processes "
        "(dask LocalCluster) or a dask scheduler address tcp://host:port",
    )
    run.add_argument(
        "--workers",
        type=int,
        default=None,
        help="workers for threads/processes (default: number of cores)",
    )
    run.add_argument("--chunk", type=int, default=None, help="sweep points per task / netCDF part")
    noise = run.add_mutually_exclusive_group()
    noise.add_argument("--quiet", action="store_true", help="no progress bar")
    noise.add_argument(
        "--progress", action="store_true", help="progress bar even when stderr is not a terminal"
    )
    run.set_defaults(func=_cmd_run)

    val = sub.add_parser("validate", help="check a scene without solving it")
    val.add_argument("scene", help="scene TOML file")
    val.add_argument("--set", action="append", metavar="KEY=VALUE", help="override a value")
    val.add_argument("--json", action="store_true", help="print the resolved scene as JSON")
    val.set_defaults(func=_cmd_validate)

    info = sub.add_parser("info", help="summarise an archive")
    info.add_argument("archive", help=".nc file written by xpersson run")
    info.set_defaults(func=_cmd_info)

    plo = sub.add_parser("plot", help="plot an archive (matplotlib)")
    plo.add_argument("archive", help=".nc file or sweep folder written by xpersson run")
    plo.add_argument(
        "--kind",
        default="area",
        choices=["area", "pressure_pdf", "gap_pdf", "leakage", "energy", "friction"],
        help="what to plot (default: area)",
    )
    plo.add_argument("-o", "--output", required=True, help="figure file (.png, .pdf, .svg)")
    plo.add_argument("--dpi", type=int, default=110, help="resolution of raster figures")
    plo.set_defaults(func=_cmd_plot)

    rep = sub.add_parser("reproduce", help="re-solve an archive from its own scene")
    rep.add_argument("archive", help=".nc file written by xpersson run")
    rep.add_argument("-o", "--output", required=True, help="output .nc file")
    rep.add_argument("--overwrite", action="store_true", help="replace an existing output")
    rep.set_defaults(func=_cmd_reproduce)

    try:
        from . import cli_plugins
    except ImportError:  # pragma: no cover - during development only
        pass
    else:
        cli_plugins.register(sub)
    return parser


def _one_line_warnings() -> None:
    """Show warnings as one line each on stderr (no source line of the CLI's own code)."""
    import warnings

    def show(
        message: Any,
        category: type,
        filename: str,
        lineno: int,
        file: Any = None,
        line: str | None = None,
    ) -> None:
        print(f"{category.__name__}: {message}", file=sys.stderr)

    warnings.showwarning = show


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``xpersson`` console script; returns the exit code."""
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.version:
        from .provenance import version

        print(version())
        return 0
    if not getattr(args, "func", None):
        parser.print_help(sys.stderr)
        return 1
    from .scene import SceneError

    _one_line_warnings()
    try:
        return int(args.func(args) or 0)
    except BrokenPipeError:  # the reader went away (`xpersson info OUT.nc | head`)
        import os

        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())  # no second error when Python flushes stdout
        return 1
    except (SceneError, FileExistsError, FileNotFoundError) as exc:
        _err(f"xpersson: error: {exc}")
        return 2
    except Exception as exc:  # plugin errors etc.: one clear line, no traceback
        from .checks import PluginFailure
        from .plugins import PluginError

        if isinstance(exc, PluginError | ValueError | PluginFailure):
            _err(f"xpersson: error: {exc}")
            return 2
        raise


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
