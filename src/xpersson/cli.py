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
    from .cli_reproduce import check_texts

    check_texts(out, "--set ")
    return out


def _load(args: argparse.Namespace) -> Any:
    from .scene import load_scene

    scene = load_scene(args.scene)
    from .cli_reproduce import check_texts

    check_texts(getattr(scene, "data", {}) or {}, "")
    sets = _parse_sets(args.set or [])
    return scene.with_values(**sets) if sets else scene


def _cmd_run(args: argparse.Namespace) -> int:
    from pathlib import Path

    out = Path(args.output)
    as_parts = args.output.endswith(("/", "\\")) or out.is_dir()
    if not as_parts and out.exists() and not args.overwrite:
        _err(f"xpersson: {out} exists; add --overwrite to replace it")
        return 2
    if args.resume and args.overwrite:
        _err("xpersson: --resume and --overwrite exclude each other")
        return 2
    if args.resume and not as_parts:
        _err(f"xpersson: --resume applies to a sweep folder (DIR/), not to {out}")
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
        **({"resume": args.resume or None, "overwrite": args.overwrite} if as_parts else {}),
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
    """Check a scene without solving it: a readable summary on stderr; ``--json`` adds the
    resolved scene (a sweep: the scene with its swept lists) as JSON on stdout."""
    scene = _load(args)
    from .sweep import expand

    plan = expand(scene)
    if plan is not None:
        from .sweep import check_size, resolve_points

        check_size(plan, None, None, None, None, False)  # before resolving every point
        rs = resolve_points(plan, None)[0]
        dims = ", ".join(f"{p.name} = {p.path} ({len(p.values)} values)" for p in plan.params)
        _err(f"xpersson: {args.scene} is valid: a sweep of {plan.size} points ({dims})")
    else:
        rs = scene.resolve()
        _err(f"xpersson: {args.scene} is valid")
    each = " per point" if plan is not None else ""
    _err(
        f"  loads: {rs.p0.size}{each}; magnification: {rs.zeta.size} points from 1 to "
        f"{rs.zeta[-1]:g}"
    )
    _err("  plugins: " + ", ".join(f"{k} {v}" for k, v in rs.plugin_names.items()))
    if rs.analyses:
        _err("  analyses: " + ", ".join(n for n, _ in rs.analyses))
    if args.json:
        resolved = plan.scene_lists() if plan is not None else rs.resolved
        print(json.dumps(resolved, indent=1, sort_keys=True))
    return 0


def _open(path: str) -> Any:
    """An xpersson result (file or sweep folder) or one clear error naming the file."""
    from . import io

    ds = io.open_dataset(path)
    io.check_attributes(ds, path, require=True)
    return ds


def _cmd_info(args: argparse.Namespace) -> int:
    from .cli_info import info

    info(_open(args.archive), args.archive, args.point or [])
    return 0


def _cmd_reproduce(args: argparse.Namespace) -> int:
    from pathlib import Path

    from . import io
    from .api import solve
    from .scene import Scene

    out = Path(args.output)
    if out.exists() and not args.overwrite:
        _err(f"xpersson: {out} exists; add --overwrite to replace it")
        return 2
    if not (args.rtol >= 0 and args.atol >= 0):
        _err("xpersson: --rtol and --atol must be >= 0")
        return 2
    old = _open(args.archive)
    from .cli_reproduce import archived_scene

    data = archived_scene(old, args.archive, args.read_files)
    try:
        ds = solve(Scene(data, source=None)).load()
    except ValueError as exc:  # quotes (a file's lines, a stored value) are withheld
        import re

        text = re.sub(r"'[^']*'|\"[^\"]*\"", "'...'", str(exc))
        _err(f"xpersson: error: {args.archive}: its scene cannot be solved again ({text})")
        return 2
    if Path(args.archive).is_dir():
        old = old.load()
    io.to_netcdf(ds, out, overwrite=args.overwrite)
    n, diffs = io.compare(old, ds, rtol=args.rtol, atol=args.atol)
    for line in diffs:
        _err(f"xpersson: {line}")
    verdict = "matches" if not diffs else f"DIFFERS FROM ({len(diffs)} differences)"
    _err(
        f"xpersson: wrote {out}; {n} coordinates and variables compared (coordinates exactly, "
        f"values within rtol={args.rtol:g}, atol={args.atol:g}): {verdict} {args.archive}"
    )
    return 0 if not diffs else 4


