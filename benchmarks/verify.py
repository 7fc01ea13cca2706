"""The verification matrix (issue 22): every output against an independent reference.

    python benchmarks/verify.py            # full regime grids (minutes)
    python benchmarks/verify.py --fast     # the subset the tests run (seconds)
    python benchmarks/verify.py --markdown # the table of docs/verification.md

Prints, per output variable of the core and of the first-party plugins, the reference it is
checked against (computed another way: adaptive quadrature with explicit breakpoints, closed
forms, an image series, the Markov walkers, published tables), the regime grid, and the worst
error measured. Rows come from ``verify_core`` (core, plasticity), ``verify_interface``
(xpersson-interface), ``verify_friction`` (xpersson-viscoelastic, written by its own helper:
included when the file exists and offers ``rows(fast)``) and the adhesion BEM comparison
(``results/adhesion_bem_compare.json`` when present). GFMD data are read from
``../shared/refdata`` relative to the repository root (``XPERSSON_REFDATA`` overrides).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import verify_core  # noqa: E402
import verify_interface  # noqa: E402

SECTIONS = (
    ("core", (verify_core.core_rows, verify_core.pressure_pdf_rows, verify_core.markov_rows)),
    ("xpersson-plasticity (constant hardness)", (verify_core.plastic_rows,)),
    (
        "xpersson-interface",
        (
            verify_interface.energy_gap_stiffness_rows,
            verify_interface.gap_table_rows,
            verify_interface.gfmd_rows,
            verify_interface.leakage_rows,
        ),
    ),
)


def friction_rows(fast: bool) -> list[dict]:
    """Rows of ``verify_friction.py`` (the friction helper's), when present."""
    try:
        import verify_friction
    except ImportError:
        return [_missing("friction (xpersson-viscoelastic)", "verify_friction.py not present")]
    rows = getattr(verify_friction, "rows", None)
    if not callable(rows):
        return [
            _missing(
                "friction (xpersson-viscoelastic)",
                "verify_friction.py has no rows(fast); run it directly",
            )
        ]
    return list(rows(fast))


def adhesion_rows(fast: bool) -> list[dict]:
    """Adhesive areas against the BEM results of the adhesion helper, when present."""
    path = HERE / "results" / "adhesion_bem_compare.json"
    if not path.is_file():
        return [_missing("adhesion (xpersson-adhesion)", "no BEM results in benchmarks/results")]
    data = json.loads(path.read_text())
    worst: dict[str, float] = {}
    tabor: list[float] = []
    for block in data.values():
        for w in block.get("works", []):
            tabor.append(float(w.get("tabor", math.nan)))
            for model in ("jkr", "dmt", "adhesive"):
                ratio = [r for r in (w.get(model) or {}).get("ratio", []) if r is not None]
                if ratio:
                    err = max(abs(float(r) - 1.0) for r in ratio)
                    worst[model] = max(worst.get(model, 0.0), err)
    regime = f"Tabor {min(tabor):g}-{max(tabor):g}, H {', '.join(data)}" if tabor else "-"
    note = "theory vs BEM: Persson's adhesive area is a mean-field theory"
    return [
        {
            "output": f"area_fraction ({m} boundary)",
            "regime": regime,
            "reference": "BEM (adhesion_bem_compare.json)",
            "worst": e,
            "measure": "|A/A_BEM - 1|",
            "note": note,
        }
        for m, e in sorted(worst.items())
    ]


def _missing(output: str, why: str) -> dict:
    return {
        "output": output,
        "regime": "-",
        "reference": "-",
        "worst": math.nan,
        "measure": "-",
        "note": f"missing: {why}",
    }


def collect(fast: bool) -> list[tuple[str, dict]]:
    """Every row, with its section name."""
    out = []
    for name, funcs in SECTIONS:
        for f in funcs:
            out.extend((name, r) for r in f(fast))
    out.extend(("xpersson-viscoelastic", r) for r in friction_rows(fast))
    out.extend(("xpersson-adhesion", r) for r in adhesion_rows(fast))
    return out


def _fmt(x: float) -> str:
    return "-" if x != x else f"{x:.3g}"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fast", action="store_true", help="the small grids of the tests")
    ap.add_argument("--markdown", action="store_true", help="print a markdown table")
    args = ap.parse_args(argv)
    t0 = time.perf_counter()
    rows = collect(args.fast)
    if args.markdown:
        print("| section | output | reference | regime | worst | measure | note |")
        print("|---|---|---|---|---|---|---|")
        for sec, r in rows:
            print(
                f"| {sec} | `{r['output']}` | {r['reference']} | {r['regime']} | "
                f"{_fmt(r['worst'])} | {r['measure']} | {r['note']} |"
            )
    else:
        for sec, r in rows:
            print(
                f"{sec:28.28s} {r['output']:44.44s} {_fmt(r['worst']):>10s} "
                f"{r['measure']:18.18s} {r['regime']}  {r['note']}"
            )
    print(f"# {len(rows)} rows in {time.perf_counter() - t0:.0f} s", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
