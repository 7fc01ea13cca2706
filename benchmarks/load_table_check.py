"""``gap_pdf`` and ``leakage`` through their table in the load against the direct path.

For every scene of the speed design (``summary_design.design``), at ``--loads`` loads (range
1 kPa - 1 MPa, as ``benchmarks/summary.py``): each analysis solved through the table
(``xpersson_interface._by_load``) and directly (every load computed), and per analysis the
largest relative difference of an interpolated load (rows: of the load's largest element, at
least 1e-30 of the largest over the loads; per-load values: of the value), the largest ratio
of that difference to the load's stated error (``gap_pdf_load_error``, ``leak_load_error``;
must be <= 1), the largest difference of a directly computed load (round-off) and how many
loads were computed directly. ``--seeds`` adds held-out designs (``design(12, seed)``, seed 36
is the speed design's; the two named scenes, in every design, are checked once).

    python benchmarks/load_table_check.py [--loads 3000] [--seeds 36 37 38] [--held-out 2026]
        [--analyses gap_pdf leakage] [--out results/load_table_check.json]
"""

from __future__ import annotations

import argparse
import json
import sys
import warnings
from pathlib import Path

import numpy as np
from summary_design import labelled, load_range, scene

import xpersson
from xpersson_interface import _by_load

ERROR = {"gap_pdf": "gap_pdf_load_error", "leakage": "leak_load_error"}


def _difference(got: np.ndarray, want: np.ndarray) -> np.ndarray:
    """Per load: |got - want| relative to the load's largest |want| (>= 1e-30 of all's)."""
    got, want = got.astype(float), want.astype(float)
    with np.errstate(all="ignore"):
        top = np.nanmax(np.abs(np.where(np.isfinite(want), want, 0.0)))
        d = np.abs(got - want)
        if want.ndim > 1:
            scale = np.maximum(np.max(np.abs(want), axis=1), 1e-30 * top)
            return np.max(d, axis=1) / scale
        same = (got == want) | (np.isnan(got) & np.isnan(want))
        r = np.where(same, 0.0, d / np.maximum(np.abs(want), 1e-30 * top))
    return np.nan_to_num(r, nan=np.inf)


def check(spec: dict, analysis: str, n: int) -> dict:
    return check_scene(scene(spec, load_range(n), analyses={analysis: {}}), analysis)


def check_scene(sc: dict, analysis: str) -> dict:
    """The table against the direct path on the scene ``sc`` (its ``analysis`` set up)."""
    table = xpersson.solve(sc)
    least = _by_load.TABLE_MIN
    _by_load.TABLE_MIN = 10**9
    try:
        direct = xpersson.solve(sc)
    finally:
        _by_load.TABLE_MIN = least
    est = table[ERROR[analysis]].values
    worst = np.zeros(est.size)
    for name in direct.data_vars:
        var = direct[name]
        prefix = "gap_" if analysis == "gap_pdf" else "leak_"
        if not name.startswith(prefix) or name == ERROR[analysis] or var.dtype.kind not in "fiu":
            continue
        if "exact" in name or "model_error" in name:
            continue
        got = table[name].transpose("p0", ...).values
        worst = np.maximum(worst, _difference(got, var.transpose("p0", ...).values))
    inter = est > 0
    return {
        "interpolated_max": float(worst[inter].max()) if inter.any() else 0.0,
        "ratio_to_estimate_max": float(np.max(worst[inter] / est[inter])) if inter.any() else 0.0,
        "estimate_max": float(est.max()),
        "direct_max": float(worst[~inter].max()) if (~inter).any() else 0.0,
        "computed_directly": int((~inter).sum()),
        "loads": int(est.size),
    }


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--loads", type=int, default=3000)
    ap.add_argument("--seeds", type=int, nargs="+", default=[36])
    ap.add_argument("--held-out", type=int, nargs="*", default=[], help="summary.py's designs")
    ap.add_argument("--analyses", nargs="+", default=list(ERROR), choices=list(ERROR))
    ap.add_argument("--out", type=Path, default=None)
    args = ap.parse_args(argv)
    out: dict = {}
    warnings.simplefilter("ignore")
    scenes = labelled(args.seeds, args.held_out)
    for analysis in args.analyses:
        for name, spec in scenes:
            out.setdefault(analysis, {})[name] = report(
                analysis, name, check(spec, analysis, args.loads)
            )
    if args.out:
        args.out.write_text(json.dumps(out, indent=1) + "\n")
    verdict(out)


def report(analysis: str, name: str, r: dict) -> dict:
    """Print one scene's check ``r`` (and return it)."""
    print(
        f"{analysis:8s} {name:34s} interpolated <= {r['interpolated_max']:.1e} "
        f"(<= {r['ratio_to_estimate_max']:.2f} of its estimate), direct "
        f"{r['computed_directly']}/{r['loads']} (round-off {r['direct_max']:.0e})",
        flush=True,
    )
    return r


def verdict(out: dict) -> None:
    """Exit 1 naming the scenes of ``out`` (``{analysis: {scene: check}}``) where a load lies
    beyond its stated error."""
    bad = [(a, s) for a, d in out.items() for s, r in d.items() if r["ratio_to_estimate_max"] > 1]
    if bad:
        sys.exit(f"loads beyond their stated error: {bad}")


if __name__ == "__main__":
    main()
