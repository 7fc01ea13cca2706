"""Validation campaign: the theory against exact (boundary-element) contact on a random design.

Scenes are drawn from a seeded random design over the documented domain that a periodic
boundary-element cell can resolve: Hurst exponent ``H`` 0.3-0.95, with or without a roll-off
(``q_r = 2-4 q_L``), ``q_1 = n/8 q_L`` on an ``n^2`` cell (8 grid points per shortest
wavelength: ``q_1 = 16 q_L`` on the default 128^2; at 4 points the BEM's area was 1.1-1.3x
its 8-point value at light load),
rms slope 0.1, loads from about 0.3 % to 60 % contact. Each scene is one of

* ``elastic``: area, mean gap and incremental stiffness ``K = -dp0/du`` (the conductance by
  Barber's analogy is ``c K``, so its ratio is the stiffness's);
* ``plastic``: constant hardness ``sigma_Y`` (``KatoSaturated``) against the ``plastic``
  boundary's total and plastic areas, hardness ratios ``sigma_Y / (E* h'_rms)`` 0.1-2;
* ``adhesive``: exponential law (range ``0.1 h_rms``) at finest-scale Tabor parameters
  0.1-10, approached then retracted under gap control: the area on the retraction branch at
  compressive loads and at half the theory's pull-off (tensile), and the pull-off stress.

The theory runs through :func:`xpersson.solve` with every option at its default except the
alternatives measured side by side (``s_factor``, the gap's ``separation``). The BEM is
:mod:`xpersson.bem` (tamaas): ``--realisations`` maps per scene from
:func:`xpersson.bem.synthesise` (the scene's own spectrum, ``seed = design seed x 1000 +
scene``); a solve that did not converge never enters a reference (its scene/load is recorded
as ``not converged`` and skipped). ``--grid-check`` solves every fourth scene also on a grid
twice as fine (same spectrum band; other realisations, as the noise is drawn on the grid).

Resumable: every finished scene is one JSON line appended to ``results/campaign_<name>.jsonl``
(provenance in each line: seed, grid, realisations, tamaas and xpersson versions, date);
scenes already there are skipped. ``--scheduler processes`` (a dask ``LocalCluster`` of
``--workers`` single-threaded processes) or a scheduler address runs one dask task per scene;
the client writes the records in design order, bitwise equal to the serial run's
(``benchmarks/campaign_compare.py``; ``results/campaign_dask_check.md``).
Alternate blocks of four scenes (one of each kind in ``KINDS``) are the calibration and the
held-out half; another ``--seed`` gives a new test set.

Decades of roughness: the same design on a larger ``--grid`` keeps each scene's ``H`` and
roll-off and moves ``q_1`` to ``grid/8 q_L``: ``log10(q_1/q_r)`` = 1.2-1.8 decades on 512^2,
1.5-2.1 on 1024^2 (0.6-1.2 on 128^2). One elastic 512^2 scene costs about 75 s of CPU (18
``PolonskyKeerRey`` solves, 1.6 s at 0.6 % contact to 10 s at 45 %), a 1024^2 one about 4-5x
that; ``--indices`` picks design scenes and ``--loads N`` the first N loads (the heaviest
costs the most) to fit a CPU budget. Record files ``campaign_cal*.jsonl`` (seed 1) and
``campaign_new*.jsonl`` (new seeds) are all read by ``campaign_report.py``.

Usage::

    OPENBLAS_NUM_THREADS=1 python benchmarks/campaign.py --name cal --seed 1 --scenes 30
    OPENBLAS_NUM_THREADS=1 python benchmarks/campaign.py --name new --seed 2 --scenes 12
    OPENBLAS_NUM_THREADS=1 python benchmarks/campaign.py --scheduler processes --workers 2
    OPENBLAS_NUM_THREADS=1 python benchmarks/campaign.py --name cal512 --seed 1 --grid 512 \
        --scenes 16 --realisations 1 --only elastic --loads 5 --indices 0,1,4,5
    python benchmarks/campaign_report.py      # the band table, coverage and docs tables
"""

from __future__ import annotations

import argparse
import datetime
import json
import math
import platform
import sys
import time
import warnings
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "results"
Q_L = 2 * math.pi / 1e-4  # cell side L = 100 um [1/m]
E_STAR = 1e6  # [Pa] (E = 0.75 MPa, nu = 0.5)
SLOPE = 0.1  # rms 2-D slope [1]
LOADS = np.geomspace(0.002, 0.25, 6)  # p0 / (E* h'_rms): about 0.3 % to 60 % contact
STEP = 1.06  # K from the secant between p0/STEP and p0*STEP
KINDS = ("elastic", "elastic", "plastic", "adhesive")


