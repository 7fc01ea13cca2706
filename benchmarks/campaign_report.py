"""The validation campaign's bands, coverage and tables (reads ``results/campaign_*.jsonl``).

For every (scene, load, output) point of the campaign the ratio ``r = exact / theory`` (BEM over
xpersson, both at the same nominal pressure). Points are grouped by output and regime
(:func:`regime_ranges`); a regime's band is a normal tolerance interval of ``ln r`` over its
calibration points, 90 % content at 95 % confidence, ``exp(mean +- k sd)`` with Howe's factor
``k`` for ``n`` = the number of calibration *scenes* in the regime (the loads of one scene are
not independent draws), widened to hold every calibration point; written only where the
calibration half has at least :data:`MIN_POINTS` points from 4 scenes. (``[min r, max r]``
alone covered 81-92 % of the held-out points: its nominal ``(n - 1)/(n + 1)`` assumes
independent points.) The band table goes to
``src/xpersson/data/model_error.json`` (with the provenance of the campaign), the tables to
``results/campaign.md``: per output and regime the calibration median and band, and the
coverage (fraction inside the band) on the held-out half and on the new seed's scenes.

Usage::

    python benchmarks/campaign_report.py [--write-table]
"""

from __future__ import annotations

import argparse
import json
import math
from collections import defaultdict
from pathlib import Path
from typing import Any

import numpy as np

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "results"
TABLE = HERE.parent / "src" / "xpersson" / "data" / "model_error.json"
MIN_POINTS = 8
AREA_BINS = ((1e-3, 0.02), (0.02, 0.1), (0.1, 0.6))
TABOR_BINS = ((0.1, 0.6), (0.6, 1.6), (1.6, 10.0))
ELASTIC = {"boundary": "elastic", "closure": "persson01"}

#: output -> (Dataset variable, extra match, BEM key, theory key, regime axes)
OUTPUTS: dict[str, tuple[str, dict[str, Any], str, str, str]] = {
    "area_fraction": ("area_fraction", ELASTIC, "area_fraction", "area_fraction", "area"),
    "mean_gap": ("mean_gap", {**ELASTIC, "s_factor": "closure"}, "mean_gap", "mean_gap", "area"),
    "mean_gap@yang_persson": (
        "mean_gap",
        {**ELASTIC, "s_factor": "yang_persson"},
        "mean_gap",
        "mean_gap@yang_persson",
        "area",
    ),
    "gap_mean": (
        "gap_mean",
        {**ELASTIC, "s_factor": "closure", "separation": "pressure"},
        "mean_gap",
        "gap_mean",
        "area",
    ),
    "contact_stiffness": (
        "contact_stiffness",
        {**ELASTIC, "s_factor": "closure"},
        "stiffness",
        "contact_stiffness",
        "area",
    ),
    "contact_stiffness@yang_persson": (
        "contact_stiffness",
        {**ELASTIC, "s_factor": "yang_persson"},
        "stiffness",
        "contact_stiffness@yang_persson",
        "area",
    ),
    "total_contact_fraction": (
        "total_contact_fraction",
        {"boundary": "plastic", "closure": "persson01"},
        "total_contact_fraction",
        "total_contact_fraction",
        "area",
    ),
    "plastic_area_fraction": (
        "plastic_area_fraction",
        {"boundary": "plastic", "closure": "persson01"},
        "plastic_area_fraction",
        "plastic_area_fraction",
        "area",
    ),
    "adhesive area_fraction": (
        "area_fraction",
        {"boundary": "adhesive", "closure": "persson01", "boundary.law": "exponential"},
        "area_fraction",
        "area_fraction",
        "tabor_sign",
    ),
    "pull_off_stress": (
        "pull_off_stress",
        {
            "boundary": "adhesive",
            "closure": "persson01",
            "boundary.law": "exponential",
            "boundary.nominal_size": "0.0 m",
        },
        "pull_off_stress",
        "pull_off_stress",
        "tabor",
    ),
}
#: Barber's analogy: the constriction conductances are c K, so their ratio is the stiffness's
CONDUCTANCES = ("electrical_constriction_conductance", "thermal_constriction_conductance")


