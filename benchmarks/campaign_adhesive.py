"""The validation campaign's adhesive scenes: a Tabor-stratified design, in the campaign's format.

``benchmarks/campaign.py`` draws one adhesive scene in four with a log-uniform Tabor parameter
0.1-10; its 8 adhesive scenes left every Tabor regime with fewer than 4 calibration scenes.
This design draws adhesive scenes only, cycling through the report's Tabor regimes
(``campaign_report.TABOR_BINS``: 0.1-0.6, 0.6-1.6, 1.6-10; log-uniform inside each), H 0.3-0.95,
with or without roll-off, in alternate blocks of one scene per regime for the calibration and
the held-out half. Scenes, spectra, loads, maps (``seed x 1000 + index``) and records are those
of ``campaign.py`` (:func:`campaign.run_scene`, :mod:`adhesion_campaign`): ids ``a<seed>-...``.

``--refresh-theory`` recomputes the theory side of every record of a file from its stored BEM
branches (after a change of the adhesive plugin's constants): the loads follow the theory's
pull-off, the BEM's area is re-interpolated on the same branches (no BEM solve).

Usage::

    OPENBLAS_NUM_THREADS=1 nice -n 10 python benchmarks/campaign_adhesive.py --name adhcal \\
        --seed 11 --scenes 18
    OPENBLAS_NUM_THREADS=1 nice -n 10 python benchmarks/campaign_adhesive.py --name adhnew \\
        --seed 12 --scenes 9
    python benchmarks/campaign_adhesive.py --name adhcal --refresh-theory
    OPENBLAS_NUM_THREADS=1 nice -n 10 python benchmarks/campaign_adhesive.py --elastic \
        --name adhcal,adhnew
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import adhesion_campaign as adh  # noqa: E402
import campaign  # noqa: E402

TABOR_BINS = ((0.1, 0.6), (0.6, 1.6), (1.6, 10.0))


def design(
    seed: int, n_scenes: int, grid: int, strata: tuple[tuple[float, float], ...] = TABOR_BINS
) -> list[dict[str, Any]]:
    """The adhesive scenes (dimensionless numbers; the same for the same seed and strata)."""
    rng = np.random.default_rng(seed)
    k = len(strata)
    out = []
    for i in range(n_scenes):
        lo, hi = strata[i % k]
        rolloff = bool(rng.integers(2))
        out.append(
            {
                "id": f"a{seed}-{i:03d}-n{grid}",
                "index": i,
                "half": "calibration" if (i // k) % 2 == 0 else "held_out",
                "kind": "adhesive",
                "H": round(float(rng.uniform(0.3, 0.95)), 3),
                "k_r": float(rng.choice([2.0, 4.0])) if rolloff else 1.0,
                "k_1": float(grid // 8),
                "tabor": round(float(np.exp(rng.uniform(np.log(lo), np.log(hi)))), 3),
            }
        )
    return out


def refresh(rec: dict[str, Any]) -> dict[str, Any]:
    """The record with its theory side recomputed (current plugin) and the BEM's area
    re-interpolated at the theory's loads on the stored branches."""
    loads, theory = adh.theory_side(rec, rec["work"], rec["range"], campaign.base_scene, _solve)
    return {
        **rec,
        "p0": loads.tolist(),
        "theory": theory,
        "bem": adh.bem_side(rec["bem"]["branches"], loads),
    }


def elastic_pass(names: list[str]) -> None:
    """The non-adhesive BEM area on each resolved scene's own maps at its compressive loads,
    into ``results/campaign_adh_elastic.json`` (by id; the denominator of the area enhancement
    ``A(w)/A(0)`` that ``adhesion_fit.py`` fits ``ATTRACTION_SCALE`` on)."""
    path = campaign.RESULTS / "campaign_adh_elastic.json"
    refs = json.loads(path.read_text()) if path.exists() else {}
    comp = adh.COMPRESSIVE * adh.E_STAR * adh.SLOPE
    for name in names:
        for rec in _read(campaign.RESULTS / f"campaign_{name}.jsonl"):
            if rec["id"] in refs or "excluded" in rec:
                continue
            seed = rec["provenance"]["seed"] * 1000 + rec["index"]
            maps = campaign._maps(rec, rec["grid"], rec["realisations"], seed)
            refs[rec["id"]] = {"p0": comp.tolist(), "area_fraction": adh.elastic_areas(maps, comp)}
            path.write_text(json.dumps(refs, indent=1) + "\n")
            print(f"{rec['id']} elastic reference", flush=True)


def _solve(scene: dict[str, Any]) -> Any:
    return campaign._solve(scene)


def _read(path: Path) -> list[dict[str, Any]]:
    if not path.exists():
        return []
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()]


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--name", default="adhcal", help="results/campaign_<name>.jsonl")
    ap.add_argument("--seed", type=int, default=11)
    ap.add_argument("--scenes", type=int, default=18)
    ap.add_argument("--grid", type=int, default=128)
    ap.add_argument("--realisations", type=int, default=2)
    ap.add_argument(
        "--strata",
        default="0.1-0.6,0.6-1.6,1.6-10",
        help="Tabor strata lo-hi, comma-separated (one scene of each per block)",
    )
    ap.add_argument("--refresh-theory", action="store_true", help="recompute the theory side")
    ap.add_argument("--elastic", action="store_true", help="non-adhesive BEM areas (--name, csv)")
    args = ap.parse_args(argv)
    if args.elastic:
        elastic_pass(args.name.split(","))
        return
    out = campaign.RESULTS / f"campaign_{args.name}.jsonl"
    if args.refresh_theory:
        recs = [refresh(r) for r in _read(out)]
        out.write_text("".join(json.dumps(r) + "\n" for r in recs))
        return
    done = {r["id"] for r in _read(out)}
    strata = tuple(tuple(float(x) for x in s.split("-")) for s in args.strata.split(","))
    scenes = design(args.seed, args.scenes, args.grid, strata)  # type: ignore[arg-type]
    todo = [s for s in scenes if s["id"] not in done]
    prov = campaign.provenance(args.seed, args.grid, args.realisations)
    prov["design"] = f"benchmarks/campaign_adhesive.py, Tabor strata {args.strata}"
    t0 = time.perf_counter()
    for sc in todo:
        rec = campaign.run_scene(sc, args.grid, args.realisations, args.seed * 1000 + sc["index"])
        rec["provenance"] = prov
        with out.open("a") as fh:
            fh.write(json.dumps(rec) + "\n")
        bem = rec["bem"]["area_fraction"]["mean"]
        ok = sum(math.isfinite(x) for x in bem)
        print(
            f"{rec['id']} tabor {sc['tabor']:.3g} zone {rec['zone_pixels']:.2f} px "
            f"{ok}/{len(bem)} loads {rec['seconds']:.1f} s",
            flush=True,
        )
    print(f"{len(todo)} scenes: wall {time.perf_counter() - t0:.1f} s", flush=True)


if __name__ == "__main__":
    main()
