"""The rough-sphere campaign's bands and coverage (reads ``results/bem_sphere_campaign_*.jsonl``).

For every (scene, force) of ``benchmarks/bem_sphere_campaign.py`` the ratio ``r = exact /
theory`` of the real contact area, the nominal contact radius (99 % of the force) and the
approach: the BEM's mean over its converged realisations over :func:`xpersson.solve` of the
same sphere scene (closures ``persson01``, the default, and ``yp08``). Points are grouped by
closure, output and regime of Johnson's parameter (:data:`ALPHA_BINS`); a regime's band is the
flat campaign's (``benchmarks/campaign_report.py``): a normal tolerance interval of ``ln r`` over
the calibration points (90 % content, 95 % confidence, Howe's factor for the number of
calibration *scenes*), widened to hold every calibration point; written only where the
calibration half has at least :data:`MIN_POINTS` points from 3 scenes. The coverage is the
fraction of held-out points inside their band.

The body's separation ``u(p)`` uses mean_gap's ``s_factor = "auto"`` (the form the flat campaign
chose by accuracy: ``yang_persson`` on Persson's closure). Also measured, not used for the
bands: the nominal radius with ``s_factor = "closure"`` on Persson's closure (the form used
before), and the L1 distance of the nominal pressure.

Usage::

    python benchmarks/bem_sphere_report.py [--write-table] [--name cal cal2]
"""

from __future__ import annotations

import argparse
import json
import math
import warnings
from pathlib import Path
from typing import Any

import numpy as np
from bem_sphere_campaign import ZETA, scene
from campaign_report import tolerance_band

import xpersson
import xpersson.pipeline.body as pipeline_body
from xpersson.bem.sphere import ring_means

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "results"
TABLE = HERE.parent / "src" / "xpersson" / "data" / "body_model_error.json"
OUTPUTS = ("real_contact_area", "nominal_contact_radius", "approach")
#: Outputs with bands: the approach is a difference of two comparable lengths (the elastic
#: displacement and the separation at the centre) and crosses zero, so its ratio has no
#: band; it is compared as (BEM - theory) / Hertz approach instead (``approach_error``).
BANDED = ("real_contact_area", "nominal_contact_radius")
KEYS = {"real_contact_area": 0, "nominal_contact_radius": 1, "approach": 2}
CLOSURES = ("persson01", "yp08")
#: Regimes of Johnson's parameter (the design's 0.05 with a rounding margin).
ALPHA_BINS = ((0.05 * (1 - 1e-9), 0.3), (0.3, 1.0), (1.0, 3.05))
MIN_POINTS = 6
#: The campaign's domain (the band's ranges besides Johnson's parameter).
DOMAIN = {
    "hurst": [0.5, 0.9 + 1e-9],
    "decades": [math.log10(ZETA) - 0.05, math.log10(ZETA) + 0.05],
    "rolloff": [0.0, 0.5],
    "contact_rolloff": [6.0, 21.0],
}


def load(*names: str) -> list[dict[str, Any]]:
    """The records of the campaign files ``names`` (missing files skipped), each scene tagged
    ``name:scene`` in ``"tag"``."""
    out = []
    for name in names:
        path = RESULTS / f"bem_sphere_campaign_{name}.jsonl"
        if path.exists():
            rows = [json.loads(line) for line in path.read_text().splitlines() if line]
            out += [r | {"tag": f"{name}:{r['scene']}"} for r in rows]
    return out


def theory(sc: dict[str, Any], closure: str, form: str | None = None) -> Any:
    """The theory's Dataset of design point ``sc``; ``form``: the separation's s_factor in
    place of the default (mean_gap's ``"auto"``)."""
    if form is None:
        return xpersson.solve(scene(sc, closure))
    original = pipeline_body.separation_form
    pipeline_body.separation_form = lambda ctx: form
    try:
        return xpersson.solve(scene(sc, closure))
    finally:
        pipeline_body.separation_form = original


