"""``gap_pdf`` and ``leakage`` through their load table beyond the scenes it was tuned on.

:mod:`load_table_check` measures the table (``xpersson_interface._by_load``) against the direct
path on the speed design (H 0.3-0.95, 3-6 decades, 1 kPa - 1 MPa) with default parameters.
This script takes it to the documented domain's edges and to the analyses' other parameters:

* ``--extreme SEED [--scenes N]``: N seeded scenes with H uniform in 0.05-1, 3-9 decades of
  ``q_1/q_L``, with or without roll-off, ``q_L`` 1e2-1e4 1/m, 60 output magnifications up to
  ``zeta_max``; the loads (``--loads``, log-spaced) from a contact area of ``--area-low`` (1e-8)
  to ``1 - --open-high`` (``1 - 1e-12``) at ``zeta_max``, found from a coarse solve.
* ``--design``: the 24 scenes of ``summary.py`` and ``--held-out 2026`` instead.
* ``--params JSON``: the analysis's parameters (e.g. ``'{"separation": "almqvist"}'``).

Per scene and analysis: the largest relative difference of an interpolated load (rows: of the
load's largest element, at least 1e-30 of the largest over the loads), its ratio to the load's
stated error (``gap_pdf_load_error``, ``leak_load_error``: must be <= 1) and the loads computed
directly. Exits 1 naming the scenes where a ratio exceeds 1.

    python benchmarks/load_table_extreme.py --extreme 11 [--scenes 20] [--loads 1000]
        [--analyses gap_pdf leakage] [--params '{...}'] [--design] [--out FILE.json]
"""

from __future__ import annotations

import argparse
import json
import warnings
from pathlib import Path

import numpy as np
from load_table_check import check_scene, report, verdict
from summary_design import labelled, load_range, scene, spectrum

import xpersson


def extreme(seed: int, n: int) -> list[tuple[str, dict, float]]:
    """``n`` seeded ``(name, spectrum, decades)`` over the domain's edges."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        H, roll = float(rng.uniform(0.05, 1.0)), bool(rng.integers(0, 2))
        decades, q_L = float(rng.integers(3, 10)), float(10 ** rng.uniform(2, 4))
        name = f"seed {seed}: {'roll' if roll else 'flat'} H={H:.2f} {decades:.0f}dec"
        out.append((name, spectrum(H, roll, decades, q_L), decades))
    return out


def wide(spec: dict, decades: float, loads: object, analyses: dict | None = None) -> dict:
    """An elastic scene on ``spec`` with 60 output magnifications up to ``10**decades``."""
    zeta = [float(z) for z in np.geomspace(1.0, 10.0**decades, 60)]
    return scene(spec, loads, output={"zeta": zeta}, **({"analyses": analyses} if analyses else {}))


def load_span(spec: dict, decades: float, area_low: float, open_high: float) -> tuple[float, float]:
    """The loads [Pa] at which the contact area at ``zeta_max`` is ``area_low`` and
    ``1 - open_high`` (a coarse solve of 400 loads, 1e-8 Pa - 1e11 Pa)."""
    grid = np.geomspace(1e-8, 1e11, 400)
    ds = xpersson.solve(wide(spec, decades, [f"{float(p)!r} Pa" for p in grid]))
    area = ds["area_fraction"].transpose("p0", "zeta").values[:, -1]
    non = ds["non_contact_fraction"].transpose("p0", "zeta").values[:, -1]
    lo = float(grid[np.argmax(area >= area_low)])
    hi = float(grid[np.argmax(non <= open_high)]) if (non <= open_high).any() else float(grid[-1])
    return lo, hi


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--extreme", type=int, default=11, help="seed of the extreme scenes")
    ap.add_argument("--scenes", type=int, default=20)
    ap.add_argument("--design", action="store_true", help="the speed design and held-out 2026")
    ap.add_argument("--loads", type=int, default=1000)
    ap.add_argument("--area-low", type=float, default=1e-8)
    ap.add_argument("--open-high", type=float, default=1e-12)
    ap.add_argument("--analyses", nargs="+", default=["gap_pdf", "leakage"])
    ap.add_argument("--params", type=json.loads, default={})
    ap.add_argument("--out", type=Path, default=None)
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    out: dict = {}
    if args.design:
        cases = [
            (name, scene(spec, load_range(args.loads), analyses={a: args.params}), a)
            for name, spec in labelled([36], [2026])
            for a in args.analyses
        ]
    else:
        cases = []
        for name, spec, decades in extreme(args.extreme, args.scenes):
            lo, hi = load_span(spec, decades, args.area_low, args.open_high)
            loads = {"start": f"{lo!r} Pa", "stop": f"{hi!r} Pa", "num": args.loads}
            cases += [
                (name, wide(spec, decades, loads, {a: args.params}), a) for a in args.analyses
            ]
    for name, sc, analysis in cases:
        r = check_scene(sc, analysis)
        r["loads_Pa"] = [sc["load"]["p0"].get("start"), sc["load"]["p0"].get("stop")]
        out.setdefault(analysis, {})[name] = report(analysis, name, r)
    if args.out:
        args.out.write_text(json.dumps({"params": args.params, "checks": out}, indent=1) + "\n")
    verdict(out)


if __name__ == "__main__":
    main()
