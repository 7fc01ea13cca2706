"""The verification matrix (issue 22): every output against an independent reference.

    python benchmarks/verify.py            # full regime grids (minutes)
    python benchmarks/verify.py --fast     # the subset the tests run (seconds)
    python benchmarks/verify.py --markdown # the table of docs/verification.md

Prints, per output variable of the core and of the first-party plugins, the reference it is
checked against (computed another way: adaptive quadrature with explicit breakpoints, closed
forms, an image series, the Markov walkers, published tables), the regime grid, and the worst
error measured. Rows come from ``verify_core`` (core, plasticity), ``verify_interface``
(xpersson-interface), ``verify_leakage`` (its effective medium), ``verify_friction`` (xpersson-
viscoelastic, written by its own helper: included when the file exists and offers
``rows(fast)``), ``verify_adhesion`` (the adhesion BEM comparison, same contract, when
present), ``verify_boundaries`` (every other output of the adhesion boundaries),
``verify_coefficient`` (the viscoelastic coefficient's scalars, flash temperature),
``verify_plasticity`` (plastic_scale_dependent) and
``verify_transport`` (xpersson-transport). GFMD data are read from ``../shared/refdata``
relative to the repository root (``XPERSSON_REFDATA`` overrides).

Two parts (docs/verification.md): part I, the code against an independent implementation of
its formula (every row reads the plugin's output); part II, the theory against exact
simulation (BEM, GFMD, networks: rows with ``part = "theory"``, the sources in :data:`THEORY`
and every BEM row of the adhesion work). The validation campaign (``campaign.py``,
``campaign_report.py``) is part II's main table.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import verify_boundaries  # noqa: E402
import verify_coefficient  # noqa: E402
import verify_core  # noqa: E402
import verify_interface  # noqa: E402
import verify_leakage  # noqa: E402
import verify_load_table  # noqa: E402
import verify_plasticity  # noqa: E402

SECTIONS = (
    (
        "core",
        (
            verify_core.core_rows,
            verify_core.pressure_pdf_rows,
            verify_core.markov_rows,
            verify_core.validity_rows,
        ),
    ),
    ("xpersson-plasticity (constant hardness)", (verify_core.plastic_rows,)),
    ("xpersson-plasticity (scale-dependent)", (verify_plasticity.rows,)),
    (
        "xpersson-interface",
        (
            verify_interface.energy_gap_stiffness_rows,
            verify_interface.gap_table_rows,
            verify_interface.diffusion_rows,
            verify_interface.gfmd_rows,
            verify_interface.leakage_rows,
            verify_leakage.emt_rows,
            verify_leakage.network_rows,
            verify_load_table.rows,
        ),
    ),
)


#: row sources that compare the theory with a simulation of exact contact (part II)
THEORY = (verify_interface.gfmd_rows, verify_leakage.network_rows)


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


def transport_rows(fast: bool) -> list[dict]:
    """Rows of ``verify_transport.py`` (xpersson-transport), when the plugin is installed."""
    try:
        import verify_transport

        import xpersson_transport  # noqa: F401
    except ImportError:
        return [_missing("transport (xpersson-transport)", "xpersson-transport not installed")]
    return list(verify_transport.rows(fast))


def adhesion_rows(fast: bool) -> list[dict]:
    """Rows of ``verify_adhesion.py`` (the adhesion BEM work's), when present.

    Its contract is the one of every row source here: ``rows(fast) -> list[dict]`` with keys
    output, regime, reference, worst, measure, note. The BEM results themselves
    (``results/adhesion_bem_compare.json``) are not parsed here: their layout is the adhesion
    work's to define.
    """
    try:
        import verify_adhesion
    except ImportError:
        found = (HERE / "results" / "adhesion_bem_compare.json").is_file()
        why = "BEM results present but no verify_adhesion.rows(fast)" if found else "no BEM rows"
        return [_missing("adhesion (xpersson-adhesion)", why)]
    return [{**r, "part": "theory"} for r in verify_adhesion.rows(fast)]


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
            mark = {"part": "theory"} if f in THEORY else {}
            out.extend((name, {**r, **mark}) for r in f(fast))
    out.extend(("xpersson-viscoelastic", r) for r in friction_rows(fast))
    out.extend(("xpersson-viscoelastic", r) for r in verify_coefficient.rows(fast))
    out.extend(("xpersson-adhesion", r) for r in adhesion_rows(fast))
    out.extend(("xpersson-adhesion", r) for r in verify_boundaries.rows(fast))
    out.extend(("xpersson-transport", r) for r in transport_rows(fast))
    return out


def _cell(text: object) -> str:
    """A markdown table cell: pipes in the text escaped."""
    return str(text).replace("|", "\\|")


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
        for part, title in (("code", "Part I: code"), ("theory", "Part II: theory")):
            print(f"\n{title}\n")
            print("| section | output | reference | regime | worst | measure | note |")
            print("|---|---|---|---|---|---|---|")
            for sec, r in rows:
                if r.get("part", "code") != part:
                    continue
                cells = [_cell(r[k]) for k in ("reference", "regime")]
                print(
                    f"| {sec} | `{r['output']}` | {cells[0]} | {cells[1]} | "
                    f"{_fmt(r['worst'])} | {_cell(r['measure'])} | {_cell(r['note'])} |"
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