def design(seed: int, n_scenes: int, grid: int) -> list[dict[str, Any]]:
    """The campaign's scenes (dimensionless numbers; the same for the same seed)."""
    rng = np.random.default_rng(seed)
    k_1 = grid // 8  # 8 grid points per shortest wavelength
    out = []
    for i in range(n_scenes):
        kind = KINDS[i % len(KINDS)]
        rolloff = bool(rng.integers(2))
        k_r = float(rng.choice([2.0, 4.0])) if rolloff else 1.0
        sc = {
            "id": f"s{seed}-{i:03d}-n{grid}",
            "index": i,
            "half": "calibration" if (i // len(KINDS)) % 2 == 0 else "held_out",
            "kind": kind,
            "H": round(float(rng.uniform(0.3, 0.95)), 3),
            "k_r": k_r,
            "k_1": float(k_1),
        }
        if kind == "plastic":
            sc["hardness_ratio"] = round(float(np.exp(rng.uniform(np.log(0.1), np.log(2.0)))), 4)
        if kind == "adhesive":
            sc["tabor"] = round(float(np.exp(rng.uniform(np.log(0.1), np.log(10.0)))), 3)
        out.append(sc)
    return out


def base_scene(sc: dict[str, Any], loads: np.ndarray) -> dict[str, Any]:
    """The xpersson scene of a campaign scene at nominal pressures ``loads`` [Pa]."""
    return {
        "spectrum": {
            "model": "self_affine",
            "H": sc["H"],
            "q_L": f"{Q_L} 1/m",
            "q_r": f"{Q_L * sc['k_r']} 1/m",
            "q_1": f"{Q_L * sc['k_1']} 1/m",
            "rms_slope": SLOPE,
        },
        "material": {"E": f"{0.75 * E_STAR} Pa", "nu": 0.5},
        "load": {"p0": [f"{float(p)!r} Pa" for p in loads]},
        "output": {"zeta_per_decade": 16},
    }


def _solve(scene: dict[str, Any]) -> Any:
    import xpersson

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return xpersson.solve(scene)


def psd_of(sc: dict[str, Any]) -> Any:
    """The scene's resolved spectrum (``C(q)`` [m^4])."""
    from xpersson.scene import Scene

    return Scene(base_scene(sc, np.array([1.0]))).resolve().psd


def elastic_theory(sc: dict[str, Any], p0: np.ndarray) -> dict[str, Any]:
    """Theory outputs per load: area, gap (mean_gap, gap_mean), stiffness per s_factor."""
    scene = base_scene(sc, p0)
    closure = {"s_factor": "closure"}  # pinned: each form is measured under its own name
    scene["analyses"] = {
        "mean_gap": closure,
        "contact_stiffness": closure,
        "gap_pdf": {},
        "electrical_contact": {"resistivity_1": "1.7e-8 ohm*m", "resistivity_2": "1.7e-8 ohm*m"},
    }
    ds = _solve(scene)
    yp = dict(scene)
    yp["analyses"] = {
        "contact_stiffness": {"s_factor": "yang_persson"},
        "mean_gap": {"s_factor": "yang_persson"},
    }
    ds_yp = _solve(yp)
    c = float(ds["electrical_constriction_conductance"].values[0]) / float(
        ds["contact_stiffness"].values[0]
    )
    return {
        "area_fraction": ds["area_fraction"].isel(zeta=-1).values.tolist(),
        "mean_gap": ds["mean_gap"].values.tolist(),
        "gap_mean": ds["gap_mean"].values.tolist(),
        "contact_stiffness": ds["contact_stiffness"].values.tolist(),
        "electrical_constriction_conductance": ds[
            "electrical_constriction_conductance"
        ].values.tolist(),
        "barber_constant": c,
        "contact_stiffness@yang_persson": ds_yp["contact_stiffness"].values.tolist(),
        "mean_gap@yang_persson": ds_yp["mean_gap"].values.tolist(),
    }


def _maps(sc: dict[str, Any], grid: int, realisations: int, seed: int) -> np.ndarray:
    from xpersson import bem

    psd = psd_of(sc)
    L = 2 * math.pi / Q_L
    return bem.synthesise(
        lambda q: psd.C(q), L, grid, seed=seed, realisations=realisations, q_max=Q_L * sc["k_1"]
    )


def elastic_bem(maps: np.ndarray, p0: np.ndarray) -> dict[str, Any]:
    """BEM per load (mean over the maps): area, mean gap, secant stiffness; None: not converged."""
    from xpersson import bem

    L = 2 * math.pi / Q_L
    rows: dict[str, list[list[float]]] = {"area_fraction": [], "mean_gap": [], "stiffness": []}
    for h in maps:
        loads = np.sort(np.concatenate([p0 / STEP, p0, p0 * STEP]))
        states = bem.solve(h, L, E_STAR, loads, strict=False)
        by = {float(s_p): st for s_p, st in zip(loads, states, strict=True)}
        a, g, k = [], [], []
        for p in p0:
            lo, mid, hi = by[float(p / STEP)], by[float(p)], by[float(p * STEP)]
            ok = lo.converged and mid.converged and hi.converged
            a.append(mid.area_fraction if ok else math.nan)
            g.append(mid.mean_gap if ok else math.nan)
            du = hi.mean_gap - lo.mean_gap
            k.append(-(hi.p0 - lo.p0) / du if ok and du < 0 else math.nan)
        rows["area_fraction"].append(a)
        rows["mean_gap"].append(g)
        rows["stiffness"].append(k)
    return {key: _mean_se(v) for key, v in rows.items()}


def _mean_se(rows: list[list[float]]) -> dict[str, list[float]]:
    """Mean and standard error over realisations (NaN where any realisation failed)."""
    a = np.asarray(rows, float)
    mean = a.mean(axis=0)
    se = a.std(axis=0, ddof=1) / math.sqrt(a.shape[0]) if a.shape[0] > 1 else mean * np.nan
    return {"mean": mean.tolist(), "se": se.tolist()}


def plastic_theory(sc: dict[str, Any], p0: np.ndarray, sigma_y: float) -> dict[str, Any]:
    """Theory: total and plastic area at constant hardness ``sigma_y`` [Pa]."""
    scene = base_scene(sc, p0)
    scene["boundary"] = {"model": "plastic", "sigma_Y": f"{float(sigma_y)!r} Pa"}
    ds = _solve(scene)
    return {
        "total_contact_fraction": ds["total_contact_fraction"].isel(zeta=-1).values.tolist(),
        "plastic_area_fraction": ds["plastic_area_fraction"].isel(zeta=-1).values.tolist(),
    }


def plastic_bem(maps: np.ndarray, p0: np.ndarray, sigma_y: float) -> dict[str, Any]:
    from xpersson import bem

    L = 2 * math.pi / Q_L
    tot, pl = [], []
    for h in maps:
        states = bem.solve(h, L, E_STAR, p0, hardness=sigma_y, strict=False)
        tot.append([s.area_fraction if s.converged else math.nan for s in states])
        pl.append([s.plastic_area_fraction if s.converged else math.nan for s in states])
    return {"total_contact_fraction": _mean_se(tot), "plastic_area_fraction": _mean_se(pl)}


def run_scene(
    sc: dict[str, Any], grid: int, realisations: int, seed: int, loads: int = len(LOADS)
) -> dict[str, Any]:
    """Theory and BEM of one campaign scene (one JSON-able record) at the first ``loads``
    design loads."""
    from adhesion_campaign import adhesive_record  # noqa: PLC0415 - the adhesive part

    h_slope = SLOPE
    p0 = LOADS[:loads] * E_STAR * h_slope
    maps = _maps(sc, grid, realisations, seed)
    rec: dict[str, Any] = {**sc, "p0": p0.tolist(), "grid": grid, "realisations": realisations}
    t0 = time.perf_counter()
    if sc["kind"] == "elastic":
        rec["theory"] = elastic_theory(sc, p0)
        rec["bem"] = elastic_bem(maps, p0)
    elif sc["kind"] == "plastic":
        sigma_y = sc["hardness_ratio"] * E_STAR * h_slope
        keep = (p0 < 0.5 * sigma_y) & (np.arange(p0.size) % 2 == 1)  # 3 loads: KatoSaturated
        # costs ~10x the elastic solve
        p0 = p0[keep]
        rec["p0"], rec["sigma_Y"] = p0.tolist(), sigma_y
        rec["theory"] = plastic_theory(sc, p0, sigma_y)
        rec["bem"] = plastic_bem(maps, p0, sigma_y)
    else:
        rec.update(adhesive_record(sc, maps, base_scene, _solve))
    rec["seconds"] = time.perf_counter() - t0
    return rec


def refresh_theory(path: Path) -> None:
    """Recompute the theory side of every elastic and plastic record of ``path`` (cheap; the
    BEM side is kept): after a change of the theory or of how an option is pinned."""
    recs = [json.loads(line) for line in path.read_text().splitlines() if line.strip()]
    for rec in recs:
        p0 = np.asarray(rec["p0"], float)
        if rec["kind"] == "elastic":
            rec["theory"] = elastic_theory(rec, p0)
        elif rec["kind"] == "plastic":
            rec["theory"] = plastic_theory(rec, p0, rec["sigma_Y"])
    path.write_text("".join(json.dumps(r) + "\n" for r in recs))


def provenance(seed: int, grid: int, realisations: int) -> dict[str, Any]:
    import xpersson
    from xpersson import bem

    return {
        "seed": seed,
        "grid": grid,
        "realisations": realisations,
        "tamaas": bem.tamaas_version(),
        "xpersson": xpersson.__version__,
        "python": platform.python_version(),
        "date": datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%dT%H:%M:%SZ"),
    }


def scene_task(
    sc: dict[str, Any], grid: int, realisations: int, seed: int, loads: int = len(LOADS)
) -> dict[str, Any]:
    """One scene as a task (a dask worker process imports ``adhesion_campaign`` from here)."""
    if str(HERE) not in sys.path:
        sys.path.insert(0, str(HERE))
    return run_scene(sc, grid, realisations, seed, loads)


def _records(todo: list[dict[str, Any]], args: argparse.Namespace, grid: int) -> Iterator[dict]:
    """The scenes' records in design order: computed serially, or as dask tasks (one per
    scene) on ``args.scheduler`` and gathered by the client in the same order."""
    tasks = [
        (sc, grid, args.realisations, args.seed * 1000 + sc["index"], args.loads) for sc in todo
    ]
    if args.scheduler in (None, "serial"):
        yield from (scene_task(*t) for t in tasks)
        return
    from xpersson.sweep.schedule import client_for

    client, owned, _ = client_for(args.scheduler, args.workers)
    if client is None:
        raise SystemExit(f"--scheduler {args.scheduler}: use serial, processes or an address")
    try:
        futures = [client.submit(scene_task, *t, pure=False) for t in tasks]
        for fut in futures:  # in order: a finished prefix is written as soon as it is done
            yield fut.result()
    finally:
        client.close()
        if owned is not None and owned is not client:
            owned.close()


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--name", default="cal", help="results/campaign_<name>.jsonl")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--scenes", type=int, default=24)
    ap.add_argument("--grid", type=int, default=128)
    ap.add_argument("--realisations", type=int, default=2)
    ap.add_argument("--only", default=None, help="comma-separated kinds to run")
    ap.add_argument(
        "--indices", default=None, help="comma-separated design indices to run (default: all)"
    )
    ap.add_argument(
        "--loads",
        type=int,
        default=len(LOADS),
        help="the first N design loads only (large cells: the heaviest load costs the most)",
    )
    ap.add_argument("--grid-check", action="store_true", help="every 4th scene on 2x the grid")
    ap.add_argument("--refresh-theory", action="store_true", help="recompute the theory side")
    ap.add_argument(
        "--scheduler",
        default=None,
        help="serial (default), processes (dask LocalCluster of single-threaded workers) or a "
        "dask scheduler address tcp://host:port: one task per scene",
    )
    ap.add_argument("--workers", type=int, default=None, help="LocalCluster workers (processes)")
    args = ap.parse_args(argv)
    sys.path.insert(0, str(HERE))
    RESULTS.mkdir(exist_ok=True)
    out = RESULTS / f"campaign_{args.name}.jsonl"
    if args.refresh_theory:
        refresh_theory(out)
        return
    done = set()
    if out.exists():
        done = {json.loads(line)["id"] for line in out.read_text().splitlines() if line.strip()}
    scenes = design(args.seed, args.scenes, args.grid)
    if args.grid_check:
        scenes = [
            {**s, "id": s["id"].replace(f"n{args.grid}", f"n{2 * args.grid}")} for s in scenes[::4]
        ]
    kinds = None if args.only is None else set(args.only.split(","))
    prov = provenance(args.seed, 2 * args.grid if args.grid_check else args.grid, args.realisations)
    picks = None if args.indices is None else {int(i) for i in args.indices.split(",")}
    todo = [
        s
        for s in scenes
        if s["id"] not in done
        and not (kinds and s["kind"] not in kinds)
        and (picks is None or s["index"] in picks)
    ]
    t0 = time.perf_counter()
    for rec in _records(todo, args, prov["grid"]):
        rec["provenance"] = prov
        with out.open("a") as fh:
            fh.write(json.dumps(rec) + "\n")
        print(f"{rec['id']} {rec['kind']:9s} {rec['seconds']:.1f} s", flush=True)
    wall = time.perf_counter() - t0
    how = args.scheduler or "serial"
    print(f"{len(todo)} scenes, scheduler {how}: wall {wall:.1f} s", flush=True)


if __name__ == "__main__":
    main()
