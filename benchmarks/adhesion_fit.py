"""Refit of the ``adhesive`` plugin's two calibrated constants on the campaign's calibration half.

``ATTRACTION_SCALE`` (the factor on the mean field's attraction,
``xpersson_adhesion.adhesive``) and ``BUMPS`` (the bumps of the finite-size floor,
``xpersson_adhesion._bump``) are chosen on a grid (``ATTRACTION_SCALE <= MAX_SCALE``) to minimise

    ``J = mean (ln r_enh)^2 + mean (ln r_pull)^2``

over the **calibration** scenes of ``results/campaign_adhcal.jsonl`` that have a BEM reference
(resolved cohesive zone, converged): ``r_enh`` the ratio of the area *enhancements*
``A(w)/A(0)``, BEM over theory, at every compressive load (``A(0)`` the non-adhesive area on
the same maps, ``results/campaign_adh_elastic.json``, and the theory's elastic area: the
adhesion constant is not asked to absorb the elastic theory's own area error, which the
elastic campaign measures), ``r_pull`` the pull-off ratio BEM / theory where the BEM holds
tension (as the constants were first chosen, ``docs/adhesion_bem.md``). For each candidate
the theory side is recomputed from the records' stored BEM branches
(``campaign_adhesive.refresh``: the tensile load follows the theory's pull-off, no BEM solve).
The held-out half and the new seed (``campaign_adhnew.jsonl``) are only evaluated,
before (the shipped constants) and after (the fitted ones). Points where the BEM cell has
detached at the theory's tensile load (area 0: no ratio) and pull-offs where the BEM holds no
tension are counted, not fitted. Result: ``results/adhesion_fit.json``.

Usage::

    OPENBLAS_NUM_THREADS=1 nice -n 10 python benchmarks/adhesion_fit.py fit
    OPENBLAS_NUM_THREADS=1 nice -n 10 python benchmarks/adhesion_fit.py evaluate
"""

from __future__ import annotations

import argparse
import datetime
import itertools
import json
import math
import sys
from pathlib import Path
from typing import Any

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import campaign_adhesive as ca  # noqa: E402

SCALES = (0.7, 0.85, 1.0, 1.15, 1.3, 1.4, 1.5, 1.6, 1.75, 2.0)
BUMPS = (0.7, 1.0, 1.25, 1.5, 1.75, 2.0, 2.7)
#: the largest attraction scale admitted (the value before this fit). The campaign's resolved
#: scenes (Tabor <= 1, all below the mean field's stickiness) prefer a larger scale (1.6: their
#: enhancement is 1.35x the theory's at Tabor 0.6-1 with 0.85, 1.3x with 1.0), but they do not
#: reach the stickiness threshold, where the scale matters most: on the earlier referee's
#: mu_T = 1 scene (docs/adhesion_bem.md, H = 0.8, 256^2) the lightest load's enhancement is
#: 1.54x the BEM's at 0.85, 2.4x at 1.0, and 1.6 makes it sticky with a pull-off of 2.2 kPa
#: against the BEM's 0.11 kPa (the adhesion tests pin these). The campaign cannot bound the
#: scale from above, so it is not raised.
MAX_SCALE = 0.85
#: the constants as shipped before this fit (fitted on the earlier referee, docs/adhesion_bem.md)
BEFORE = (0.85, 2.7)
OUT = HERE / "results" / "adhesion_fit.json"


def set_constants(scale: float, bumps: float) -> None:
    """Set the plugin's two constants (module globals read at call time) and drop the caches."""
    import xpersson_adhesion._bump as bump_mod
    import xpersson_adhesion.adhesive as adh_mod
    from xpersson.cache import clear_caches

    adh_mod.ATTRACTION_SCALE = float(scale)
    bump_mod.BUMPS = float(bumps)
    clear_caches()


