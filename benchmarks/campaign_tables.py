"""The validation campaign's docs tables (markdown), for ``campaign_report.py``."""

from __future__ import annotations

import json
from typing import Any

import numpy as np


def fmt_regime(rng: dict[str, Any]) -> str:
    parts = []
    for k, (lo, hi) in rng.items():
        if k == "tensile":
            parts.append("tensile" if lo > 0 else "compressive")
        else:
            parts.append(f"{k} {lo:g}-{hi:g}")
    return ", ".join(parts)


def _cell(stats: dict[str, Any], with_cov: bool) -> str:
    if not stats["n"]:
        return "-"
    text = f"{stats['median']:.3g} [{stats['p05']:.3g}, {stats['p95']:.3g}] (n={stats['n']})"
    if with_cov and "inside" in stats:
        text += f"; {stats['inside']}/{stats['n']} in band"
    return text


def _band_text(band: Any) -> str:
    if not band:
        return "not verified"
    if isinstance(band, list):
        if len(band) == 1:
            return _band_text(band[0])
        return "; ".join(
            f"d {e['ranges']['decades'][0]:.2f}-{e['ranges']['decades'][1]:.2f}: " + _band_text(e)
            for e in band
        )
    text = f"{band['low']:.3g}-{band['high']:.3g}"
    tr = band.get("trend")
    if tr:
        text += f" x exp({tr['slope']:+.2f} (d - {tr['reference']:.2f})"
        for key, (c, ref) in tr.get("other", {}).items():
            text += f" {c:+.2f} ({key} - {ref:.2f})"
        text += ")"
    return text


def _cov_cell(c: dict[str, Any] | None, key: str) -> str:
    if not c or not c[key][1]:
        return "-"
    inside, n = c[key]
    return f"{inside}/{n} = {inside / n:.0%}"


def markdown(rows: list[dict[str, Any]], cov: dict[str, Any], prov: dict[str, Any]) -> str:
    """The docs' part II tables: per output and regime, exact/theory by split; coverage."""
    out = [
        "| output | regime | band (exact/theory; d: decades) | calibration: median [5 %, 95 %] "
        "| held-out | new seed |",
        "|---|---|---|---|---|---|",
    ]
    for row in rows:
        out.append(
            f"| {row['output']} | {fmt_regime(row['regime'])} | {_band_text(row['band'])} | "
            f"{_cell(row['calibration'], False)} | {_cell(row['held_out'], True)} | "
            f"{_cell(row['new_seed'], True)} |"
        )
    out += [
        "",
        "| output | held-out: verified points inside | extrapolated inside | not verified "
        "| new seed: verified inside | extrapolated inside | not verified |",
        "|---|---|---|---|---|---|---|",
    ]
    for name, splits in cov.items():
        cells = []
        for split in ("held_out", "new_seed"):
            c = splits.get(split)
            cells += [
                _cov_cell(c, "verified"),
                _cov_cell(c, "extrapolated"),
                str(c["not_verified"]) if c else "-",
            ]
        out.append(f"| {name} | " + " | ".join(cells) + " |")
    out += ["", f"Provenance: `{json.dumps(prov, sort_keys=True)}`"]
    return "\n".join(out) + "\n"


def check_rows(chk: dict[str, Any], limits: dict[str, float], tests: dict[str, Any]) -> list[str]:
    """The extrapolation's two tests per output: the check (fit on 0.6-1.2 decades, judged
    beyond) and the table's own extrapolated band on the held-out and new-seed points."""
    lines = [
        "| output | check: points beyond 1.2 decades inside the band fitted on 0.6-1.2 "
        "| distance [decades] | the table's extrapolated band: held-out and new-seed points "
        "inside | extrapolated in the table |",
        "|---|---|---|---|---|",
    ]
    for name, c in chk.items():
        frac = f" = {c['inside'] / c['n']:.0%}" if c["n"] else ""
        t = tests.get(name)
        own = "-" if not t or not t["n"] else f"{t['inside']}/{t['n']}"
        ok = f"yes, up to {limits[name]:g} decades beyond" if name in limits else "no"
        lines.append(
            f"| {name} | {c['inside']}/{c['n']}{frac} | {c['distance']:g} | {own} | {ok} |"
        )
    return lines


def accuracy_of_options(pts: list[dict[str, Any]]) -> list[str]:
    """Median |ln r| and median r per option pair over all splits (defaults by accuracy)."""
    lines = [
        "| quantity | option | median exact/theory | median abs ln ratio | n |",
        "|---|---|---|---|---|",
    ]
    pairs = (
        ("contact stiffness / conductance", "contact_stiffness", "contact_stiffness@yang_persson"),
        ("mean gap (mean_gap)", "mean_gap", "mean_gap@yang_persson"),
        ("mean gap: mean_gap vs gap_mean", "mean_gap", "gap_mean"),
    )
    for label, a, b in pairs:
        for name in (a, b):
            r = np.array([p["ratio"] for p in pts if p["output"] == name])
            if r.size:
                lines.append(
                    f"| {label} | `{name}` | {np.median(r):.3g} | "
                    f"{np.median(np.abs(np.log(r))):.3f} | {r.size} |"
                )
    return lines


def large_rows(large: dict[str, Any]) -> list[str]:
    """The verified bands beyond 1.2 decades on the large cells' held-out and new-seed points."""
    lines = [
        "| output | large-cell held-out and new-seed points (1.5-1.8 decades) inside the "
        "verified band | band beyond 1.2 decades |",
        "|---|---|---|",
    ]
    for name, c in large.items():
        kept = "kept" if c["kept"] else "dropped: not verified beyond 1.2 decades"
        lines.append(f"| {name} | {c['inside']}/{c['n']} | {kept} |")
    return lines