def load(name: str) -> list[dict[str, Any]]:
    path = RESULTS / f"campaign_{name}.jsonl"
    if not path.exists():
        return []
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()]


KIND_OUTPUTS = {
    "elastic": (
        "area_fraction",
        "mean_gap",
        "mean_gap@yang_persson",
        "gap_mean",
        "contact_stiffness",
        "contact_stiffness@yang_persson",
    ),
    # every plastic record was (re)run after the fix of the BEM's hardness units: the plastic
    # area is compared too (a BEM plastic area of 0, below one pixel, has no ratio: left out)
    "plastic": ("total_contact_fraction", "plastic_area_fraction"),
    "adhesive": ("adhesive area_fraction", "pull_off_stress"),
}


def points(records: list[dict[str, Any]], split: str | None = None) -> list[dict[str, Any]]:
    """Every (scene, load, output) point: ratio exact/theory, features, split.

    Points where the BEM did not converge (NaN) or a value is not positive are left out.
    """
    out = []
    for rec in records:
        th, bem = rec["theory"], rec["bem"]
        base = {
            "id": rec["id"],
            "split": split or rec["half"],
            "hurst": rec["H"],
            "rolloff": 1.0 if rec["k_r"] > 1 else 0.0,
            "decades": math.log10(rec["k_1"] / rec["k_r"]),
            "tabor": th.get("tabor", math.nan),
        }
        area = th.get("total_contact_fraction", th.get("area_fraction"))
        for name in KIND_OUTPUTS[rec["kind"]]:
            _, _, bkey, tkey, _ = OUTPUTS[name]
            t, b = th[tkey], bem[bkey]["mean"]
            loads = rec["p0"]
            if np.ndim(t) == 0:
                t, b, loads = [t], [b], [1.0]
            for i, (tv, bv) in enumerate(zip(t, b, strict=True)):
                if not (np.isfinite(tv) and np.isfinite(bv)) or tv <= 0 or bv <= 0:
                    continue
                out.append(
                    {
                        **base,
                        "output": name,
                        "ratio": bv / tv,
                        "area_fraction": area[i] if len(t) > 1 else math.nan,
                        "tensile": 1.0 if loads[i] < 0 else 0.0,
                    }
                )
    return out


def regime_ranges(axes: str) -> list[dict[str, tuple[float, float]]]:
    """The regimes of an output: ranges of its per-point features."""
    if axes == "area":
        return [{"area_fraction": b} for b in AREA_BINS]
    if axes == "tabor":
        return [{"tabor": b} for b in TABOR_BINS]
    return [{"tabor": b, "tensile": s} for b in TABOR_BINS for s in ((0.0, 0.5), (0.5, 1.5))]


def _inside(p: dict[str, Any], ranges: dict[str, tuple[float, float]]) -> bool:
    return all(lo <= p[k] < hi for k, (lo, hi) in ranges.items())


def domain(pts: list[dict[str, Any]]) -> dict[str, tuple[float, float]]:
    """The scene-level ranges the campaign covered (outside them: not verified)."""
    return {
        "hurst": (0.3, 0.95 + 1e-9),
        "decades": (
            round(min(p["decades"] for p in pts) - 1e-6, 6),
            round(max(p["decades"] for p in pts) + 1e-6, 6),
        ),
    }


def tolerance_band(r: np.ndarray, n: int, content: float = 0.9, conf: float = 0.95) -> tuple:
    """``exp(mean ln r +- k sd)`` (Howe's two-sided normal tolerance factor for ``n``), widened
    to ``[min r, max r]``."""
    from scipy.stats import chi2, norm

    ln = np.log(r)
    z = norm.ppf(0.5 + content / 2)
    k = math.sqrt((n - 1) * (1 + 1 / n) * z**2 / chi2.ppf(1 - conf, n - 1))
    sd = float(np.std(ln, ddof=1))
    lo, hi = math.exp(ln.mean() - k * sd), math.exp(ln.mean() + k * sd)
    return min(lo, float(r.min())), max(hi, float(r.max()))