def _cmd_plot(args: argparse.Namespace) -> int:
    from . import plot

    ds = _open(args.archive)
    if args.kind is None:
        args.kind = "body" if "nominal_pressure" in ds else "area"
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

    _add_run(sub)

    val = sub.add_parser("validate", help="check a scene without solving it")
    val.add_argument("scene", help="scene TOML file")
    val.add_argument("--set", action="append", metavar="KEY=VALUE", help="override a value")
    val.add_argument(
        "--json", action="store_true", help="print the summary and the resolved scene as JSON"
    )
    val.set_defaults(func=_cmd_validate)

    info = sub.add_parser("info", help="summarise an archive")
    info.add_argument("archive", help=".nc file written by xpersson run")
    info.add_argument(
        "--point",
        action="append",
        metavar="DIM=INDEX",
        help="the sweep point whose area fractions are shown (default: index 0 of each)",
    )
    info.set_defaults(func=_cmd_info)

    plo = sub.add_parser("plot", help="plot an archive (matplotlib)")
    plo.add_argument("archive", help=".nc file or sweep folder written by xpersson run")
    plo.add_argument(
        "--kind",
        default=None,
        choices=["area", "pressure_pdf", "gap_pdf", "leakage", "energy", "friction", "psd", "body"],
        help="what to plot (default: body for a finite-body archive, else area)",
    )
    plo.add_argument("-o", "--output", required=True, help="figure file (.png, .pdf, .svg)")
    plo.add_argument("--dpi", type=int, default=110, help="resolution of raster figures")
    plo.set_defaults(func=_cmd_plot)

    _add_reproduce(sub)

    try:
        from . import cli_plugins
    except ImportError:  # pragma: no cover - during development only
        pass
    else:
        cli_plugins.register(sub)
    from . import cli_psd

    cli_psd.register(sub)
    from . import cli_crosscheck

    cli_crosscheck.register(sub)
    return parser


def _add_run(sub: Any) -> None:
    """The ``run`` sub-command's parser."""
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
    run.add_argument(
        "--overwrite",
        action="store_true",
        help="replace an existing output (a sweep folder: start the study over)",
    )
    run.add_argument(
        "--resume",
        action="store_true",
        help="a sweep folder must hold this study: solve only its missing or damaged parts "
        "(the default when it does)",
    )
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


def _add_reproduce(sub: Any) -> None:
    """The ``reproduce`` sub-command's parser."""
    rep = sub.add_parser("reproduce", help="re-solve an archive from its own scene")
    rep.add_argument("archive", help=".nc file written by xpersson run")
    rep.add_argument("-o", "--output", required=True, help="output .nc file")
    rep.add_argument("--overwrite", action="store_true", help="replace an existing output")
    rep.add_argument(
        "--rtol", type=float, default=1e-9, help="relative tolerance of values (default 1e-9)"
    )
    rep.add_argument(
        "--atol", type=float, default=0.0, help="absolute tolerance of values (default 0)"
    )
    rep.add_argument(
        "--read-files",
        action="store_true",
        help="read the files the archive's scene names (never done otherwise)",
    )
    rep.set_defaults(func=_cmd_reproduce)


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


def _ignore_file_size_signal() -> None:
    """With ``SIGXFSZ`` ignored, a write past a file-size limit fails with ``EFBIG`` (reported
    as one line) instead of killing the process."""
    import contextlib
    import signal

    if hasattr(signal, "SIGXFSZ"):
        with contextlib.suppress(ValueError):  # not the main thread: left as it is
            signal.signal(signal.SIGXFSZ, signal.SIG_IGN)


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
    _ignore_file_size_signal()
    try:
        return int(args.func(args) or 0)
    except BrokenPipeError:  # the reader went away (`xpersson info OUT.nc | head`)
        import os

        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())  # no second error when Python flushes stdout
        return 1
    except (SceneError, FileExistsError, FileNotFoundError) as exc:
        _err(f"xpersson: error: {_one_line(exc)}")
        return 2
    except OSError as exc:  # disk full, quota, file-size limit, permission, read-only, ...
        _err(f"xpersson: error: {_os_message(exc)}")
        return 2
    except Exception as exc:  # plugin errors etc.: one clear line, no traceback
        from .checks import PluginFailure
        from .plugins import PluginError

        if isinstance(exc, PluginError | ValueError | PluginFailure):
            _err(f"xpersson: error: {_one_line(exc)}")
            return 2
        raise


def _one_line(exc: BaseException) -> str:
    text = " ".join(str(exc).split()) or type(exc).__name__
    return text if len(text) <= 2000 else text[:1997] + "..."


def _os_message(exc: OSError) -> str:
    """``PATH: CAUSE`` of an operating-system error (the path it names, its strerror)."""
    from .archive import WriteError

    if isinstance(exc, WriteError) or exc.errno is None:  # ours (TimeoutError too): one line
        return _one_line(exc)
    cause = exc.strerror or _one_line(exc)
    where = exc.filename if exc.filename is not None else "(no path)"
    return f"{where}: {cause}"


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