def _l1(rec: dict[str, Any], ds: Any, k: int) -> float:
    """``int |p_theory - p_BEM| dA / F`` on the campaign's rings (theory ring means)."""
    edges = np.asarray(rec["edges"])
    prof = np.array([row[k][3] for row in rec["bem"] if row[k][4]])
    p_th = ring_means(ds["r"].values, ds["nominal_pressure"].values[k], edges)
    area = math.pi * np.diff(edges**2)
    return float(np.nansum(np.abs(p_th - np.nanmean(prof, axis=0)) * area) / rec["forces"][k])


def points(records: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """One point per (scene, force, closure): ratios exact/theory and the scene's features."""
    out = []
    for rec in records:
        for closure in CLOSURES:
            ds = theory(rec, closure)
            old = theory(rec, closure, "closure") if closure == "persson01" else None
            for k in range(len(rec["forces"])):
                ok = [row[k] for row in rec["bem"] if row[k][4]]
                if not ok:
                    continue
                pt = {"scene": rec["tag"], "split": rec["split"], "closure": closure,
                      "force": k, "alpha": float(ds["johnson_parameter"].values[k]),
                      "H": rec["H"], "a0_qL": rec["a0_qL"], "ppw": rec["points_per_wavelength"],
                      "l1": _l1(rec, ds, k)}  # fmt: skip
                for name in OUTPUTS:
                    bem = float(np.mean([row[KEYS[name]] for row in ok]))
                    pt[name] = bem / float(ds[name].values[k])
                pt["approach_error"] = (ok_mean(ok, 2) - float(ds["approach"].values[k])) / float(
                    ds["hertz_approach"].values[k]
                )
                if old is not None:
                    pt["radius_closure_form"] = ok_mean(ok, 1) / float(
                        old["nominal_contact_radius"].values[k]
                    )
                out.append(pt)
    return out


def ok_mean(rows: list[list[Any]], key: int) -> float:
    return float(np.mean([row[key] for row in rows]))


def _regime(alpha: float) -> tuple[float, float] | None:
    return next((b for b in ALPHA_BINS if b[0] <= alpha < b[1]), None)


def bands(pts: list[dict[str, Any]], chk: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """The table's entries from the calibration points, widened by the BEM's convergence
    checks (:func:`widening`)."""
    cal = [p for p in pts if p["split"] == "calibration"]
    out = []
    for closure in CLOSURES:
        for name in BANDED:
            for b in ALPHA_BINS:
                sel = [p for p in cal if p["closure"] == closure and _regime(p["alpha"]) == b]
                scenes = len({p["scene"] for p in sel})
                if len(sel) < MIN_POINTS or scenes < 3:
                    continue
                r = np.array([p[name] for p in sel])
                lo, hi = tolerance_band(r, scenes)
                w_lo, w_hi = widening(chk, name, b)
                out.append({
                    "variable": name,
                    "match": {"geometry": "sphere", "boundary": "elastic", "closure": closure,
                              "spectrum": "self_affine"},
                    "ranges": {"johnson": list(b), **DOMAIN},
                    "low": lo * w_lo, "high": hi * w_hi, "median": float(np.median(r)),
                    "n": len(sel), "scenes": scenes, "calibration_band": [lo, hi],
                    "bem_convergence_widening": [w_lo, w_hi],
                })  # fmt: skip
    return out


def _band_of(table: list[dict[str, Any]], p: dict[str, Any], name: str) -> Any:
    for e in table:
        if e["variable"] == name and e["match"]["closure"] == p["closure"]:
            lo, hi = e["ranges"]["johnson"]
            if lo <= p["alpha"] < hi:
                return e
    return None


def coverage(pts: list[dict[str, Any]], table: list[dict[str, Any]], split: str) -> dict:
    """``(closure, output) -> (inside, verified points, all points)`` of ``split``."""
    out = {}
    for closure in CLOSURES:
        for name in BANDED:
            sel = [p for p in pts if p["split"] == split and p["closure"] == closure]
            inside = verified = 0
            for p in sel:
                e = _band_of(table, p, name)
                if e is None:
                    continue
                verified += 1
                inside += e["low"] <= p[name] <= e["high"]
            out[(closure, name)] = (inside, verified, len(sel))
    return out


def markdown(pts: list[dict[str, Any]], table: list[dict[str, Any]], records: list) -> str:
    lines = [
        "# Rough-sphere campaign (benchmarks/bem_sphere_campaign.py, bem_sphere_report.py)",
        "",
        f"{len(records)} scenes ({', '.join(sorted({r['tag'].split(':')[0] for r in records}))})"
        f" x 2 forces, {records[0]['realisations']} realisations each; "
        f"grids {min(r['n'] for r in records)}-{max(r['n'] for r in records)}^2, "
        f"{min(r['points_per_wavelength'] for r in records):.1f}-"
        f"{max(r['points_per_wavelength'] for r in records):.1f} points per shortest "
        f"wavelength; BEM time {sum(r['seconds'] for r in records):.0f} s (nice 10, shared).",
        "",
        "## Points (exact / theory)",
        "",
        "| scene | split | force | alpha | H | a0 q_L | closure | area | radius | "
        "approach (BEM - theory) / Hertz's | "
        "radius, u(p) s_factor closure | p(r) L1 |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for p in sorted(pts, key=lambda p: (p["closure"], p["alpha"])):
        yp = p.get("radius_closure_form")
        lines.append(
            f"| {p['scene']} | {p['split']} | {'F/4' if p['force'] == 0 else 'F'} | "
            f"{p['alpha']:.3g} | {p['H']:.2f} | {p['a0_qL']:.1f} | {p['closure']} | "
            f"{p['real_contact_area']:.3f} | {p['nominal_contact_radius']:.3f} | "
            f"{p['approach_error']:+.3f} | {'' if yp is None else f'{yp:.3f}'} | {p['l1']:.3f} |"
        )
    lines += ["", "## Bands (calibration) and held-out coverage", "",
              "| closure | output | alpha | calibration points (scenes) | median | "
              "calibration band | widened by the BEM's convergence | held-out inside |",
              "|---|---|---|---|---|---|---|---|"]  # fmt: skip
    held = [p for p in pts if p["split"] == "held_out"]
    for e in table:
        c = e["match"]["closure"]
        lo, hi = e["ranges"]["johnson"]
        sel = [p for p in held if p["closure"] == c and lo <= p["alpha"] < hi]
        inside = sum(e["low"] <= p[e["variable"]] <= e["high"] for p in sel)
        lines.append(
            f"| {c} | {e['variable']} | {lo:g}-{hi:g} | {e['n']} ({e['scenes']}) | "
            f"{e['median']:.3f} | {e['calibration_band'][0]:.3f}-{e['calibration_band'][1]:.3f}"
            f" | {e['low']:.3f}-{e['high']:.3f} | {inside}/{len(sel)} |"
        )
    lines += ["", "Held-out coverage per output (inside / verified / all held-out points):", ""]
    for (c, name), (i, v, a) in coverage(pts, table, "held_out").items():
        lines.append(f"- {c} {name}: {i}/{v} inside ({a} held-out points)")
    return "\n".join(lines) + "\n"


CHECKS = (
    ("conv_ppw16", "16 points per wavelength (campaign 8)"),
    ("conv_ppw12", "12 points per wavelength (campaign 8)"),
    ("conv_cell", "cell 1.5x wider (same spacing)"),
)


def checks(records: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """The BEM's convergence checks: per (check, scene, force) the finer / wider BEM's mean
    over the campaign's (other realisations: the noise is drawn on the grid), with the
    relative standard error of that ratio."""
    base = {r["tag"]: r for r in records}
    out = []
    for name, what in CHECKS:
        for rec in load(name):
            b = base[f"cal:{rec['scene']}"]
            for k in range(len(rec["forces"])):
                pt = {"what": what, "scene": rec["scene"], "force": k, "n": rec["n"],
                      "alpha": rec["alpha"] * (4 ** (2 / 3) if k == 0 else 1.0)}  # fmt: skip
                for out_name, key in KEYS.items():
                    new = [row[k][key] for row in rec["bem"] if row[k][4]]
                    old = [row[k][key] for row in b["bem"] if row[k][4]]
                    pt[out_name] = float(np.mean(new) / np.mean(old))
                    pt[out_name + "_se"] = math.hypot(
                        *(np.std(v, ddof=1) / math.sqrt(len(v)) / np.mean(v) for v in (new, old))
                    )
                out.append(pt)
    return out


def widening(chk: list[dict[str, Any]], name: str, regime: tuple[float, float]) -> tuple:
    """``(low, high)`` factors on a band: the largest changes of the BEM's ``name`` in the
    convergence checks of the regime (of every check when the regime has none), never
    narrowing."""
    sel = [c[name] for c in chk if regime[0] <= c["alpha"] < regime[1]] or [c[name] for c in chk]
    return (min([1.0, *sel]), max([1.0, *sel]))


def convergence(chk: list[dict[str, Any]]) -> list[str]:
    """Markdown of the convergence checks."""
    lines = ["", "## The BEM's convergence (same scenes, other realisations)", "",
             "| check | scene | force | alpha | n | area / campaign's | radius / campaign's | "
             "approach / campaign's |", "|---|---|---|---|---|---|---|---|"]  # fmt: skip
    for c in chk:
        cells = " | ".join(f"{c[o]:.3f} +- {c[o + '_se']:.3f}" for o in KEYS)
        lines.append(f"| {c['what']} | {c['scene']} | {'F/4' if c['force'] == 0 else 'F'} | "
                     f"{c['alpha']:.3g} | {c['n']} | {cells} |")  # fmt: skip
    return lines


def provenance(records: list[dict[str, Any]]) -> dict[str, Any]:
    r = records[0]
    return {
        "campaign": "bem_sphere_campaign (benchmarks/bem_sphere_campaign.py)",
        "date": max(x["date"] for x in records),
        "seeds": sorted({x["seed"] for x in records}),
        "scenes": len(records),
        "realisations": r["realisations"],
        "solver": f"tamaas {r['tamaas']} PolonskyKeerRey, xpersson.bem.sphere",
        "xpersson": r["xpersson"],
        "band": "90 % content, 95 % confidence normal tolerance interval of ln(exact/theory) "
        "over the calibration scenes, widened to hold every calibration point, then by the "
        "largest change of the BEM's convergence checks (finer grid, wider cell) in the regime",
        "split": "even scenes calibration, odd scenes held out",
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--name", nargs="+", default=["cal", "cal2"])
    ap.add_argument("--write-table", action="store_true")
    args = ap.parse_args()
    warnings.simplefilter("ignore", xpersson.XperssonWarning)
    records = load(*args.name)
    pts = points(records)
    chk = checks(records)
    table = bands(pts, chk)
    text = markdown(pts, table, records)
    if (RESULTS / "bem_sphere_campaign_new.jsonl").exists():
        new = points(load("new"))
        for p in new:
            p["split"] = "new_seed"
        text += "\nNew seed (seed 2, scenes drawn after the fit), inside / verified / all:\n\n"
        for (c, name), (i, v, a) in coverage(new, table, "new_seed").items():
            text += f"- {c} {name}: {i}/{v} inside ({a} points)\n"
    text += "\n".join(convergence(chk)) + "\n"
    print(text)
    (RESULTS / "bem_sphere_campaign.md").write_text(text)
    if args.write_table:
        doc = {"provenance": provenance(records), "variables": list(OUTPUTS), "bands": table}
        TABLE.write_text(json.dumps(doc, indent=1) + "\n")


if __name__ == "__main__":
    main()