def bands(pts: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """The band table's entries from the calibration points."""
    cal = [p for p in pts if p["split"] == "calibration"]
    dom = domain(cal)
    out = []
    for name, (var, match, _, _, axes) in OUTPUTS.items():
        for rng in regime_ranges(axes):
            mine = [p for p in cal if p["output"] == name and _inside(p, rng)]
            r = np.array([p["ratio"] for p in mine])
            n_scenes = len({p["id"] for p in mine})
            if r.size < MIN_POINTS or n_scenes < 4:
                continue
            low, high = tolerance_band(r, n_scenes)
            entry = {
                "variable": var,
                "match": dict(match),
                "ranges": {
                    **{k: list(v) for k, v in dom.items()},
                    **{k: list(v) for k, v in rng.items()},
                },
                "low": low,
                "high": high,
                "median": float(np.median(r)),
                "n": int(r.size),
                "scenes": n_scenes,
                "campaign_output": name,
            }
            out.append(entry)
            if name.startswith("contact_stiffness"):
                s_factor = match["s_factor"]
                for cond in CONDUCTANCES:
                    m = {k: v for k, v in match.items() if k != "s_factor"}
                    m["contact_stiffness.s_factor"] = s_factor
                    out.append({**entry, "variable": cond, "match": m})
    return out


def coverage(pts: list[dict[str, Any]], table: list[dict[str, Any]]) -> dict[str, Any]:
    """Per output and split: points inside their band / points with a band; not verified."""
    res: dict[str, dict[str, list[int]]] = defaultdict(lambda: defaultdict(lambda: [0, 0, 0]))
    for p in pts:
        entry = next(
            (
                e
                for e in table
                if e["campaign_output"] == p["output"]
                and e["variable"] not in CONDUCTANCES
                and _inside(p, {k: tuple(v) for k, v in e["ranges"].items() if k in p})
            ),
            None,
        )
        c = res[p["output"]][p["split"]]
        if entry is None:
            c[2] += 1
            continue
        c[1] += 1
        c[0] += int(entry["low"] <= p["ratio"] <= entry["high"])
    return {k: dict(v) for k, v in res.items()}


def summary(pts: list[dict[str, Any]], table: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Per output and regime: median and 90 % range of r per split, band, coverage."""
    rows = []
    for name, (_, _, _, _, axes) in OUTPUTS.items():
        for rng in regime_ranges(axes):
            entry = next(
                (
                    e
                    for e in table
                    if e["campaign_output"] == name
                    and e["variable"] not in CONDUCTANCES
                    and all(e["ranges"].get(k) == list(v) for k, v in rng.items())
                ),
                None,
            )
            row: dict[str, Any] = {"output": name, "regime": rng, "band": entry}
            for split in ("calibration", "held_out", "new_seed"):
                mine = [p for p in pts if p["output"] == name and p["split"] == split]
                mine = [p for p in mine if _inside(p, rng)]
                r = np.array([p["ratio"] for p in mine])
                stats: dict[str, Any] = {"n": int(r.size)}
                if r.size:
                    stats["median"] = float(np.median(r))
                    stats["p05"], stats["p95"] = (float(x) for x in np.percentile(r, [5, 95]))
                    if entry is not None:
                        stats["inside"] = int(np.sum((r >= entry["low"]) & (r <= entry["high"])))
                row[split] = stats
            if any(row[s]["n"] for s in ("calibration", "held_out", "new_seed")):
                rows.append(row)
    return rows


def _fmt_regime(rng: dict[str, Any]) -> str:
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


def markdown(rows: list[dict[str, Any]], cov: dict[str, Any], prov: dict[str, Any]) -> str:
    """The docs' part II tables: per output and regime, exact/theory by split; coverage."""
    out = [
        "| output | regime | band (exact/theory) | calibration: median [5 %, 95 %] | held-out "
        "| new seed |",
        "|---|---|---|---|---|---|",
    ]
    for row in rows:
        band = row["band"]
        btxt = "not verified" if band is None else f"{band['low']:.3g}-{band['high']:.3g}"
        out.append(
            f"| {row['output']} | {_fmt_regime(row['regime'])} | {btxt} | "
            f"{_cell(row['calibration'], False)} | {_cell(row['held_out'], True)} | "
            f"{_cell(row['new_seed'], True)} |"
        )
    out += [
        "",
        "| output | held-out: inside / with band (not verified) | new seed |",
        "|---|---|---|",
    ]
    for name, splits in cov.items():
        cells = []
        for split in ("held_out", "new_seed"):
            c = splits.get(split)
            if not c:
                cells.append("-")
                continue
            frac = f"{c[0] / c[1]:.0%}" if c[1] else "-"
            cells.append(f"{c[0]}/{c[1]} = {frac} ({c[2]} not verified)")
        out.append(f"| {name} | {cells[0]} | {cells[1]} |")
    out += ["", f"Provenance: `{json.dumps(prov, sort_keys=True)}`"]
    return "\n".join(out) + "\n"


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


def grid_check() -> list[str]:
    """BEM at twice the grid / BEM at the campaign's grid, same scenes and maps' modes."""
    fine = {r["id"].rsplit("-n", 1)[0]: r for r in load("grid")}
    coarse = {r["id"].rsplit("-n", 1)[0]: r for r in load("cal")}
    ratios: dict[str, list[float]] = defaultdict(list)
    for key, rf in fine.items():
        rc = coarse.get(key)
        if rc is None:
            continue
        for bkey, v in rf["bem"].items():
            a = np.atleast_1d(np.asarray(v["mean"], float))
            b = np.atleast_1d(np.asarray(rc["bem"][bkey]["mean"], float))
            ok = np.isfinite(a) & np.isfinite(b) & (b > 0)
            ratios[f"{rf['kind']} {bkey}"] += (a[ok] / b[ok]).tolist()
    lines = ["| BEM output | fine/coarse grid: median [min, max] | n |", "|---|---|---|"]
    for k, r in sorted(ratios.items()):
        if r:
            lines.append(f"| {k} | {np.median(r):.3g} [{min(r):.3g}, {max(r):.3g}] | {len(r)} |")
    return lines


def pts_cal(pts: list[dict[str, Any]]) -> list[dict[str, Any]]:
    return [p for p in pts if p["split"] == "calibration"]


def provenance(records: list[dict[str, Any]], new: list[dict[str, Any]]) -> dict[str, Any]:
    p = dict(records[0]["provenance"]) if records else {}
    return {
        "campaign": "benchmarks/campaign.py",
        "seed": p.get("seed"),
        "new_seed": new[0]["provenance"]["seed"] if new else None,
        "scenes": len(records),
        "new_seed_scenes": len(new),
        "grid": p.get("grid"),
        "realisations": p.get("realisations"),
        "tamaas": p.get("tamaas"),
        "xpersson": p.get("xpersson"),
        "date": p.get("date"),
        "band": "90 % content / 95 % confidence normal tolerance interval of ln(exact/theory) "
        "over the calibration half's points in the regime (n = scenes), widened to hold them all",
    }


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write-table", action="store_true", help="write the packaged table")
    args = ap.parse_args(argv)
    cal, new = load("cal"), load("new")
    pts = points(cal) + points(new, "new_seed")
    table = bands(pts)
    cov = coverage(pts, table)
    prov = provenance(cal, new)
    rows = summary(pts, table)
    text = markdown(rows, cov, prov)
    text += "\n" + "\n".join(accuracy_of_options(pts)) + "\n\n" + "\n".join(grid_check()) + "\n"
    check = RESULTS / "campaign_dask_check.md"  # serial == LocalCluster (campaign_compare.py)
    if check.exists():
        text += "\n" + check.read_text()
    (RESULTS / "campaign.md").write_text(text)
    print(text)
    if args.write_table:
        variables = sorted({v[0] for v in OUTPUTS.values()} | set(CONDUCTANCES))
        prov["coverage"] = {
            name: {split: c for split, c in splits.items() if split != "calibration"}
            for name, splits in cov.items()
        }
        prov["domain"] = {k: list(v) for k, v in domain(pts_cal(pts)).items()}
        data = {"provenance": prov, "variables": variables, "bands": table}
        TABLE.write_text(json.dumps(data, indent=1) + "\n")


if __name__ == "__main__":
    main()
