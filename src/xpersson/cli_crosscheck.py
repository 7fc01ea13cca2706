"""``xpersson crosscheck SCENE``: the theory against a boundary-element solver (tamaas).

Prints the estimate before any work (stderr), then one table of theory/BEM ratios per load
(stdout); ``-o OUT.nc`` archives the Dataset. A missing tamaas, a physics the BEM cannot do
or a grid above the memory budget is one line on stderr and exit status 2.
"""

from __future__ import annotations

import argparse
import sys
from typing import Any

__all__ = ["register"]


def register(sub: Any) -> None:
    """Add the ``crosscheck`` sub-command to the ``xpersson`` parser's sub-parsers."""
    cc = sub.add_parser(
        "crosscheck", help="compare the theory with a boundary-element solver (tamaas)"
    )
    cc.add_argument("scene", help="scene TOML file (one scene; lists only in load.p0)")
    cc.add_argument("-o", "--output", default=None, help="archive the comparison (.nc)")
    cc.add_argument("--overwrite", action="store_true", help="replace an existing output")
    cc.add_argument("--realisations", type=int, default=4, help="synthesised maps (default 4)")
    cc.add_argument("--grid", type=int, default=256, help="grid points per side (default 256)")
    cc.add_argument("--seed", type=int, default=0, help="base seed of the maps (default 0)")
    cc.add_argument(
        "--grid-check",
        action="store_true",
        help="also solve on a grid twice as fine; report fine/coarse ratios (X_grid_ratio)",
    )
    cc.add_argument(
        "--scheduler",
        default=None,
        metavar="S",
        help="serial (default), threads, processes, synchronous or tcp://host:port",
    )
    cc.set_defaults(func=_cmd_crosscheck)


def _err(line: str) -> None:
    print(line, file=sys.stderr, flush=True)


def _table(ds: Any) -> list[str]:
    """Theory/BEM ratio (and the BEM's relative standard error) per output and load."""
    import numpy as np

    if ds.attrs.get("crosscheck_kind") == "sphere":
        from .bem.sphere import table_lines

        return table_lines(ds)
    names = [
        v[: -len("_ratio")]
        for v in ds.data_vars
        if v.endswith("_ratio") and not v.endswith("_grid_ratio")
    ]
    lines = ["theory / BEM (+- relative standard error of the BEM mean)"]
    head = f"{'p0 [Pa]':>12}  " + "  ".join(f"{n:>24}" for n in names)
    if "gap_pdf_l1" in ds:
        head += f"  {'gap_pdf_l1':>10}"
    lines.append(head)
    for i, p in enumerate(ds["p0"].values):
        cells = []
        for n in names:
            r = ds[f"{n}_ratio"].values.reshape(-1)
            se = ds[f"{n}_se"].values.reshape(-1)
            bem = ds[n].values.reshape(-1)
            k = min(i, r.size - 1)
            rel = abs(se[k] / bem[k]) if bem[k] else float("nan")
            cells.append(f"{r[k]:>13.3f} +- {rel:>7.3f}")
        row = f"{p:>12.4g}  " + "  ".join(f"{c:>24}" for c in cells)
        if "gap_pdf_l1" in ds:
            row += f"  {ds['gap_pdf_l1'].values[i]:>10.3f}"
        lines.append(row)
    if "bem_full_contact" in ds and ds["bem_full_contact"].values.any():
        full = ds["p0"].values[ds["bem_full_contact"].values.any(axis=0)]
        lines.append(
            "full contact in the BEM at p0 = "
            + ", ".join(f"{p:.4g}" for p in full)
            + " Pa: gap, stiffness and conductance not compared there"
        )
    if ds.attrs.get("crosscheck_kind") == "adhesive" and np.isnan(ds["area_fraction"]).any():
        lines.append(
            "NaN area: the load lies outside the BEM's stable retraction branch (above its "
            "deepest approach, or beyond its pull-off)"
        )
    lines.extend(_grid_lines(ds, names))
    bad = int((ds["bem_converged"].values == 0).sum())
    if bad:
        lines.append(f"{bad} realisation x load point(s) did not converge: NaN, not averaged")
    return lines


def _grid_lines(ds: Any, names: list[str]) -> list[str]:
    """The grid check: BEM fine/coarse ratio per output and load (none without it)."""
    have = [n for n in names if f"{n}_grid_ratio" in ds]
    if not have:
        return []
    fine = 2 * int(ds.attrs.get("crosscheck_grid", 0))
    lines = [f"grid check: BEM on {fine}^2 / BEM on the cross-check's grid (same surfaces)"]
    lines.append(f"{'p0 [Pa]':>12}  " + "  ".join(f"{n:>24}" for n in have))
    for i, p in enumerate(ds["p0"].values):
        cells = [f"{ds[f'{n}_grid_ratio'].values.reshape(-1)[i]:>24.4f}" for n in have]
        lines.append(f"{p:>12.4g}  " + "  ".join(cells))
    return lines


def _cmd_crosscheck(args: argparse.Namespace) -> int:
    from .bem import MissingTamaasError, crosscheck
    from .io import to_netcdf

    try:
        ds = crosscheck(
            args.scene,
            realisations=args.realisations,
            grid=args.grid,
            scheduler=args.scheduler,
            seed=args.seed,
            grid_check=args.grid_check,
            echo=_err,
        )
    except MissingTamaasError as exc:
        _err(f"xpersson: error: {exc}")
        return 2
    print("\n".join(_table(ds)))
    if args.output:
        to_netcdf(ds, args.output, overwrite=args.overwrite)
        _err(f"crosscheck: wrote {args.output}")
    return 0