def usable(recs: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Records with a BEM reference (not excluded, at least one converged branch)."""
    return [
        r
        for r in recs
        if "excluded" not in r and any(b.get("converged") for b in r["bem"]["branches"])
    ]


def elastic_ratio(rec: dict[str, Any], refs: dict[str, Any]) -> dict[float, float]:
    """``{load: A_bem(0) / A_theory(0)}`` at the record's compressive loads [Pa] (the elastic
    area ratio on the scene's own maps; constant-independent)."""
    ref = refs.get(rec["id"])
    if ref is None:
        return {}
    p0 = np.asarray(ref["p0"], float)
    ds = ca._solve(ca.campaign.base_scene(rec, p0))
    th = ds["area_fraction"].isel(zeta=-1).values
    bem = ref["area_fraction"]["mean"]
    return {float(p): b / t for p, b, t in zip(p0, bem, th, strict=True) if t > 0 and b > 0}


def ratios(rec: dict[str, Any], elastic: dict[float, float]) -> dict[str, list]:
    """``{"area": [(load, r, tensile)], "enh": [...], "pull": [...], "detached": [...],
    "no_tension": [...]}`` of one refreshed record (``r`` = BEM / theory; ``enh`` the ratio of
    enhancements, ``r / elastic[load]``)."""
    th, bem = rec["theory"], rec["bem"]
    out: dict[str, list] = {"area": [], "enh": [], "pull": [], "detached": [], "no_tension": []}
    for p, t, b in zip(rec["p0"], th["area_fraction"], bem["area_fraction"]["mean"], strict=True):
        if not (math.isfinite(t) and math.isfinite(b)) or t <= 0:
            continue
        key = "area" if b > 0 else "detached"
        out[key].append((p, b / t if b > 0 else 0.0, p < 0))
        if b > 0 and float(p) in elastic:
            out["enh"].append((p, b / t / elastic[float(p)], False))
    t, b = th["pull_off_stress"], bem["pull_off_stress"]["mean"]
    if math.isfinite(b) and t > 0:
        # a BEM pull-off below 1 % of the theory's: the cell holds no tension (no ratio fitted)
        out["pull" if b > 0.01 * t else "no_tension"].append((0.0, b / t, True))
    return out


def evaluate(
    recs: list[dict[str, Any]], scale: float, bumps: float, elastic: dict[str, dict]
) -> list[dict[str, Any]]:
    """Per record: its id, Tabor parameter and ratios under the candidate constants."""
    set_constants(scale, bumps)
    out = []
    for rec in recs:
        new = ca.refresh(rec)
        out.append({"id": rec["id"], "tabor": rec["tabor"], **ratios(new, elastic[rec["id"]])})
    return out


def objective(rows: list[dict[str, Any]]) -> dict[str, float]:
    """``{"J": J_enh + J_pull, "J_enh": mean (ln r_enh)^2, "J_pull": mean (ln r_pull)^2}``
    (0 terms where no points)."""
    out = {}
    for key in ("enh", "pull"):
        ln = [math.log(r) for row in rows for _, r, _ in row[key]]
        out[f"J_{key}"] = float(np.mean(np.square(ln))) if ln else 0.0
    return {"J": out["J_enh"] + out["J_pull"], **out}


def stats(rows: list[dict[str, Any]]) -> dict[str, Any]:
    """Per Tabor regime and output: n, median, 5-95 % of r; detached / no-tension counts."""
    out: dict[str, Any] = {}
    for lo, hi in ca.TABOR_BINS:
        mine = [r for r in rows if lo <= r["tabor"] < hi]
        reg: dict[str, Any] = {}
        for name, key, sel in (
            ("area compressive", "area", False),
            ("area tensile", "area", True),
            ("enhancement compressive", "enh", False),
            ("pull_off", "pull", True),
        ):
            r = np.array([x for row in mine for _, x, t in row[key] if t == sel])
            reg[name] = {"n": int(r.size), "scenes": len({row["id"] for row in mine})}
            if r.size:
                p5, p50, p95 = np.percentile(r, [5, 50, 95])
                reg[name].update(median=float(p50), p05=float(p5), p95=float(p95))
        reg["tensile detached in BEM"] = sum(len(row["detached"]) for row in mine)
        reg["pull-off: BEM holds no tension"] = sum(len(row["no_tension"]) for row in mine)
        out[f"{lo}-{hi}"] = reg
    return out


def _records(args: argparse.Namespace) -> tuple[list, list, list, dict[str, dict]]:
    recs = usable(ca._read(ca.campaign.RESULTS / f"campaign_{args.cal}.jsonl"))
    new = usable(ca._read(ca.campaign.RESULTS / f"campaign_{args.new}.jsonl"))
    path = ca.campaign.RESULTS / "campaign_adh_elastic.json"
    refs = json.loads(path.read_text()) if path.exists() else {}
    elastic = {r["id"]: elastic_ratio(r, refs) for r in recs + new}
    cal = [r for r in recs if r["half"] == "calibration"]
    held = [r for r in recs if r["half"] == "held_out"]
    return cal, held, new, elastic


def fit(args: argparse.Namespace) -> None:
    """The grid search on the calibration half only; writes ``results/adhesion_fit.json``."""
    cal, _, _, elastic = _records(args)
    grid = {}
    for s, b in itertools.product(SCALES, BUMPS):
        grid[(s, b)] = objective(evaluate(cal, s, b, elastic))
        print(f"scale {s:.2f} bumps {b:.2f}: {grid[(s, b)]}", flush=True)
    free = min(grid, key=lambda k: grid[k]["J"])
    best = min((k for k in grid if k[0] <= MAX_SCALE), key=lambda k: grid[k]["J"])
    result: dict[str, Any] = {
        "date": datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%dT%H:%M:%SZ"),
        "script": "benchmarks/adhesion_fit.py fit",
        "calibration": [r["id"] for r in cal],
        "objective": "mean (ln r_enh)^2 + mean (ln r_pull)^2 over the calibration half",
        "grid": [{"scale": s, "bumps": b, **j} for (s, b), j in grid.items()],
        "before": {"ATTRACTION_SCALE": BEFORE[0], "BUMPS": BEFORE[1], **grid[BEFORE]},
        "fitted": {"ATTRACTION_SCALE": best[0], "BUMPS": best[1], **grid[best]},
        "constraint": f"ATTRACTION_SCALE <= {MAX_SCALE} (see MAX_SCALE in the script)",
        "unconstrained": {"ATTRACTION_SCALE": free[0], "BUMPS": free[1], **grid[free]},
        "provenance": [r["provenance"] for r in cal[:1]] + [cal[-1]["provenance"]],
    }
    OUT.write_text(json.dumps(result, indent=1) + "\n")
    print(json.dumps({k: result[k] for k in ("before", "fitted", "unconstrained")}, indent=1))


def evaluate_splits(args: argparse.Namespace) -> None:
    """Per split and Tabor regime, before and after: adds ``stats`` to the fit's file."""
    import xpersson_adhesion._bump as bump_mod
    import xpersson_adhesion.adhesive as adh_mod

    now = (adh_mod.ATTRACTION_SCALE, bump_mod.BUMPS)
    result = json.loads(OUT.read_text())
    cal, held, new, elastic = _records(args)
    fitted = (result["fitted"]["ATTRACTION_SCALE"], result["fitted"]["BUMPS"])
    for label, consts in (("before", BEFORE), ("fitted", fitted)):
        result[label]["stats"] = {
            split: stats(evaluate(rs, *consts, elastic))
            for split, rs in (("calibration", cal), ("held_out", held), ("new_seed", new))
        }
    set_constants(*now)
    result["evaluated"] = {
        "date": datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%dT%H:%M:%SZ"),
        "held_out": [r["id"] for r in held],
        "new_seed": [r["id"] for r in new],
        "new_seed_provenance": new[0]["provenance"] if new else None,
    }
    OUT.write_text(json.dumps(result, indent=1) + "\n")
    print(json.dumps({k: result[k]["stats"] for k in ("before", "fitted")}, indent=1))


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("step", choices=("fit", "evaluate"))
    ap.add_argument("--cal", default="adhcal")
    ap.add_argument("--new", default="adhnew")
    args = ap.parse_args(argv)
    if args.step == "fit":
        fit(args)
    else:
        evaluate_splits(args)


if __name__ == "__main__":
    main()
