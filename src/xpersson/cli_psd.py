"""The ``xpersson psd`` sub-command: the spectrum of measured maps, as a solve would use it.

``xpersson psd MAP... -o psd.csv [--plot psd.png]`` reads one or several maps or line scans of
one surface (any format SurfaceTopography reads; the options give what a format lacks, as the
scene's ``spectrum`` keys do), builds the table that keeps their roughness (the ``topography``
spectrum's estimator), and writes it in the Persson convention with a self-affine fit and each
scan's provenance in the CSV header. The CSV is a ``tabulated`` spectrum file as it stands.

numpy and SurfaceTopography are imported when the command runs, not when the CLI starts.
"""

from __future__ import annotations

import argparse
import json
import sys
from typing import Any

__all__ = ["register", "cmd_psd", "header"]

_CONVENTION = (
    "isotropic PSD, Persson convention: C(q) = (2 pi)^-2 int d2x <h(x) h(0)> exp(-i q.x), "
    "h_rms^2 = 2 pi int q C(q) dq; q in 1/m (rad/m), C in m^4 (SurfaceTopography's C / (2 pi)^2)"
)


def register(subparsers: Any) -> argparse.ArgumentParser:
    """Add the ``psd`` sub-command to an argparse sub-parser collection."""
    p = subparsers.add_parser(
        "psd",
        help="the power spectrum of measured maps (CSV, fit, plot)",
        description="Write the isotropic PSD of measured maps or line scans (one surface; "
        "several scan sizes are combined) in the Persson convention, with a self-affine fit.",
    )
    p.add_argument("maps", nargs="+", metavar="MAP", help="map or line-scan files")
    p.add_argument("-o", "--output", required=True, help="CSV file to write")
    p.add_argument("--plot", metavar="FIGURE", help="also draw C(q), the fit and the bands")
    p.add_argument(
        "--physical-sizes",
        nargs="+",
        metavar="SIZE",
        help="size per axis when a file does not state it, e.g. '10 um' '10 um'",
    )
    p.add_argument("--unit", help="height/length unit when a file does not state it")
    p.add_argument("--height-scale", type=float, help="factor on the heights (file lacks it)")
    p.add_argument("--periodic", action="store_true", help="the maps are periodic")
    p.add_argument("--detrend", default="center", help="SurfaceTopography detrend mode")
    p.add_argument("--tip-radius", metavar="LENGTH", help="probe tip radius, e.g. '20 nm'")
    p.add_argument("--points-per-decade", type=int, default=20, help="rings per decade")
    p.set_defaults(func=cmd_psd)
    return p


def _keys(args: argparse.Namespace) -> Any:
    from .builtin.surface_maps import DETREND_MODES, MapKeys
    from .units import to_si

    if args.detrend not in DETREND_MODES:
        raise ValueError(
            f"--detrend: {args.detrend!r} is not allowed; one of {', '.join(DETREND_MODES)}"
        )
    if not 2 <= args.points_per_decade <= 1000:
        raise ValueError(f"--points-per-decade: {args.points_per_decade} is outside [2, 1000]")
    sizes = args.physical_sizes
    return MapKeys(
        physical_sizes=None
        if sizes is None
        else tuple(to_si(s, "m", "--physical-sizes") for s in sizes),
        unit=args.unit,
        height_scale=args.height_scale,
        periodic=bool(args.periodic),
        detrend=args.detrend,
        tip_radius=None if args.tip_radius is None else to_si(args.tip_radius, "m", "--tip-radius"),
    )


def header(record: dict[str, Any], fit: Any, table: Any) -> list[str]:
    """The CSV header lines (without ``#``): convention, roughness, fit, provenance."""
    lines = [
        f"xpersson psd: {_CONVENTION}",
        f"{'map' if len(record['parts']) == 1 else 'scans combined'}: "
        f"h_rms = {record['map_h_rms']:.6g} m, rms slope = {record['map_rms_slope']:.6g}; "
        f"table: h_rms = {table.h_rms():.6g} m, rms slope = {table.rms_slope():.6g} "
        "(integrated as the solver does: piecewise power law)",
        "fit: C = C_r for q < q_r, C_r (q/q_r)^(-2(1+H)) above: "
        f"H = {fit.H:.4f} +- {fit.H_err:.2g}, q_r = {fit.q_r:.6g} +- {fit.q_r_err:.2g} 1/m, "
        f"C_r = {fit.C_r:.6g} +- {fit.C_r_err:.2g} m^4, h_rms = {fit.h_rms:.6g} +- "
        f"{fit.h_rms_err:.2g} m over [{fit.q_L:.6g}, {fit.q_1:.6g}] 1/m",
    ]
    lines += [
        f"part {i + 1}: {json.dumps(p, sort_keys=True)}" for i, p in enumerate(record["parts"])
    ]
    lines.append('use: [spectrum] model = "tabulated", file = "<this file>" (convention persson)')
    return lines


def cmd_psd(args: argparse.Namespace) -> int:
    """Run ``xpersson psd``: every map read and checked before anything is written."""
    import numpy as np

    from .builtin.surface_maps import measured_from_file, table_of
    from .physics.psd import Tabulated, fit_self_affine

    try:
        import SurfaceTopography  # noqa: F401
    except ImportError:
        raise ValueError(
            "xpersson psd needs SurfaceTopography: pip install 'xpersson[topography]'"
        ) from None
    keys = _keys(args)
    parts = []
    for path in args.maps:
        try:
            parts.append(measured_from_file(path, keys))
        except ValueError as exc:
            raise ValueError(f"{path}: {exc}") from None
    q, C, record = table_of(parts, args.points_per_decade)
    fit = fit_self_affine(q, C)
    lines = header(record, fit, Tabulated(q, C))
    text = "".join(f"# {line}\n" for line in lines) + "q_1_per_m,C_m4\n"
    text += "".join(f"{a!r},{b!r}\n" for a, b in zip(q.tolist(), C.tolist(), strict=True))
    figure = _figure(record, fit, np.asarray(q), np.asarray(C)) if args.plot else None
    _write_atomic(args.output, text)
    print(f"xpersson: wrote {args.output} ({q.size} rows, H = {fit.H:.3f})", file=sys.stderr)
    if figure is not None:
        figure.savefig(args.plot, dpi=110)
        from .plot import pyplot

        pyplot().close(figure)
        print(f"xpersson: wrote {args.plot}", file=sys.stderr)
    return 0


def _figure(record: dict[str, Any], fit: Any, q: Any, C: Any) -> Any:
    """The figure of ``--plot`` (drawn before anything is written: no matplotlib, no files)."""
    from .plot import MatplotlibMissingError, draw_psd

    bands = [
        (p["band_1_per_m"][0], p["band_1_per_m"][1], str(p["file"]).rsplit("/", 1)[-1])
        for p in record["parts"]
    ]
    try:
        return draw_psd(q, C, fit, bands).figure
    except MatplotlibMissingError as exc:
        raise ValueError(f"--plot: {exc}") from None


def _write_atomic(path: str, text: str) -> None:
    """Write ``text`` to a temporary file next to ``path``, then rename it into place."""
    import os
    import tempfile

    folder = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(prefix=".psd-", suffix=".tmp", dir=folder)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
