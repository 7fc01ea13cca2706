"""The adhesive campaign's model-error bands, checked locally (``campaign_report.py``'s rules).

Reads ``results/campaign_adhcal.jsonl`` (calibration and held-out halves) and
``results/campaign_adhnew.jsonl`` (new seed) and applies ``campaign_report.py``'s points, band
(90 % content / 95 % confidence tolerance interval of ``ln(exact/theory)``, at least
``MIN_POINTS`` points from 4 calibration scenes) and coverage to the two adhesive outputs, for
the report's Tabor regimes and for the regimes the resolved data support (``--bins``). It also
counts what has no ratio: scenes not solved (cohesive zone below one grid spacing), tensile
loads where the BEM cell has detached (area 0), and the light loads ``p0/(E* h'_rms) < 2e-3``
separately (issue 34's 2e-4..1e-3 cases). Writes ``results/campaign_adh_bands.md``; never the
packaged table (``campaign_report.py --write-table`` does, after the merge).

Usage::

    python benchmarks/adhesion_bands.py [--bins 0.1-0.6,0.6-1.0,1.0-10]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import campaign_report as cr  # noqa: E402

ADHESIVE = ("adhesive area_fraction", "pull_off_stress")
LIGHT = 2e-3 * 1e6 * 0.1  # p0 below the campaign's lightest grid load [Pa]


def adhesive_points(name: str, split: str | None = None) -> list[dict[str, Any]]:
    """The adhesive points of ``results/campaign_<name>.jsonl`` with their load [Pa]."""
    recs = [r for r in cr.load(name) if r["kind"] == "adhesive"]
    pts = cr.points(recs, split)
    for p in pts:
        p["light"] = 0.0
    for rec in recs:  # the load of each area point (points() keeps the order of the loads)
        mine = [p for p in pts if p["id"] == rec["id"] and p["output"] == ADHESIVE[0]]
        loads = [
            x
            for x, t, b in zip(
                rec["p0"],
                rec["theory"]["area_fraction"],
                rec["bem"]["area_fraction"]["mean"],
                strict=True,
            )
            if np.isfinite(t) and np.isfinite(b) and t > 0 and b > 0
        ]
        for p, x in zip(mine, loads, strict=True):
            p["light"] = 1.0 if 0 < x < LIGHT else 0.0
    return pts


def _stats(r: np.ndarray, lo: float | None, hi: float | None) -> str:
    if r.size == 0:
        return "-"
    p5, p50, p95 = np.percentile(r, [5, 50, 95])
    s = f"{p50:.3g} [{p5:.3g}, {p95:.3g}] (n={r.size})"
    if lo is not None:
        s += f"; {int(np.sum((r >= lo) & (r <= hi)))}/{r.size} in band"
    return s


def table(pts: list[dict[str, Any]], bins: tuple[tuple[float, float], ...]) -> list[str]:
    """Markdown rows: output, regime, band, calibration / held-out / new seed (light loads too)."""
    cr.TABOR_BINS = bins
    bands = [b for b in cr.bands(pts) if b["campaign_output"] in ADHESIVE]
    lines = [
        "| output | regime | band | scenes (cal) | calibration | held-out | new seed |",
        "|---|---|---|---|---|---|---|",
    ]
    for name in ADHESIVE:
        axes = cr.OUTPUTS[name][4]
        for rng in cr.regime_ranges(axes):
            band = next(
                (
                    b
                    for b in bands
                    if b["campaign_output"] == name
                    and all(b["ranges"].get(k) == list(v) for k, v in rng.items())
                ),
                None,
            )
            lo, hi = (band["low"], band["high"]) if band else (None, None)
            mine = [p for p in pts if p["output"] == name and cr._inside(p, rng)]
            cells = []
            for split in ("calibration", "held_out", "new_seed"):
                r = np.array([p["ratio"] for p in mine if p["split"] == split])
                cells.append(_stats(r, lo, hi))
            light = [p for p in mine if p.get("light")]
            n_cal = len({p["id"] for p in mine if p["split"] == "calibration"})
            text = f"{lo:.3g}-{hi:.3g}" if band else "not verified"
            lines.append(
                f"| {name} | {cr._fmt_regime(rng)} | {text} | {n_cal} | " + " | ".join(cells) + " |"
            )
            if light:
                cells = []
                for split in ("calibration", "held_out", "new_seed"):
                    r = np.array([p["ratio"] for p in light if p["split"] == split])
                    cells.append(_stats(r, lo, hi))
                lines.append(
                    "| (light loads) | p0/(E* h'_rms) 2e-4..1e-3 | | | " + " | ".join(cells) + " |"
                )
    return lines


def unresolved(names: tuple[str, ...]) -> list[str]:
    """Scenes with no BEM reference and tensile loads where the BEM cell detached."""
    out = []
    for name in names:
        for rec in cr.load(name):
            if rec["kind"] != "adhesive":
                continue
            bem = rec["bem"]["area_fraction"]["mean"]
            det = sum(1 for x, b in zip(rec["p0"], bem, strict=True) if x < 0 and b == 0)
            if "excluded" in rec or det:
                why = rec.get("excluded", f"{det} tensile load(s): BEM cell detached (area 0)")
                out.append(
                    f"| {rec['id']} | {rec['half']} | {rec['theory']['tabor']:.3g} | "
                    f"{rec.get('zone_pixels', float('nan')):.2f} | {why} |"
                )
    return out


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bins", default="0.1-0.6,0.6-1.0,1.0-10", help="Tabor regimes lo-hi")
    args = ap.parse_args(argv)
    pts = adhesive_points("adhcal") + adhesive_points("adhnew", "new_seed")
    proposed = tuple(tuple(float(x) for x in b.split("-")) for b in args.bins.split(","))
    text = ["# Adhesive campaign: bands by Tabor regime (local check)", ""]
    for title, bins in (("report's regimes", cr.TABOR_BINS), ("regimes " + args.bins, proposed)):
        text += [f"## {title}", "", *table(pts, bins), ""]  # type: ignore[arg-type]
    text += [
        "## Not compared",
        "",
        "| scene | half | Tabor | zone [px] | why |",
        "|---|---|---|---|---|",
        *unresolved(("adhcal", "adhnew")),
        "",
    ]
    out = cr.RESULTS / "campaign_adh_bands.md"
    out.write_text("\n".join(text))
    print("\n".join(text))


if __name__ == "__main__":
    main()
